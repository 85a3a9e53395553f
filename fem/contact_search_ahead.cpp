#include "fem/contact_search_ahead.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>


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

// CPU time of the calling thread, seconds.
double thread_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// The searching thread's nice value: the solve's threads (nice 0) get about nine tenths of a
// core they share with it (CFS weights 1024 and 110).
constexpr int kSearchNice = 10;

}  // namespace

struct ContactSearchAhead::Search {
  enum class State { kQueued, kRunning, kDone };
  ContactModel model;
  ContactSurfaces surfaces;  // turned to the model's placement
  std::shared_ptr<const std::vector<SlaveBoundaryNodes>> slaves;
  const ElasticSystem* system = nullptr;  // for its finite element's tables only
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
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!slaves_ && !upcoming.empty())
    slaves_ = std::make_shared<const std::vector<SlaveBoundaryNodes>>(
        slave_boundary_nodes(system, upcoming.front()));
  std::list<std::shared_ptr<Search>> queue;
  for (const ContactModel& model : upcoming) {
    if (!slave_boundaries_of(*slaves_, model)) continue;  // the run searches itself
    auto kept = queue_.begin();
    while (kept != queue_.end() && !same_search_geometry((*kept)->model, model)) ++kept;
    if (kept != queue_.end() && (*kept)->slaves == slaves_) {
      queue.splice(queue.end(), queue_, kept);
      continue;
    }
    auto search = std::make_shared<Search>();
    search->model = model;
    search->surfaces = surfaces.predicted(model);
    search->slaves = slaves_;
    search->system = &system;
    // One thread: the run's own stages keep the worker pool (a search that entered it would
    // hold its slots while the solve waits for them).
    search->settings = {contact_search_radius(system.diameter_if_placed(model)), 1, tangent_plane_cull};
    search->fixed_dof = fixed_dof;
    search->n_dofs = system.dof_handler().n_dofs();
    queue.push_back(std::move(search));
  }
  queue_ = std::move(queue);
  if (!thread_.joinable()) thread_ = std::thread([this] { work(); });
  changed_.notify_all();
}

void ContactSearchAhead::work() {
  // The searches are ahead of the solves: they need only the time the solves leave, so this
  // thread yields its core to the run's own threads (the run's stages split their loops over the
  // worker pool, and a search taking a core would leave those loops to one thread). Linux gives
  // each thread its own nice value; where that fails the thread runs at the normal priority.
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), kSearchNice);
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    std::shared_ptr<Search> next;
    changed_.wait(lock, [&] {
      if (stop_) return true;
      for (const std::shared_ptr<Search>& search : queue_) {
        if (search->state != Search::State::kQueued) continue;
        next = search;
        return true;
      }
      return false;
    });
    if (stop_) return;
    next->state = Search::State::kRunning;
    lock.unlock();
    std::optional<std::vector<SlaveNode>> nodes;
    const double started = thread_seconds();
    try {
      nodes = collect_slave_nodes(*next->system, next->model, next->surfaces, *next->slaves,
                                  next->fixed_dof, next->settings);
    } catch (...) {
      // The run that needs this placement searches it again and reports the error itself.
    }
    const double spent = thread_seconds() - started;
    lock.lock();
    ++searched_;
    search_seconds_ += spent;
    next->nodes = std::move(nodes);
    next->state = Search::State::kDone;
    changed_.notify_all();
  }
}

std::optional<double> ContactSearchAhead::remaining_seconds() {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto left = std::count_if(queue_.begin(), queue_.end(), [](const std::shared_ptr<Search>& search) {
    return search->state != Search::State::kDone;
  });
  if (left == 0) return 0.0;
  if (searched_ == 0) return std::nullopt;
  return static_cast<double>(left) * search_seconds_ / static_cast<double>(searched_);
}

std::optional<std::vector<SlaveNode>> ContactSearchAhead::take(const ElasticSystem& system,
                                                               const ContactSurfaces& surfaces,
                                                               const ContactModel& model,
                                                               const std::vector<bool>& fixed_dof,
                                                               bool tangent_plane_cull) {
  std::unique_lock<std::mutex> lock(mutex_);
  auto it = queue_.begin();
  while (it != queue_.end() && !same_search_geometry((*it)->model, model)) ++it;
  if (it == queue_.end()) return std::nullopt;  // a pose nobody expected (a cutback's half step)
  queue_.erase(queue_.begin(), it);             // the poses before it have passed
  const std::shared_ptr<Search> search = queue_.front();
  queue_.pop_front();
  if (search->state == Search::State::kRunning)
    changed_.wait(lock, [&] { return search->state == Search::State::kDone; });
  lock.unlock();
  bool same = search->state == Search::State::kDone && search->nodes.has_value() &&
              search->surfaces.same_faces(surfaces) &&
              search->settings.search_radius_mm == contact_search_radius(system.diameter()) &&
              search->settings.tangent_plane_cull == tangent_plane_cull &&
              search->n_dofs == system.dof_handler().n_dofs() && search->fixed_dof == fixed_dof;
  // The slave nodes were read from the mesh before: they must not have moved (their dofs are
  // those of the faces, compared above).
  const std::vector<dealii::Point<3>>& points = system.support_points();
  bool slaves_same = true;
  for (std::size_t p = 0; same && slaves_same && p < search->slaves->size(); ++p) {
    for (const SlaveNode& node : (*search->slaves)[p].nodes) {
      slaves_same = node.dofs[0] < points.size() && node.position == points[node.dofs[0]];
      if (!slaves_same) break;
    }
  }
  if (!slaves_same) {
    const std::lock_guard<std::mutex> relock(mutex_);
    if (slaves_ == search->slaves) slaves_.reset();
  }
  if (!same || !slaves_same) return std::nullopt;
  return std::move(search->nodes);
}

}  // namespace hipfai::fem
