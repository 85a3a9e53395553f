// hipfai — radial segmenting collision detection for sliding objects (thesis §3.3, App. F).
//
// Inputs: the table of the FIXED mesh F around the centre O (radial_table.h, built once), the
// fixed mesh itself (its current coordinates), and the MOBILE mesh M already posed by the caller.
// For each mobile vertex v the ray from O through v is tested against the fixed triangles stored
// in the cell of its direction (and the always-checked list), with the watertight test of
// ray_triangle.h. Only mobile VERTICES are tested (the thesis' definition).
//
// THE CROSSING RULE (shared by radial_segmenting, oracle_radial and ray_sampling). Let
// r = |v - O| and let the crossings of the ray be at distances t_i r (ray_triangle_crossing with
// d = v - O, so t_i = 1 is v itself) with facing s_i (+1 exit, -1 enter, from the outward
// normals). The crossing that matters is the one ADJACENT to v on the side the configuration
// pushes it back to; the normals then say whether v is inside the fixed solid (thesis Fig. 40,
// §3.6.5: between two layers of F the adjacent normals point toward v and v is outside).
//   kMobileInsideFixed (femoral cartilage sliding inside the socket; the thesis' Fig. 27):
//     the LAST crossing with t <= 1 (largest t; the surface between O and v nearest to v).
//     v penetrates iff it exists, t < 1, and it ENTERS the fixed solid (s = -1).
//     depth_mm = (1 - t) r  = | Dist - |v - O| |  (Eq. 36).
//   kFixedInsideMobile (the fixed object inside the mobile one; inequalities reversed):
//     the FIRST crossing with t >= 1 (smallest t; the surface beyond v nearest to v).
//     v penetrates iff it exists, t > 1, and it EXITS the fixed solid (s = +1).
//     depth_mm = (t - 1) r.
// Ties (equal t, e.g. a ray through an edge or vertex shared by several triangles) are broken by
// the lowest triangle index, so a shared edge is counted once and the answer does not depend on
// the order triangles are visited. A vertex exactly on the fixed surface (adjacent crossing at
// t == 1) does not penetrate (depth 0, like Fig. 27's strict Diff < 0). A vertex AT the centre
// (v == O) has no ray and never penetrates. Only crossings strictly in front of O count (t > 0).
// Because the rule looks only at the adjacent crossing it also works for open surfaces (a socket
// patch whose normals face O): v beyond the patch, seen from O, penetrates.
//
// Output: PenetrationPair{mobile_vertex, fixed_triangle (the adjacent crossing's), depth_mm},
// sorted by vertex, one per penetrating vertex; angle_deg is NaN.
#pragma once

#include "contact/penetration_result.h"
#include "contact/radial_table.h"
#include "geometry/tri_mesh.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::contact {

namespace detail {
class RadialPoseState;
}  // namespace detail

enum class RadialConfiguration { kMobileInsideFixed, kFixedInsideMobile };

const char* to_string(RadialConfiguration configuration);

// The opposite configuration: what the nesting looks like after swapping the roles of the meshes.
RadialConfiguration swapped(RadialConfiguration configuration);

// Which crossing decides (see THE CROSSING RULE above for kAdjacent).
//   kAdjacent  the crossing next to v: the fixed solids are taken one surface at a time.
//   kUnion     the fixed mesh is read as a union of closed solids that may touch or overlap
//              (cartilage on bone, labrum on cartilage): v penetrates iff it lies inside the
//              union, and the depth is measured to the union's boundary along the ray — for
//              kMobileInsideFixed the point nearest v towards O where the ray enters the union,
//              for kFixedInsideMobile the point nearest v away from O where it leaves it. This is
//              the depth of thesis Fig. 27 when every fixed polygon between O and v is reported
//              and the deepest kept, and it stays right when a vertex has passed through a thin
//              layer into the tissue behind it. Inside-ness is the winding number along the
//              ray: sum over crossings beyond v of +1 (exit) / -1 (enter); the crossings of
//              one ray through a shared edge or vertex (equal t and facing, triangles sharing a
//              vertex) count once. If the union reaches O (kMobileInsideFixed) the depth is |v - O|.
//   kBeyond    the thesis' rule read literally (§3.3.2, Fig. 27 without its normals; §4.3.2.1: "If
//              the radial distance of a femur vertex to the center was more than the radial
//              distance of its corresponding acetabular soft tissues polygon, the femur vertex was
//              returned as a penetrated vertex"): for kMobileInsideFixed v penetrates iff some fixed
//              triangle lies between O and v on its ray (a crossing with 0 < t < 1), whatever its
//              facing, and the depth is measured to the crossing nearest O (the socket's articular
//              surface): (1 - t_min) |v - O|. For kFixedInsideMobile: a crossing with t > 1, depth
//              (t_max - 1) |v - O|. It measures how far v stands beyond the fixed surface in the
//              fixed mesh's directions, also when v has passed through a thin layer (the labrum)
//              and is no longer inside any fixed solid.
enum class RadialCrossingRule { kAdjacent, kUnion, kBeyond };

// "adjacent", "union", "beyond": the names users write (study options) and reports print.
const char* to_string(RadialCrossingRule rule);

struct RadialQueryOptions {
  RadialConfiguration configuration = RadialConfiguration::kMobileInsideFixed;
  RadialCrossingRule rule = RadialCrossingRule::kAdjacent;
  // 1 or 2 threads over the mobile vertices (results are identical either way).
  int num_threads = 1;
  // Deformation without updating the table (§3.3.4): when k > 0, each vertex also checks every
  // cell within k nominal cell widths (RadialGrid::nominal_cell_angle_rad, measured as an angle
  // around its direction, across seams, poles and faces). A fixed triangle whose points have
  // turned by less than that angle since the table was built is still found.
  int neighbour_cells = 0;
  // (Radial spans, radial_spans.h, decide the vertices outside the table's cap or at a distance
  // from O where the rule cannot find its crossing without a triangle test: the same answers bit
  // for bit. The benchmark and the tests switch them off through contact/detail/ablation.h.)
};

// The per-pose query. `fixed` must have the triangles the table was built from (coordinates may
// have moved). Returns kInvalidInput (with a message) for a size mismatch, non-finite mobile
// coordinates or bad options; never throws for data-dependent reasons.
PenetrationResult radial_segmenting(const RadialTable& table, const geometry::TriMesh& fixed,
                                    const geometry::TriMesh& mobile,
                                    const RadialQueryOptions& options);

// A rigid body pair prepared for many poses: the fixed mesh with its table, and the
// mobile mesh at rest, its vertices stored in buckets (a coarse rest direction about O and a
// 0.5 mm shell of rest distance). Rotation about the centre keeps each mobile vertex's distance
// from O and turns a bucket's cone of directions as a whole, so query(pose) drops whole buckets
// without posing a vertex: those whose distances the radial spans rule out (radial_spans.h: the
// rule needs a crossing on a side of v where the fixed mesh has none), those whose cone the
// pose turns away from the spans' cap (every fixed point lies within the cap), and those whose
// distances the spans of the triangles near their turned cone rule out (the distance map below).
// It poses and tests only the vertices of the other buckets. A pose that also translates moves a distance by at
// most s = |c' - O| (c' = pose^-1 O) and a direction by at most asin(s / |v - O|), which widens
// both tests. Same answer as radial_segmenting(table, fixed,
// pose * mobile, options) bit for bit (each kept vertex is posed as pose * v, like
// bench::transformed and geometry::apply_transform).
// `table` and `fixed` are referenced, not copied: they must outlive this object and not change
// (build a new one after a deformation). status() is kInvalidInput (message()) for the inputs
// radial_segmenting rejects.
class RadialPoseQuery {
 public:
  RadialPoseQuery(const RadialTable& table, const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                  const RadialQueryOptions& options);
  QueryStatus status() const;
  const std::string& message() const;
  // Mobile vertices that may penetrate at some pose (the others were dropped once).
  std::size_t num_kept_vertices() const;
  PenetrationResult query(const Eigen::Isometry3d& pose) const;
  // A rotation about the table's centre O, each kept vertex posed as O + rotation (v - O) (as the
  // studies pose a femur): the same answer as radial_segmenting on the mesh posed that way, bit for bit.
  PenetrationResult query_rotation(const Eigen::Matrix3d& rotation) const;
  // Mobile vertices query(pose) poses and tests (those of the buckets it does not drop).
  std::size_t num_tested_vertices(const Eigen::Isometry3d& pose) const;

 private:
  // The buckets and the distance map (contact/detail/radial_pose_state.h), shared by copies: they
  // never change after construction.
  std::shared_ptr<const detail::RadialPoseState> state_;
};

// Role swap (thesis §3.3.1, §4.3: "repeated by exchanging the role"): the vertices of `fixed`
// are tested against the triangles of `mobile`, with the configuration swapped (if M slides
// inside F, F is outside M). Builds a table for the posed `mobile` (so call it per pose).
// In the returned pairs mobile_vertex indexes `fixed`'s vertices and fixed_triangle indexes
// `mobile`'s triangles.
PenetrationResult radial_swap_roles(const geometry::TriMesh& fixed,
                                    const geometry::TriMesh& mobile, const Vec3& centre,
                                    const RadialTableOptions& table_options,
                                    const RadialQueryOptions& options);

}  // namespace hipfai::contact
