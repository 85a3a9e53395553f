#include "contact/range_finder.h"

#include <cmath>
#include <numbers>

namespace hipfai::contact {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

struct DirectionBest {
  double angle_rad = kTwoPi;
  LimitingContact contact;
  void offer(double angle, const LimitingContact& candidate) {
    if (angle < angle_rad) {
      angle_rad = angle;
      contact = candidate;
    }
  }
};

// Smallest anticlockwise ("forward") and clockwise ("backward") motion of the cached vertices
// before they meet a crossing; one pass over the stored crossings.
void scan(const CylindricalPoseCache& cache, ContactKind kind, int num_threads,
          DirectionBest& forward, DirectionBest& backward) {
  const auto& tracked = cache.tracked();
  const int threads = detail::resolve_threads(num_threads);
  std::vector<DirectionBest> chunk_forward(static_cast<std::size_t>(threads));
  std::vector<DirectionBest> chunk_backward(static_cast<std::size_t>(threads));
  const double touching_mm = cache.touching_mm();
  detail::parallel_chunks(tracked.size(), threads, [&](std::size_t begin, std::size_t end, int c) {
    DirectionBest& fwd = chunk_forward[static_cast<std::size_t>(c)];
    DirectionBest& bwd = chunk_backward[static_cast<std::size_t>(c)];
    for (std::size_t i = begin; i < end; ++i) {
      const auto& vertex = tracked[i];
      for (std::size_t k = vertex.first; k < vertex.last; ++k) {
        const double theta = cache.crossing_theta_rad(k);
        const std::int32_t triangle = cache.crossing_triangle(k);
        const LimitingContact contact{kind, vertex.vertex, triangle};
        const double delta = wrap_angle(theta - vertex.theta0_rad);
        if (vertex.r * std::abs(delta) <= touching_mm) {
          // Resting contact: limits only the direction that enters the other solid.
          const double exit = crossing_exit_sign(theta, cache.local_normal(triangle));
          if (exit < 0.0) fwd.offer(0.0, contact);
          if (exit > 0.0) bwd.offer(0.0, contact);
          continue;
        }
        fwd.offer(delta > 0.0 ? delta : delta + kTwoPi, contact);
        bwd.offer(delta < 0.0 ? -delta : kTwoPi - delta, contact);
      }
    }
  });
  for (int c = 0; c < threads; ++c) {
    forward.offer(chunk_forward[static_cast<std::size_t>(c)].angle_rad,
                  chunk_forward[static_cast<std::size_t>(c)].contact);
    backward.offer(chunk_backward[static_cast<std::size_t>(c)].angle_rad,
                   chunk_backward[static_cast<std::size_t>(c)].contact);
  }
}

RangeOfMotion invalid_range(std::string message) {
  RangeOfMotion range;
  range.status = QueryStatus::kInvalidInput;
  range.message = std::move(message);
  return range;
}

}  // namespace

RangeOfMotion range_of_motion(const CylindricalPoseCache& mobile_on_fixed,
                              const CylindricalPoseCache* fixed_on_mobile, int num_threads) {
  if (mobile_on_fixed.status() == QueryStatus::kInvalidInput) {
    return invalid_range("range of motion: invalid pre-processed mobile mesh");
  }
  if (fixed_on_mobile != nullptr && fixed_on_mobile->status() == QueryStatus::kInvalidInput) {
    return invalid_range("range of motion: invalid pre-processed fixed mesh");
  }
  DirectionBest anticlockwise, clockwise;
  scan(mobile_on_fixed, ContactKind::kMobileVertexOnFixedTriangle, num_threads, anticlockwise,
       clockwise);
  if (fixed_on_mobile != nullptr) {
    // The mobile mesh turning anticlockwise moves the fixed vertices clockwise relative to it.
    scan(*fixed_on_mobile, ContactKind::kFixedVertexOnMobileTriangle, num_threads, clockwise,
         anticlockwise);
  }
  RangeOfMotion range;
  range.anticlockwise_deg = anticlockwise.angle_rad * kDegPerRad;
  range.clockwise_deg = clockwise.angle_rad * kDegPerRad;
  range.anticlockwise_limit = anticlockwise.contact;
  range.clockwise_limit = clockwise.contact;
  return range;
}

RangeOfMotion range_of_motion(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                              const Vec3& centre, const Vec3& axis,
                              const RangeOfMotionOptions& options) {
  const CylindricalTable fixed_table =
      CylindricalTable::build(fixed, centre, axis, options.table, &mobile);
  if (fixed_table.status() == QueryStatus::kInvalidInput) return invalid_range(fixed_table.message());
  const CylindricalPoseCache mobile_on_fixed(fixed_table, mobile, options.query);
  if (!options.include_fixed_vertices) {
    return range_of_motion(mobile_on_fixed, nullptr, options.query.num_threads);
  }
  const CylindricalTable mobile_table =
      CylindricalTable::build(mobile, centre, axis, options.table, &fixed);
  if (mobile_table.status() == QueryStatus::kInvalidInput) {
    return invalid_range(mobile_table.message());
  }
  const CylindricalPoseCache fixed_on_mobile(mobile_table, fixed, options.query);
  return range_of_motion(mobile_on_fixed, &fixed_on_mobile, options.query.num_threads);
}

std::vector<AxisRangeOfMotion> range_of_motion_fan(const geometry::TriMesh& fixed,
                                                   const geometry::TriMesh& mobile,
                                                   const Vec3& centre, const Vec3& plane_normal,
                                                   int steps,
                                                   const RangeOfMotionOptions& options) {
  std::vector<AxisRangeOfMotion> fan;
  const AxisFrameResult plane = make_axis_frame(centre, plane_normal);
  if (!plane.valid || steps <= 0) {
    AxisRangeOfMotion bad;
    bad.range = invalid_range("fan: the plane normal must be non-zero and steps > 0");
    fan.push_back(bad);
    return fan;
  }
  for (int i = 0; i < steps; ++i) {
    AxisRangeOfMotion entry;
    entry.angle_deg = 180.0 * i / steps;
    const double angle = entry.angle_deg / kDegPerRad;
    entry.axis = std::cos(angle) * plane.frame.e1 + std::sin(angle) * plane.frame.e2;
    entry.range = range_of_motion(fixed, mobile, centre, entry.axis, options);
    fan.push_back(entry);
  }
  return fan;
}

std::vector<AxisRangeOfMotion> range_of_motion_sphere(const geometry::TriMesh& fixed,
                                                      const geometry::TriMesh& mobile,
                                                      const Vec3& centre, const Vec3& pole,
                                                      int polar_steps, int azimuth_steps,
                                                      const RangeOfMotionOptions& options) {
  std::vector<AxisRangeOfMotion> grid;
  const AxisFrameResult frame = make_axis_frame(centre, pole);
  if (!frame.valid || polar_steps <= 0 || azimuth_steps <= 0) {
    AxisRangeOfMotion bad;
    bad.range = invalid_range("sphere: the pole must be non-zero and steps > 0");
    grid.push_back(bad);
    return grid;
  }
  for (int i = 0; i <= polar_steps; ++i) {
    const double polar_deg = 90.0 * i / polar_steps;
    const int azimuths = i == 0 ? 1 : azimuth_steps;
    for (int j = 0; j < azimuths; ++j) {
      AxisRangeOfMotion entry;
      entry.angle_deg = polar_deg;
      entry.azimuth_deg = 360.0 * j / azimuth_steps;
      const double polar = polar_deg / kDegPerRad, azimuth = entry.azimuth_deg / kDegPerRad;
      entry.axis = std::cos(polar) * frame.frame.axis +
                   std::sin(polar) * (std::cos(azimuth) * frame.frame.e1 +
                                      std::sin(azimuth) * frame.frame.e2);
      entry.range = range_of_motion(fixed, mobile, centre, entry.axis, options);
      grid.push_back(entry);
    }
  }
  return grid;
}

}  // namespace hipfai::contact
