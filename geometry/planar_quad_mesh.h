#pragma once

// An all-quadrilateral mesh of a plane domain (the stereographic image of a tissue's shadow, see
// hip_volume_mesh.h) and the checks and repairs the volume mesher applies to it before every
// node becomes a column of hexahedra.

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hipfai::geometry {

struct PlanarQuadMesh {
  std::vector<Eigen::Vector2d> nodes;
  std::vector<bool> on_boundary;                     // per node: on the domain's outline
  std::vector<std::array<std::int32_t, 4>> quads;    // counter-clockwise in the plane
};

// Interior angle of `quad` at its corner c, in [0, 2 pi): pi/2 for a square, above pi where the
// quad is reflex there.
double quad_corner_angle(const PlanarQuadMesh& mesh, const std::array<std::int32_t, 4>& quad, std::size_t c);

// Smallest sine of a corner angle over all quads (negative for a reflex corner).
double planar_quality(const PlanarQuadMesh& mesh);

// Corners of boundary nodes that only one quad uses and that are flatter than this are opened by
// open_flat_boundary_corners (the corner range the mesher calls good, 30-150 deg).
inline constexpr double kFlatBoundaryCornerDeg = 150.0;

// What open_flat_boundary_corners did.
struct FlatCornerRepair {
  std::size_t found = 0;   // boundary nodes used by one quad at a corner above the bound
  std::size_t opened = 0;  // of these, given a second quad by an edge swap
};

// A boundary node used by one quad only, whose corner there is near 180 deg, lies between two
// boundary edges of one quad: that quad is a triangle with the node in the middle of one side,
// and a Q2 vertex shape function there integrates to almost nothing (its Jacobian vanishes as
// the corner opens to 180 deg), so the node's nodal area, and any nodal contact pressure divided
// by it, is wrong by a large factor. Such a quad q = (v, n, o, p) and a neighbour across n-o or
// o-p form a hexagon; splitting the hexagon by the diagonal from v instead of the shared edge
// gives v two quads (an edge swap, the quad-mesh counterpart of a triangle edge flip). Of the two
// neighbours, the swap whose two quads have the larger smallest corner sine is taken, when both
// quads are convex, that sine is above the pair's before, no interior node is left in fewer
// than three quads and no other boundary node is left as the flat corner of one quad. Nodes do
// not move; the quad count is unchanged. Repeats until no swap is possible.
FlatCornerRepair open_flat_boundary_corners(PlanarQuadMesh& mesh,
                                            double max_corner_deg = kFlatBoundaryCornerDeg);

// A triangle mesh of a plane domain, the step before quadrangles.
struct PlanarTriMesh {
  std::vector<Eigen::Vector2d> nodes;
  std::vector<bool> on_boundary;
  std::vector<std::array<std::int32_t, 3>> triangles;  // counter-clockwise
};

// A boundary node with one triangle only, between the outline's two edges at a corner flatter
// than the bound, is an ear: a sliver lying along the outline (on a thin domain, the labrum's
// band, the triangulator makes them). Its edge opposite the node is flipped with the triangle
// across it, so the node gets two triangles — when both new triangles are counter-clockwise,
// their smallest angle is larger than the pair's before, no interior node is left in fewer than
// three triangles and no boundary node becomes such an ear. Repeats until no flip is possible.
FlatCornerRepair flip_flat_boundary_ears(PlanarTriMesh& mesh, double max_corner_deg = kFlatBoundaryCornerDeg);

// Every triangle split into three quads through its edge midpoints and centroid (all-quad
// always; the corner a triangle has at a node is the corner of that node's quad), then the
// interior nodes smoothed towards the mean of their quad-edge neighbours for `sweeps` sweeps,
// each kept only while it does not lower planar_quality. Boundary nodes stay on the outline.
PlanarQuadMesh split_into_quads(const PlanarTriMesh& mesh, int sweeps = 5);

}  // namespace hipfai::geometry
