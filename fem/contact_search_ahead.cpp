#include "fem/contact_search_ahead.h"

#include <deal.II/base/timer.h>

namespace hipfai::fem {

namespace {

// The parts of a model the contact search reads: which bone each body is bonded to, the bones'
// placements and surfaces, and the contact pairs.
bool same_search_geometry(const ContactModel& a, const ContactModel& b) {
  if (a.bodies.size() != b.bodies.size() || a.rigid_bodies.size() != b.rigid_bodies.size() ||
      a.contact_pairs.size() != b.contact_pairs.size())
    return false;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    if (a.bodies[i].material_id != b.bodies[i].material_id ||
        a.bodies[i].bonded_rigid_body != b.bodies[i].bonded_rigid_body)
      return false;
  }
  for (std::size_t i = 0; i < a.rigid_bodies.size(); ++i) {
    const RigidBody& x = a.rigid_bodies[i];
    const RigidBody& y = b.rigid_bodies[i];
    if (!(x.rotation == y.rotation) || !(x.rotation_center_mm == y.rotation_center_mm) ||
        x.surface != y.surface)
      return false;
  }
  for (std::size_t i = 0; i < a.contact_pairs.size(); ++i) {
    const ContactPair& x = a.contact_pairs[i];
    const ContactPair& y = b.contact_pairs[i];
    if (x.slave_boundary_id != y.slave_boundary_id || x.master_rigid_body != y.master_rigid_body ||
        x.master_boundary_id != y.master_boundary_id)
      return false;
  }
  return true;
}

}  // namespace

struct ContactSearchAhead::Search {
  enum class State { kQueued, kRunning, kDone };
  ContactModel model;
  ContactSurfaces surfaces;  // turned to the model's placement
  ContactSearchSettings settings;
  std::vector<bool> fixed_dof;
  dealii::types::global_dof_index n_dofs = 0;
  State state = State::kQueued;
  std::optional<std::vector<SlaveNode>> nodes;  // when done; empty: the search failed
};

ContactSearchAhead::ContactSearchAhead() = default;

ContactSearchAhead::~ContactSearchAhead() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void ContactSearchAhead::plan(const ElasticSystem& system, const ContactSurfaces& surfaces,
                              const std::vector<ContactModel>& upcoming,
                              const std::vector<bool>& fixed_dof, bool tangent_plane_cull) {
  pause();
  const std::lock_guard<std::mutex> lock(mutex_);
  std::list<Search> queue;
  for (const ContactModel& model : upcoming) {
    auto kept = queue_.begin();
    while (kept != queue_.end() && !same_search_geometry(kept->model, model)) ++kept;
    if (kept != queue_.end()) {
      queue.splice(queue.end(), queue_, kept);
      continue;
    }
    Search& search = queue.emplace_back();
    search.model = model;
    search.surfaces = surfaces.predicted(model);
    // One thread: the run's own stages keep the worker pool (a search that entered it would
    // hold its slots while the solve waits for them).
    search.settings = {contact_search_radius(system.diameter_if_placed(model)), 1, tangent_plane_cull};
    search.fixed_dof = fixed_dof;
    search.n_dofs = system.dof_handler().n_dofs();
  }
  queue_ = std::move(queue);
  system_ = &system;
  if (!thread_.joinable()) thread_ = std::thread([this] { work(); });
}

void ContactSearchAhead::resume() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    paused_ = false;
  }
  changed_.notify_all();
}

double ContactSearchAhead::pause() {
  const dealii::Timer timer;
  std::unique_lock<std::mutex> lock(mutex_);
  paused_ = true;
  changed_.wait(lock, [this] {
    for (const Search& search : queue_)
      if (search.state == Search::State::kRunning) return false;
    return true;
  });
  return timer.wall_time();
}

void ContactSearchAhead::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    Search* next = nullptr;
    changed_.wait(lock, [&] {
      if (stop_) return true;
      if (paused_) return false;
      for (Search& search : queue_) {
        if (search.state != Search::State::kQueued) continue;
        next = &search;
        return true;
      }
      return false;
    });
    if (stop_) return;
    next->state = Search::State::kRunning;
    lock.unlock();
    std::optional<std::vector<SlaveNode>> nodes;
    try {
      nodes = collect_slave_nodes(*system_, next->model, next->surfaces, next->fixed_dof,
                                  next->settings);
    } catch (...) {
      // The run that needs this placement searches it again and reports the error itself.
    }
    lock.lock();
    next->nodes = std::move(nodes);
    next->state = Search::State::kDone;
    changed_.notify_all();
  }
}

std::optional<std::vector<SlaveNode>> ContactSearchAhead::take(const ElasticSystem& system,
                                                               const ContactSurfaces& surfaces,
                                                               const ContactModel& model,
                                                               const std::vector<bool>& fixed_dof,
                                                               bool tangent_plane_cull) {
  pause();
  const std::lock_guard<std::mutex> lock(mutex_);
  auto it = queue_.begin();
  while (it != queue_.end() && !same_search_geometry(it->model, model)) ++it;
  if (it == queue_.end()) return std::nullopt;  // a pose nobody expected (a cutback's half step)
  queue_.erase(queue_.begin(), it);             // the poses before it have passed
  Search search = std::move(queue_.front());
  queue_.pop_front();
  bool same = search.state == Search::State::kDone && search.nodes.has_value() &&
              search.surfaces.same_faces(surfaces) &&
              search.settings.search_radius_mm == contact_search_radius(system.diameter()) &&
              search.settings.tangent_plane_cull == tangent_plane_cull &&
              search.n_dofs == system.dof_handler().n_dofs() && search.fixed_dof == fixed_dof;
  // The slave nodes were read from the mesh in another placement: they must not have moved.
  for (std::size_t n = 0; same && n < search.nodes->size(); ++n) {
    const SlaveNode& node = (*search.nodes)[n];
    same = node.position == system.support_points()[node.dofs[0]];
  }
  if (!same) return std::nullopt;
  return std::move(search.nodes);
}

}  // namespace hipfai::fem
