// hipfai — the contact nodes of every contact pair and their coupling to the master surface.
//
// Every node of a slave surface (a boundary id) is a contact node. Against a rigid master its
// gap is measured at the closest point of the rigid surface, along its normal:
//   g = (x_s + u_s - x_m - t) . n.
// Against a deformable master (a boundary on a non-matching mesh) the gap is a mortar gap: it is
// integrated against the slave node's shape function over the part of the slave surface that
// sees the master (segment-based integration, fem/mortar_segments.h),
//   D_s (u_s . n) = sum_j M_sj (u_j . n) - integral phi_s (x_s - x_m) . n,
//   D_s = integral phi_s,  M_sj = integral phi_s N_j(x_m),
// which transmits a uniform pressure exactly (the patch test) where node-to-surface
// interpolation of the master at the slave node would not. The normal n is the master normal at
// the node's closest master point (fem/boundary_projection.h).
//
// The initial gap is weighted by the node's bilinear hat on its faces' sub-grid (psi_s: 1 at the
// node, 0 at its neighbouring nodes, never negative) instead of phi_s:
//   g_s = integral psi_s (x_s - x_m) . n / integral psi_s   (over the covered part),
// a true average of the gap around the node. phi_s of a quadratic element changes sign over
// its support, so its weighted gap is not: where the gap grows quadratically away from a vertex
// node (a curved slave face leaving a master it touches) a Q2 vertex's phi-weighted gap is
// -h^2/60 per h/6 of weight, a penetration where nothing penetrates (the shortcoming for which
// Puso, Laursen & Solberg 2008, CMAME 197:555, transform the quadratic basis in their mortar
// contact). On a generated hip such spurious penetrations of 0.06-0.23 mm, at labrum nodes
// beside the femoral cartilage's thin edge, moved from node to node as the head turned and the
// nodal peak pressure jumped from step to step (docs/fem-levels.md). The kinematic rows (D_s,
// M_sj) keep phi_s, so a uniform pressure still passes exactly; zero gaps stay zero.
//
// Each kept node names the slave displacement component its contact constraint eliminates (the
// free component with the largest normal share, fem/contact_constraints.h); nodes that have no
// such component, see no master, or are barely covered by it are dropped.
#pragma once

#include "fem/contact_model.h"
#include "fem/contact_surfaces.h"
#include "fem/elastic_system.h"

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>

#include <array>
#include <map>
#include <utility>
#include <vector>

namespace hipfai::fem {

// One contact node of a slave surface.
struct SlaveNode {
  unsigned int pair = 0;                                  // index into ContactModel::contact_pairs
  std::array<dealii::types::global_dof_index, 3> dofs{};  // its x, y, z displacement dofs
  unsigned int constrained_component = 0;  // the component an active contact constraint eliminates
  dealii::Point<3> position;               // support point (mm, the run's pose, undeformed)
  dealii::Tensor<1, 3> normal;  // master normal at the closest master point (into the slave)
  double initial_gap =
      0.0;            // (x_s - x_m) . n in the run's pose (mortar-weighted for deformable masters)
  double area = 0.0;  // integral of the node's shape function over the slave surface (mm^2)
  int rigid_body = -1;  // rigid master (index into ContactModel::rigid_bodies), -1: deformable
  // Deformable master: per component, (master dof, mortar weight M_sj / D_s) pairs.
  std::array<std::vector<std::pair<dealii::types::global_dof_index, double>>, 3> master;
};

// The contact nodes of all pairs, pair by pair. fixed_dof: dofs that carry another constraint
// (hanging, bonded, symmetry), which a contact constraint may not eliminate.
// Throws hipfai::Error for a pair whose slave or deformable master boundary has no faces.
// tangent_plane_cull: MortarSegmentOptions::tangent_plane_cull (off only to check that it changes
// nothing).
std::vector<SlaveNode> collect_slave_nodes(const ElasticSystem& system, const ContactModel& model,
                                           const std::vector<bool>& fixed_dof,
                                           bool tangent_plane_cull = true);
// The same with the contact surfaces' faces kept across runs (`surfaces` brought to the
// system's placement with ContactSurfaces::update).
std::vector<SlaveNode> collect_slave_nodes(const ElasticSystem& system, const ContactModel& model,
                                           const ContactSurfaces& surfaces,
                                           const std::vector<bool>& fixed_dof,
                                           bool tangent_plane_cull = true);

// How far the search looks: contact partners are close, and 5 % of the model's size (its
// diameter) is generous.
inline double contact_search_radius(double diameter_mm) { return 0.05 * diameter_mm; }

// What the search takes from its caller rather than from the system, so that it can search a
// placement other than the mesh's current one (with `surfaces` turned to it) on any thread.
struct ContactSearchSettings {
  double search_radius_mm = 0.0;  // contact_search_radius of that placement's diameter
  std::size_t n_threads = 1;      // threads of the mortar integration
  bool tangent_plane_cull = true;
};
// The same with the settings given. Reads the system's slave surfaces (dofs, support points,
// mapping) and its dof numbering, never its placement of the master faces (`surfaces` has them),
// and makes no MPI call.
std::vector<SlaveNode> collect_slave_nodes(const ElasticSystem& system, const ContactModel& model,
                                           const ContactSurfaces& surfaces,
                                           const std::vector<bool>& fixed_dof,
                                           const ContactSearchSettings& settings);

// The nodes of one contact pair's slave boundary as the mesh gives them: their pair, dofs,
// support points and areas (the integral of each node's shape function over the boundary, under
// the mapping), the rest of each SlaveNode unset. What the search reads of the mesh besides the
// faces.
struct SlaveBoundaryNodes {
  dealii::types::boundary_id boundary_id = 0;  // the slave boundary
  std::vector<SlaveNode> nodes;
  std::map<dealii::types::global_dof_index, std::size_t> node_of_dof;  // x dof -> index into nodes
};
// Those of every contact pair of `model`, in pair order, from the system as it is now. Throws
// hipfai::Error for a pair whose slave boundary has no faces.
std::vector<SlaveBoundaryNodes> slave_boundary_nodes(const ElasticSystem& system,
                                                     const ContactModel& model);
// True when `slaves` are those of `model`'s contact pairs: the same slave boundaries, in pair order.
bool slave_boundaries_of(const std::vector<SlaveBoundaryNodes>& slaves, const ContactModel& model);
// The same search from them (one per pair of `model`): of the system it reads only the finite
// element's tables, never the mesh, its dofs or support points (the faces carry their dofs), so it
// can run on another thread while the mesh is moved and its dofs renumbered.
std::vector<SlaveNode> collect_slave_nodes(const ElasticSystem& system, const ContactModel& model,
                                           const ContactSurfaces& surfaces,
                                           const std::vector<SlaveBoundaryNodes>& slaves,
                                           const std::vector<bool>& fixed_dof,
                                           const ContactSearchSettings& settings);

}  // namespace hipfai::fem
