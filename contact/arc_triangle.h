// hipfai — exact circle/arc versus triangle primitives for cylindrical segmenting (thesis §3.2,
// App. A-D). Shared by the table-based query (cylindrical_segmenting.h), the range finder and the
// exhaustive oracle (oracle_cylindrical.h), so that all three decide with the same arithmetic.
//
// The axis frame. A rotation is given by its centre c (mm) and axis a (any non-zero length,
// normalised here). Points are expressed in the right-handed orthonormal frame (e1, e2, a) with its
// origin at c: local = ((p-c).e1, (p-c).e2, (p-c).a). In this frame a rotation by +angle about a
// (right-hand rule, "anticlockwise" looking down the axis) increases the cylindrical angle
// theta = atan2(y, x) and keeps r = hypot(x, y) and z unchanged, so a mobile vertex moves on the
// circle (r, z) and can only meet the fixed triangles that this circle crosses.
//
// Angles are radians inside; wrap_angle() maps to (-pi, pi].
#pragma once

#include "geometry/tri_mesh.h"

#include <array>
#include <cstdint>
#include <limits>
#include <numbers>

namespace hipfai::contact {

using geometry::Vec3;

struct AxisFrame {
  Vec3 centre = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();  // unit
  Vec3 e1 = Vec3::UnitX();    // unit, perpendicular to axis
  Vec3 e2 = Vec3::UnitY();    // axis x e1

  Vec3 to_local(const Vec3& point) const {
    const Vec3 d = point - centre;
    return {d.dot(e1), d.dot(e2), d.dot(axis)};
  }
  Vec3 direction_to_local(const Vec3& direction) const {
    return {direction.dot(e1), direction.dot(e2), direction.dot(axis)};
  }
};

// The frame of the rotation about `axis` through `centre`. `valid` is false (and the frame is
// the identity) when the axis has zero length or any input is not finite.
struct AxisFrameResult {
  AxisFrame frame;
  bool valid = false;
};
AxisFrameResult make_axis_frame(const Vec3& centre, const Vec3& axis);

// Maps an angle to (-pi, pi].
double wrap_angle(double angle_rad);

// Cylindrical coordinates of a local point: r >= 0, theta in (-pi, pi] (0 for r = 0), z.
struct Cylindrical {
  double r = 0.0;
  double theta = 0.0;
  double z = 0.0;
};
Cylindrical to_cylindrical(const Vec3& local);

// Exact cylindrical bounding volume of a triangle given in local coordinates (App. A): r_min is
// the exact distance from the axis to the triangle (the distance from the origin to the triangle
// projected on the xy plane, 0 if the projection covers the axis), not the smallest vertex r.
struct CylindricalBounds {
  double r_min = 0.0;
  double r_max = 0.0;
  double z_min = 0.0;
  double z_max = 0.0;
};
CylindricalBounds triangle_cylindrical_bounds(const Vec3& a, const Vec3& b, const Vec3& c);

// A triangle's angular extent about the axis: every point of it has theta in [lo, lo + width]
// (mod 2 pi). Seen from the axis, a triangle off it lies in an open half-plane through the axis,
// so its vertices' angles span its whole extent (less than pi); one with a vertex on the axis, or
// spanning 0.9 pi or more (around the axis, or nearly), gets every angle (width 2 pi). The extent
// is widened by kAngularExtentMarginRad on both sides, far above the rounding of atan2 and of the
// crossing angles (acos near +-1 loses about sqrt(ulp), ~1e-8 rad), so a crossing of the circle
// with the triangle (circle_triangle_crossings) always lies inside it.
constexpr double kAngularExtentMarginRad = 1e-6;
struct AngularExtent {
  double lo = -std::numbers::pi;
  double width = 2.0 * std::numbers::pi;
  bool all_angles() const { return width >= 2.0 * std::numbers::pi; }
};
AngularExtent triangle_angular_extent(const Vec3& a, const Vec3& b, const Vec3& c);

// Exact Euclidean distance from a point to a (possibly degenerate) triangle, mm.
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Crossings of the circle {(r cos t, r sin t, z)} with the triangle (a, b, c), local frame
// (App. C Eq. 24-29 with the exact inside test of App. B). Writes the crossing angles t in
// (-pi, pi] to `angles_rad` and returns their number: 0, 1 (tangent circle, or only one root
// inside) or 2.
// Degenerate cases, chosen so that nothing is NaN and every decision is reproducible:
//   - r == 0 (vertex on the axis): the circle is a point that never moves; 0 crossings.
//   - zero-area triangle (no plane, no outward normal): 0 crossings; in a closed mesh its
//     neighbours cover the same surface.
//   - triangle plane perpendicular to the axis (the circle lies in the plane or never meets it):
//     0 crossings; the circle slides on, never through, such a triangle.
// The inside test accepts points up to a relative 1e-12 outside an edge, so a circle through a
// shared edge or a corner is found by at least one of the triangles sharing it.
int circle_triangle_crossings(double r, double z, const Vec3& a, const Vec3& b, const Vec3& c,
                              std::array<double, 2>& angles_rad);

// The parts of circle_triangle_crossings that depend on the triangle only: n = (b - a) x (c - a),
// |n|^2, rho = hypot(n_x, n_y), phi = atan2(n_y, n_x) and n.a. A table computes them once per
// triangle instead of once per circle; the overload below evaluates the very same expressions
// with them, so its crossings equal circle_triangle_crossings' bit for bit.
struct CrossingPlane {
  Vec3 n = Vec3::Zero();
  double n2 = 0.0;
  double rho = 0.0;
  double phi = 0.0;
  double offset = 0.0;  // n.a
};
CrossingPlane crossing_plane(const Vec3& a, const Vec3& b, const Vec3& c);
int circle_triangle_crossings(double r, double z, const Vec3& a, const Vec3& b, const Vec3& c,
                              const CrossingPlane& plane, std::array<double, 2>& angles_rad);

// The nearest crossing of one vertex's circle: smallest angular distance |delta| where
// delta = wrap(theta_crossing - theta_vertex) (App. C: min(|dt mod 2pi|, |-dt mod 2pi|)).
// Ties are broken by the smaller triangle index, then by delta > 0, so the choice does not
// depend on the order in which candidates are offered (table order vs oracle order).
struct NearestCrossing {
  double abs_delta_rad = std::numeric_limits<double>::infinity();
  double delta_rad = 0.0;
  double crossing_theta_rad = 0.0;
  std::int32_t triangle = -1;

  bool found() const { return triangle >= 0; }
  void offer(double vertex_theta_rad, double crossing_theta_rad_in, std::int32_t triangle_in) {
    const double delta = wrap_angle(crossing_theta_rad_in - vertex_theta_rad);
    const double abs_delta = delta < 0.0 ? -delta : delta;
    const bool better =
        abs_delta < abs_delta_rad ||
        (abs_delta == abs_delta_rad &&
         (triangle_in < triangle || (triangle_in == triangle && delta > delta_rad)));
    if (!better) return;
    abs_delta_rad = abs_delta;
    delta_rad = delta;
    crossing_theta_rad = crossing_theta_rad_in;
    triangle = triangle_in;
  }
};

// App. D: is the vertex (r, vertex_theta, z) inside the fixed solid, given its nearest crossing
// (crossing_theta, same r and z) on a triangle with outward unit normal `normal_local`?
//   T' = B x Z at the crossing V', T = +-T' oriented so that T.N >= 0, A = V - V';
//   T.A < 0 => penetrating. T.N == 0 (circle tangent to the triangle's plane): penetrating iff
//   N.A < 0. T.A == 0 (arc of 0 or pi): not penetrating.
// A vertex whose arc distance r*|delta| to the nearest crossing is at most `touching_mm` is on
// the surface: touching, not penetrating (rounding cannot decide the side of a vertex that lies
// on the surface). Correct for a closed, outward-oriented fixed mesh whose surface the circle
// crosses transversally at the nearest crossing; see cylindrical_segmenting.h.
enum class ArcVerdict { kOutside, kTouching, kPenetrating };
ArcVerdict arc_verdict(double r, double z, double vertex_theta_rad, double crossing_theta_rad,
                       const Vec3& normal_local, double touching_mm);

// On which sides of a crossing (angle c, outward unit normal N, circle of radius r at height z)
// arc_verdict can say "penetrating" for a vertex whose nearest crossing it is: `anticlockwise`
// for vertices at theta > c (up to pi away), `clockwise` for theta < c; both when the circle is
// tangent to the triangle's plane there. Computed with arc_verdict's own arithmetic, so away from
// the crossing (where rounding could flip T.A) the two never disagree.
struct CrossingSides {
  bool anticlockwise = false;
  bool clockwise = false;
};
CrossingSides penetrating_sides(double r, double z, double crossing_theta_rad, const Vec3& normal_local);

// Sign of the anticlockwise tangent t = a x B at the crossing against the outward normal:
// > 0 when moving anticlockwise through the crossing leaves the solid, < 0 when it enters,
// 0 when the circle is tangent to the triangle's plane.
double crossing_exit_sign(double crossing_theta_rad, const Vec3& normal_local);

// Default touching tolerance (arc length, mm) of every cylindrical query.
inline constexpr double kDefaultTouchingMm = 1e-9;

}  // namespace hipfai::contact
