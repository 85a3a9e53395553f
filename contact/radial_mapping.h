// hipfai — the three mapping functions of radial segmenting (thesis §3.3.3.1, Eq. 5-8, App. E)
// and the exact cell coverage of a triangle.
//
// A mapping sends a direction (a non-zero vector from the centre O) to table coordinates
// (a1, a2, a3); the table is a grid of dimension x dimension cells per face. Cell id =
// (a3 * dimension + j) * dimension + i with i, j the discretised a1, a2.
//
//   kSpherical (Eq. 5): a1 = atan2(y, x) in [-pi, pi), a2 = polar angle in [0, pi]
//     (computed as atan2(hypot(x, y), z), equal to acos(z / R) but well conditioned at the
//     poles), one face. The a1 cells wrap around the seam a1 = +-pi (atan2 returning +pi is put in
//     the first cell, like -pi).
//   kCartesian (Eq. 6): a1 = x / R, a2 = y / R in [-1, 1], a3 = 1 if z > 0 else 0 (two faces).
//   kCube (App. E, intent): the equal-angle (quasi-uniform) cube map. The face is the axis k of
//     largest |component| (ties -> lowest axis x < y < z) and its sign: a3 = 2k + (component < 0);
//     with (k1, k2) = ((k+1) % 3, (k+2) % 3) the other axes,
//       a1 = atan(d[k1] / |d[k]|) + pi/4,  a2 = atan(d[k2] / |d[k]|) + pi/4,  both in [0, pi/2].
//     The case table printed in App. E leaves gaps (directions with theta on the pi/4 borders fall
//     in no case, and the face pairing is not symmetric); this definition covers every direction.
//
// Domains are fixed (not fitted to the fixed mesh's vertices as Eq. 9 does): the fitted range of
// Eq. 9 misses triangle interiors that bulge past the vertices' range, and a fixed grid lets
// update_triangles() re-bin single triangles without invalidating the rest of the table. The
// cell width is domain / dimension (Eq. 11 divides by dimension - 1, which puts half cells at the
// ends; dividing by dimension partitions the domain exactly).
//
// Dimension (Eq. 8): ceil(sqrt(table_size / faces)) with faces = 1, 2, 6.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace hipfai::contact {

using Vec3 = Eigen::Vector3d;

enum class RadialMapping { kSpherical, kCartesian, kCube };

// Every mapping, in declaration order.
inline constexpr std::array<RadialMapping, 3> kRadialMappings = {RadialMapping::kSpherical, RadialMapping::kCartesian,
                                                                RadialMapping::kCube};

const char* to_string(RadialMapping mapping);

struct RadialCoordinates {
  double a1 = 0.0;
  double a2 = 0.0;
  int a3 = 0;
};

struct RadialGrid {
  RadialMapping mapping = RadialMapping::kCube;
  int dimension = 1;  // cells along a1 and along a2 on each face
  int faces = 6;      // 1 (spherical), 2 (cartesian), 6 (cube)

  int num_cells() const { return faces * dimension * dimension; }
  double a1_min() const;
  double a1_width() const;  // domain length along a1 (a2 likewise below)
  double a2_min() const;
  double a2_width() const;
  // Widest angle (rad) a single cell spans along either axis, used by the neighbour search.
  double nominal_cell_angle_rad() const;
};

// Eq. 8. Throws hipfai::Error if table_size < 1 or so large the cell count overflows.
RadialGrid make_radial_grid(RadialMapping mapping, std::int64_t table_size);

// The mapping of a non-zero direction (any length). Undefined for the zero vector.
RadialCoordinates map_direction(RadialMapping mapping, const Vec3& direction);

// The cell of a non-zero direction.
int cell_of_direction(const RadialGrid& grid, const Vec3& direction);

// Unit direction through the centre of a cell (the ray of ray-based sampling).
Vec3 cell_centre_direction(const RadialGrid& grid, int cell);

// Appends to `cells` (unsorted, no duplicates) every cell whose region meets the cone from O over
// the convex planar polygon `polygon` (vertices relative to O, in order, >= 3 of them). The plane
// of the polygon must not pass through O (callers check with polygon_plane_clear_of_centre).
// CONSERVATIVE AND EXACT: the result is a superset of the cells of every direction the polygon
// covers, with a margin (1e-8 rad, and full a1 rings within ~1e-6 rad of a pole) that absorbs the
// rounding of map_direction and of the watertight ray test, so no direction the ray test accepts
// lands in a cell that lacks the triangle. Cell borders are curves (Fig. 24), so the extents are
// computed from the curved geometry, not from the vertices alone:
//   - extremes of a linear function (x/R, y/R, z/R) over a great-circle arc are at its ends or at
//     the arc point closest to the axis; over the cone's interior only if the axis is inside;
//   - azimuth is monotone along any arc that avoids the poles (full ring if a pole is inside);
//   - cube coordinates are linear-fractional on the polygon clipped to the face's pyramid, so
//     their extremes are at the clipped polygon's vertices; inside that rectangle of cells, a cell
//     whose four corner rays all lie beyond one of the polygon's edge planes (through O) by more
//     than 1e-6 rad is left out (both are convex cones: such a plane separates them).
void cells_of_polygon(const RadialGrid& grid, std::span<const Vec3> polygon,
                      std::vector<int>& cells);

// True when the triangle's plane passes clearly away from O, i.e. its cone from O is a proper
// spherical triangle that cells_of_polygon can bin: plane distance > 1e-6 x the largest vertex
// distance, and non-zero area. The others go to the table's always-checked list.
bool polygon_plane_clear_of_centre(const Vec3& a, const Vec3& b, const Vec3& c);

// Appends every cell meeting the spherical cap of angular radius `radius_rad` around `direction`
// (conservative, via the circumscribed square); all cells when radius_rad >= ~80 deg.
void cells_of_cap(const RadialGrid& grid, const Vec3& direction, double radius_rad,
                  std::vector<int>& cells);

}  // namespace hipfai::contact
