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
  ContactModel model;
  ContactSurfaces surfaces;  // turned to the model's placement
  ContactSearchSettings settings;
  std::vector<bool> fixed_dof;
  dealii::types::global_dof_index n_dofs = 0;
  std::future<std::optional<std::vector<SlaveNode>>> nodes;  // empty: the search failed
  std::optional<std::vector<SlaveNode>> result;
  bool finished = false;
};

ContactSearchAhead::ContactSearchAhead() = default;
ContactSearchAhead::~ContactSearchAhead() { wait(); }

void ContactSearchAhead::start(const ElasticSystem& system, const ContactSurfaces& surfaces,
                               const ContactModel& next, const std::vector<bool>& fixed_dof,
                               bool tangent_plane_cull, std::size_t n_threads) {
  wait();
  search_ = std::make_unique<Search>();
  Search& search = *search_;
  search.model = next;
  search.surfaces = surfaces.predicted(next);
  search.settings = {contact_search_radius(system.diameter_if_placed(next)), n_threads,
                     tangent_plane_cull};
  search.fixed_dof = fixed_dof;
  search.n_dofs = system.dof_handler().n_dofs();
  // A thread of its own, so the search overlaps the caller's solve from the start; its mortar
  // integration shares the process's worker pool (core/parallel.h) with the solve.
  search.nodes = std::async(std::launch::async, [&system, &search]() {
    try {
      return std::optional<std::vector<SlaveNode>>(collect_slave_nodes(
          system, search.model, search.surfaces, search.fixed_dof, search.settings));
    } catch (...) {
      // The run that needs this placement searches it again and reports the error itself.
      return std::optional<std::vector<SlaveNode>>();
    }
  });
}

double ContactSearchAhead::wait() {
  if (!search_ || search_->finished) return 0.0;
  const dealii::Timer timer;
  search_->result = search_->nodes.get();
  search_->finished = true;
  return timer.wall_time();
}

std::optional<std::vector<SlaveNode>> ContactSearchAhead::take(const ElasticSystem& system,
                                                               const ContactSurfaces& surfaces,
                                                               const ContactModel& model,
                                                               const std::vector<bool>& fixed_dof,
                                                               bool tangent_plane_cull) {
  if (!search_) return std::nullopt;
  wait();
  std::unique_ptr<Search> search = std::move(search_);
  bool same = search->result.has_value() && same_search_geometry(search->model, model) &&
              search->surfaces.same_faces(surfaces) &&
              search->settings.search_radius_mm == contact_search_radius(system.diameter()) &&
              search->settings.tangent_plane_cull == tangent_plane_cull &&
              search->n_dofs == system.dof_handler().n_dofs() && search->fixed_dof == fixed_dof;
  // The slave nodes were read from the mesh in its previous placement: they must not have moved.
  for (std::size_t n = 0; same && n < search->result->size(); ++n) {
    const SlaveNode& node = (*search->result)[n];
    same = node.position == system.support_points()[node.dofs[0]];
  }
  if (!same) {
    ++discarded_;
    return std::nullopt;
  }
  ++used_;
  return std::move(search->result);
}

}  // namespace hipfai::fem
