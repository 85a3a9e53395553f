#include "contact/arc_triangle.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hipfai::contact {
namespace {

// Relative slack of the inside-triangle test: the crossing point is computed with rounding, so a
// circle through a shared edge must not fall between the two triangles that share it. 1e-12 of
// the barycentric range is ~1e4 ulps, far below any modelling tolerance.
constexpr double kInsideSlack = 1e-12;

double segment_distance_2d(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                           const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  double t = length2 > 0.0 ? (p - a).dot(ab) / length2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (a + t * ab - p).norm();
}

double segment_distance_3d(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  double t = length2 > 0.0 ? (p - a).dot(ab) / length2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (a + t * ab - p).norm();
}

double cross_2d(const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
  return u.x() * v.y() - u.y() * v.x();
}

// Is p (in the plane of a, b, c up to rounding) inside the triangle, edges included with slack?
bool inside_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n,
                     double n2) {
  const double limit = -kInsideSlack * n2;
  if ((b - a).cross(p - a).dot(n) < limit) return false;
  if ((c - b).cross(p - b).dot(n) < limit) return false;
  if ((a - c).cross(p - c).dot(n) < limit) return false;
  return true;
}

}  // namespace

AxisFrameResult make_axis_frame(const Vec3& centre, const Vec3& axis) {
  AxisFrameResult result;
  const double length = axis.norm();
  if (!centre.allFinite() || !axis.allFinite() || !(length > 0.0)) return result;
  AxisFrame& frame = result.frame;
  frame.centre = centre;
  frame.axis = axis / length;
  // e1: the coordinate direction least aligned with the axis, made perpendicular.
  Eigen::Index smallest = 0;
  frame.axis.cwiseAbs().minCoeff(&smallest);
  Vec3 helper = Vec3::Zero();
  helper[smallest] = 1.0;
  frame.e1 = (helper - helper.dot(frame.axis) * frame.axis).normalized();
  frame.e2 = frame.axis.cross(frame.e1);
  result.valid = true;
  return result;
}

double wrap_angle(double angle_rad) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  // Differences of two angles in [-pi, pi] lie within (-2 pi, 2 pi): there angle -+ 2 pi is exact
  // (Sterbenz), so this equals std::remainder's answer below bit for bit, without the library call
  // (a quarter of the range finder's time went to remainder, atan2 and sincos).
  if (angle_rad > -two_pi && angle_rad < two_pi) {
    if (angle_rad > std::numbers::pi) return angle_rad - two_pi;
    if (angle_rad <= -std::numbers::pi) return angle_rad + two_pi;
    return angle_rad;
  }
  double wrapped = std::remainder(angle_rad, two_pi);  // [-pi, pi]
  if (wrapped <= -std::numbers::pi) wrapped += two_pi;
  return wrapped;
}

Cylindrical to_cylindrical(const Vec3& local) {
  Cylindrical out;
  out.r = std::hypot(local.x(), local.y());
  out.theta = out.r > 0.0 ? std::atan2(local.y(), local.x()) : 0.0;
  if (out.theta <= -std::numbers::pi) out.theta = std::numbers::pi;
  out.z = local.z();
  return out;
}

CylindricalBounds triangle_cylindrical_bounds(const Vec3& a, const Vec3& b, const Vec3& c) {
  CylindricalBounds bounds;
  const double ra = std::hypot(a.x(), a.y());
  const double rb = std::hypot(b.x(), b.y());
  const double rc = std::hypot(c.x(), c.y());
  bounds.r_max = std::max({ra, rb, rc});
  bounds.z_min = std::min({a.z(), b.z(), c.z()});
  bounds.z_max = std::max({a.z(), b.z(), c.z()});

  // App. A exact r_min: distance from the axis (the 2D origin) to the projected triangle.
  const Eigen::Vector2d pa(a.x(), a.y()), pb(b.x(), b.y()), pc(c.x(), c.y());
  const Eigen::Vector2d origin(0.0, 0.0);
  const double area = cross_2d(pb - pa, pc - pa);
  if (area != 0.0) {
    const double s0 = cross_2d(pb - pa, origin - pa);
    const double s1 = cross_2d(pc - pb, origin - pb);
    const double s2 = cross_2d(pa - pc, origin - pc);
    const bool inside = area > 0.0 ? (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0)
                                   : (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0);
    if (inside) {
      bounds.r_min = 0.0;
      return bounds;
    }
  }
  bounds.r_min = std::min({segment_distance_2d(origin, pa, pb), segment_distance_2d(origin, pb, pc),
                           segment_distance_2d(origin, pc, pa)});
  return bounds;
}

AngularExtent triangle_angular_extent(const Vec3& a, const Vec3& b, const Vec3& c) {
  if (!(a.head<2>().squaredNorm() > 0.0 && b.head<2>().squaredNorm() > 0.0 && c.head<2>().squaredNorm() > 0.0)) {
    return {};  // a vertex on the axis: all angles
  }
  const double theta_a = std::atan2(a.y(), a.x());
  const double db = wrap_angle(std::atan2(b.y(), b.x()) - theta_a);
  const double dc = wrap_angle(std::atan2(c.y(), c.x()) - theta_a);
  const double lo = std::min({0.0, db, dc}), hi = std::max({0.0, db, dc});
  if (hi - lo >= 0.9 * std::numbers::pi) return {};  // around the axis, or nearly: all angles
  return {theta_a + lo - kAngularExtentMarginRad, hi - lo + 2.0 * kAngularExtentMarginRad};
}

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0.0) {
    const double plane_offset = (p - a).dot(n) / n2;
    const Vec3 projected = p - plane_offset * n;
    if ((b - a).cross(projected - a).dot(n) >= 0.0 && (c - b).cross(projected - b).dot(n) >= 0.0 &&
        (a - c).cross(projected - c).dot(n) >= 0.0) {
      return std::abs(plane_offset) * std::sqrt(n2);
    }
  }
  return std::min({segment_distance_3d(p, a, b), segment_distance_3d(p, b, c),
                   segment_distance_3d(p, c, a)});
}

CrossingPlane crossing_plane(const Vec3& a, const Vec3& b, const Vec3& c) {
  CrossingPlane plane;
  plane.n = (b - a).cross(c - a);
  plane.n2 = plane.n.squaredNorm();
  plane.rho = std::hypot(plane.n.x(), plane.n.y());
  plane.phi = std::atan2(plane.n.y(), plane.n.x());
  plane.offset = plane.n.dot(a);
  return plane;
}

int circle_triangle_crossings(double r, double z, const Vec3& a, const Vec3& b, const Vec3& c,
                              std::array<double, 2>& angles_rad) {
  if (!(r > 0.0)) return 0;
  return circle_triangle_crossings(r, z, a, b, c, crossing_plane(a, b, c), angles_rad);
}

int circle_triangle_crossings(double r, double z, const Vec3& a, const Vec3& b, const Vec3& c,
                              const CrossingPlane& plane, std::array<double, 2>& angles_rad) {
  if (!(r > 0.0)) return 0;
  const Vec3& n = plane.n;
  const double n2 = plane.n2;
  const double rho = plane.rho;
  if (!(n2 > 0.0) || !(rho > 0.0)) return 0;
  // Plane n.x = n.a; on the circle: r (n_x cos t + n_y sin t) = n.a - n_z z, i.e.
  // cos(t - phi) = q with phi = atan2(n_y, n_x) (App. C Eq. 28-29 in polar form, which keeps
  // both roots exact for any plane orientation instead of dividing by one normal component).
  const double q = (plane.offset - n.z() * z) / (rho * r);
  if (!(q >= -1.0 && q <= 1.0)) return 0;
  const double half = std::acos(q);
  const std::array<double, 2> roots = {wrap_angle(plane.phi + half), wrap_angle(plane.phi - half)};
  const int num_roots = half == 0.0 ? 1 : 2;
  int count = 0;
  for (int i = 0; i < num_roots; ++i) {
    const Vec3 point(r * std::cos(roots[i]), r * std::sin(roots[i]), z);
    if (inside_triangle(point, a, b, c, n, n2)) angles_rad[count++] = roots[i];
  }
  return count;
}

double crossing_exit_sign(double crossing_theta_rad, const Vec3& normal_local) {
  return -std::sin(crossing_theta_rad) * normal_local.x() +
         std::cos(crossing_theta_rad) * normal_local.y();
}

namespace {

Vec3 crossing_point(double r, double z, double crossing_theta_rad) {
  return {r * std::cos(crossing_theta_rad), r * std::sin(crossing_theta_rad), z};
}

// T' = B x Z with B from the axis to V' (App. D Eq. 30).
Vec3 crossing_tangent(const Vec3& crossing) { return {crossing.y(), -crossing.x(), 0.0}; }

}  // namespace

CrossingSides penetrating_sides(double r, double z, double crossing_theta_rad, const Vec3& normal_local) {
  // The same arithmetic as arc_verdict's orientation of T (Eq. 31), so the two agree bit for bit.
  const double tangent_dot_normal = crossing_tangent(crossing_point(r, z, crossing_theta_rad)).dot(normal_local);
  // T = T' (T'.N > 0): T.A < 0 for vertices anticlockwise of the crossing (T'.A = r^2 sin(c - theta));
  // T = -T': clockwise of it; T'.N == 0: N.A decides, either side.
  return {tangent_dot_normal >= 0.0, tangent_dot_normal <= 0.0};
}

ArcVerdict arc_verdict(double r, double z, double vertex_theta_rad, double crossing_theta_rad,
                       const Vec3& normal_local, double touching_mm) {
  const double delta = wrap_angle(crossing_theta_rad - vertex_theta_rad);
  if (r * std::abs(delta) <= touching_mm) return ArcVerdict::kTouching;
  const Vec3 vertex(r * std::cos(vertex_theta_rad), r * std::sin(vertex_theta_rad), z);
  const Vec3 crossing = crossing_point(r, z, crossing_theta_rad);
  const Vec3 to_vertex = vertex - crossing;  // A
  const Vec3 tangent_raw = crossing_tangent(crossing);
  const double tangent_dot_normal = tangent_raw.dot(normal_local);
  if (tangent_dot_normal == 0.0) {
    // Circle tangent to the plane: App. D first extreme case.
    return normal_local.dot(to_vertex) < 0.0 ? ArcVerdict::kPenetrating : ArcVerdict::kOutside;
  }
  const Vec3 tangent = tangent_dot_normal < 0.0 ? Vec3(-tangent_raw) : tangent_raw;  // Eq. 31
  const double tangent_dot_arc = tangent.dot(to_vertex);
  // T.A == 0: arc of 0 (handled above as touching) or pi: keep the default, non-penetrating.
  return tangent_dot_arc < 0.0 ? ArcVerdict::kPenetrating : ArcVerdict::kOutside;  // Eq. 32
}

}  // namespace hipfai::contact
