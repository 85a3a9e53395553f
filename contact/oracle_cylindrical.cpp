#include "contact/oracle_cylindrical.h"
#include "core/numbers.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace hipfai::contact {
namespace {

using hipfai::kTwoPi;
using hipfai::kDegPerRad;

Vec3 local_unit_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double length = n.norm();
  return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
}

// Best contact of one direction: smallest angle, first one found on ties.
struct Best {
  double angle_rad = kTwoPi;
  LimitingContact contact;
  void offer(double angle, ContactKind kind, std::int32_t vertex, std::int32_t triangle) {
    if (angle < angle_rad) {
      angle_rad = angle;
      contact = {kind, vertex, triangle};
    }
  }
};

// Vertices of `moving` rotating (relative motion sign `sense`: +1 anticlockwise) against the
// triangles of `still`; offers to `forward` the contacts met when the vertex moves
// anticlockwise, to `backward` clockwise.
void all_pairs(const geometry::TriMesh& still, const geometry::TriMesh& moving,
               const AxisFrame& frame, double touching_mm, ContactKind kind, Best& forward,
               Best& backward) {
  std::vector<Vec3> local(still.vertices.size());
  for (std::size_t i = 0; i < still.vertices.size(); ++i) local[i] = frame.to_local(still.vertices[i]);
  std::array<double, 2> angles{};
  for (std::size_t v = 0; v < moving.vertices.size(); ++v) {
    const Cylindrical cyl = to_cylindrical(frame.to_local(moving.vertices[v]));
    for (std::size_t t = 0; t < still.triangles.size(); ++t) {
      const auto& tri = still.triangles[t];
      const Vec3& a = local[static_cast<std::size_t>(tri[0])];
      const Vec3& b = local[static_cast<std::size_t>(tri[1])];
      const Vec3& c = local[static_cast<std::size_t>(tri[2])];
      const int n = circle_triangle_crossings(cyl.r, cyl.z, a, b, c, angles);
      for (int i = 0; i < n; ++i) {
        const double theta = angles[static_cast<std::size_t>(i)];
        const double delta = wrap_angle(theta - cyl.theta);
        const auto vi = static_cast<std::int32_t>(v);
        const auto ti = static_cast<std::int32_t>(t);
        if (cyl.r * std::abs(delta) <= touching_mm) {
          const double exit = crossing_exit_sign(theta, local_unit_normal(a, b, c));
          if (exit < 0.0) forward.offer(0.0, kind, vi, ti);
          if (exit > 0.0) backward.offer(0.0, kind, vi, ti);
          continue;
        }
        forward.offer(delta > 0.0 ? delta : delta + kTwoPi, kind, vi, ti);
        backward.offer(delta < 0.0 ? -delta : kTwoPi - delta, kind, vi, ti);
      }
    }
  }
}

}  // namespace

PenetrationResult oracle_cylindrical(const geometry::TriMesh& fixed,
                                     const geometry::TriMesh& posed_mobile, const Vec3& centre,
                                     const Vec3& axis, double touching_mm) {
  PenetrationResult result;
  const AxisFrameResult frame = make_axis_frame(centre, axis);
  if (!frame.valid) {
    result.status = QueryStatus::kInvalidInput;
    result.message = "rotation axis must be finite and non-zero, centre finite";
    return result;
  }
  // Fixed geometry in the axis frame, computed once (the same arithmetic as the table's).
  std::vector<Vec3> local(fixed.vertices.size());
  for (std::size_t i = 0; i < fixed.vertices.size(); ++i) local[i] = frame.frame.to_local(fixed.vertices[i]);
  std::array<double, 2> angles{};
  for (std::size_t v = 0; v < posed_mobile.vertices.size(); ++v) {
    const Cylindrical cyl = to_cylindrical(frame.frame.to_local(posed_mobile.vertices[v]));
    NearestCrossing nearest;
    Vec3 nearest_normal = Vec3::Zero();
    for (std::size_t t = 0; t < fixed.triangles.size(); ++t) {
      const auto& tri = fixed.triangles[t];
      const Vec3& a = local[static_cast<std::size_t>(tri[0])];
      const Vec3& b = local[static_cast<std::size_t>(tri[1])];
      const Vec3& c = local[static_cast<std::size_t>(tri[2])];
      const int n = circle_triangle_crossings(cyl.r, cyl.z, a, b, c, angles);
      for (int i = 0; i < n; ++i) {
        const std::int32_t before = nearest.triangle;
        const double before_delta = nearest.abs_delta_rad;
        nearest.offer(cyl.theta, angles[static_cast<std::size_t>(i)], static_cast<std::int32_t>(t));
        if (nearest.triangle != before || nearest.abs_delta_rad != before_delta) {
          nearest_normal = local_unit_normal(a, b, c);
        }
      }
    }
    if (!nearest.found()) continue;
    if (arc_verdict(cyl.r, cyl.z, cyl.theta, nearest.crossing_theta_rad, nearest_normal,
                    touching_mm) != ArcVerdict::kPenetrating) {
      continue;
    }
    result.pairs.push_back({static_cast<std::int32_t>(v), nearest.triangle,
                            cyl.r * nearest.abs_delta_rad, nearest.abs_delta_rad * kDegPerRad});
  }
  return result;
}

RangeOfMotion oracle_range_of_motion(const geometry::TriMesh& fixed,
                                     const geometry::TriMesh& mobile, const Vec3& centre,
                                     const Vec3& axis, bool include_fixed_vertices,
                                     double touching_mm) {
  RangeOfMotion range;
  const AxisFrameResult frame = make_axis_frame(centre, axis);
  if (!frame.valid) {
    range.status = QueryStatus::kInvalidInput;
    range.message = "rotation axis must be finite and non-zero, centre finite";
    return range;
  }
  Best anticlockwise, clockwise;
  all_pairs(fixed, mobile, frame.frame, touching_mm, ContactKind::kMobileVertexOnFixedTriangle,
            anticlockwise, clockwise);
  if (include_fixed_vertices) {
    // A fixed vertex moves clockwise relative to the mobile mesh when the mobile turns
    // anticlockwise: its backward contacts limit the anticlockwise range.
    all_pairs(mobile, fixed, frame.frame, touching_mm, ContactKind::kFixedVertexOnMobileTriangle,
              clockwise, anticlockwise);
  }
  range.anticlockwise_deg = anticlockwise.angle_rad * kDegPerRad;
  range.clockwise_deg = clockwise.angle_rad * kDegPerRad;
  range.anticlockwise_limit = anticlockwise.contact;
  range.clockwise_limit = clockwise.contact;
  return range;
}

}  // namespace hipfai::contact
