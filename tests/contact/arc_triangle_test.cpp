// Tests of the exact circle/triangle primitives against closed forms and brute force.
#include "contact/arc_triangle.h"
#include "core/numbers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

namespace hipfai::contact {
namespace {

using hipfai::kPi;

TEST(ArcTriangle, WrapAngleMapsToHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(wrap_angle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(wrap_angle(kPi), kPi);
  EXPECT_DOUBLE_EQ(wrap_angle(-kPi), kPi);  // -pi is excluded
  EXPECT_NEAR(wrap_angle(3.0 * kPi / 2.0), -kPi / 2.0, 1e-15);
  EXPECT_NEAR(wrap_angle(-5.0 * kPi / 2.0), -kPi / 2.0, 1e-14);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> angle(-50.0, 50.0);
  for (int i = 0; i < 1000; ++i) {
    const double a = angle(rng);
    const double w = wrap_angle(a);
    EXPECT_GT(w, -kPi);
    EXPECT_LE(w, kPi);
    // Same direction: differ by a multiple of 2 pi (1e-12: rounding of |a| <= 50).
    EXPECT_NEAR(std::cos(w), std::cos(a), 1e-12);
    EXPECT_NEAR(std::sin(w), std::sin(a), 1e-12);
  }
}

// The fast path of wrap_angle (|angle| < 2 pi, where angle -+ 2 pi is exact) against the library's
// exact remainder, bit for bit, signs of zero included, on random angles and on the seams.
TEST(ArcTriangle, WrapAngleEqualsTheExactRemainderBitForBit) {
  const auto reference = [](double angle) {
    double wrapped = std::remainder(angle, 2.0 * std::numbers::pi);
    if (wrapped <= -std::numbers::pi) wrapped += 2.0 * std::numbers::pi;
    return wrapped;
  };
  const auto same_bits = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-7.0, 7.0);
  std::vector<double> angles;
  for (int i = 0; i < 200000; ++i) angles.push_back(u(rng));
  const double pi = std::numbers::pi, two_pi = 2.0 * std::numbers::pi;
  for (const double seam : {0.0, pi, -pi, two_pi, -two_pi, 3 * pi, -3 * pi}) {
    double below = seam, above = seam;
    for (int k = 0; k < 4; ++k) {
      angles.push_back(below);
      angles.push_back(above);
      below = std::nextafter(below, -10.0);
      above = std::nextafter(above, 10.0);
    }
  }
  angles.push_back(-0.0);
  for (const double angle : angles) {
    ASSERT_TRUE(same_bits(wrap_angle(angle), reference(angle))) << std::hexfloat << angle;
  }
}

TEST(ArcTriangle, AxisFrameIsRightHandedOrthonormal) {
  const Vec3 centre(1.0, 2.0, 3.0);
  for (const Vec3& axis : {Vec3(0, 0, 2), Vec3(1, 1, 0), Vec3(-3, 0.5, 7), Vec3(1e-8, 0, 0)}) {
    const AxisFrameResult result = make_axis_frame(centre, axis);
    ASSERT_TRUE(result.valid);
    const AxisFrame& f = result.frame;
    EXPECT_NEAR(f.axis.dot(axis.normalized()), 1.0, 1e-15);
    EXPECT_NEAR(f.e1.norm(), 1.0, 1e-15);
    EXPECT_NEAR(f.e1.dot(f.axis), 0.0, 1e-15);
    EXPECT_NEAR((f.e1.cross(f.e2) - f.axis).norm(), 0.0, 1e-15);
    // A right-hand rotation about the axis increases theta.
    const Vec3 p = centre + f.e1 * 3.0;
    const Vec3 rotated = centre + Eigen::AngleAxisd(0.3, f.axis) * (p - centre);
    EXPECT_NEAR(to_cylindrical(f.to_local(rotated)).theta, 0.3, 1e-14);
  }
  EXPECT_FALSE(make_axis_frame(Vec3::Zero(), Vec3::Zero()).valid);
  EXPECT_FALSE(make_axis_frame(Vec3(NAN, 0, 0), Vec3::UnitZ()).valid);
}

TEST(ArcTriangle, CrossingsOfPlaneFaceMatchClosedForm) {
  // Triangle in the plane x = 5 covering |y| <= 10, |z| <= 10: the circle of radius 6 at z = 0
  // meets it where cos t = 5/6.
  const Vec3 a(5, -10, -10), b(5, 10, -10), c(5, 0, 20);
  std::array<double, 2> angles{};
  const int n = circle_triangle_crossings(6.0, 0.0, a, b, c, angles);
  ASSERT_EQ(n, 2);
  std::sort(angles.begin(), angles.end());
  EXPECT_NEAR(angles[0], -std::acos(5.0 / 6.0), 1e-15);
  EXPECT_NEAR(angles[1], std::acos(5.0 / 6.0), 1e-15);
  // Radius 4 never reaches the plane.
  EXPECT_EQ(circle_triangle_crossings(4.0, 0.0, a, b, c, angles), 0);
  // Radius exactly 5: tangent, both roots at t = 0 (acos(-1) = pi exactly).
  const int tangent = circle_triangle_crossings(5.0, 0.0, a, b, c, angles);
  ASSERT_GE(tangent, 1);
  for (int i = 0; i < tangent; ++i) EXPECT_EQ(angles[static_cast<std::size_t>(i)], 0.0);
}

TEST(ArcTriangle, DegenerateInputsGiveNoCrossings) {
  std::array<double, 2> angles{};
  const Vec3 a(5, -1, -1), b(5, 1, -1), c(5, 0, 1);
  EXPECT_EQ(circle_triangle_crossings(0.0, 0.0, a, b, c, angles), 0);            // on the axis
  EXPECT_EQ(circle_triangle_crossings(6.0, 0.0, a, a, c, angles), 0);            // zero area
  EXPECT_EQ(circle_triangle_crossings(6.0, 0.0, a, (a + c) / 2, c, angles), 0);  // collinear
  // Perpendicular to the axis, circle in its plane.
  EXPECT_EQ(circle_triangle_crossings(2.0, 0.0, Vec3(-5, -5, 0), Vec3(5, -5, 0), Vec3(0, 5, 0), angles), 0);
  EXPECT_EQ(circle_triangle_crossings(NAN, 0.0, a, b, c, angles), 0);
}

// Brute force: sign changes of the plane function along the circle, refined by bisection, kept
// when clearly inside the triangle.
std::vector<double> brute_force_crossings(double r, double z, const Vec3& a, const Vec3& b,
                                          const Vec3& c, bool& ambiguous) {
  const Vec3 n = (b - a).cross(c - a);
  const auto point = [&](double t) { return Vec3(r * std::cos(t), r * std::sin(t), z); };
  const auto f = [&](double t) { return n.dot(point(t) - a); };
  std::vector<double> roots;
  ambiguous = false;
  constexpr int kSamples = 20000;
  for (int i = 0; i < kSamples; ++i) {
    double lo = -kPi + 2 * kPi * i / kSamples, hi = -kPi + 2 * kPi * (i + 1) / kSamples;
    double flo = f(lo), fhi = f(hi);
    if (flo == 0.0) { roots.push_back(lo); continue; }
    if ((flo < 0) == (fhi < 0)) continue;
    for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
      const double mid = 0.5 * (lo + hi);
      if ((f(mid) < 0) == (flo < 0)) lo = mid; else hi = mid;
    }
    const double t = 0.5 * (lo + hi);
    const Vec3 p = point(t);
    const double n2 = n.squaredNorm();
    const double w0 = (b - a).cross(p - a).dot(n) / n2, w1 = (c - b).cross(p - b).dot(n) / n2,
                 w2 = (a - c).cross(p - c).dot(n) / n2;
    const double smallest = std::min({w0, w1, w2});
    if (std::abs(smallest) < 1e-6) ambiguous = true;  // too close to an edge to judge
    if (smallest > 0) roots.push_back(t);
  }
  return roots;
}

TEST(ArcTriangle, CrossingsMatchBruteForceOnRandomTriangles) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-10.0, 10.0), radius(0.5, 12.0);
  int compared = 0, with_crossings = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Vec3 a(coord(rng), coord(rng), coord(rng) * 0.3);
    const Vec3 b(coord(rng), coord(rng), coord(rng) * 0.3);
    const Vec3 c(coord(rng), coord(rng), coord(rng) * 0.3);
    const double r = radius(rng), z = coord(rng) * 0.2;
    bool ambiguous = false;
    const std::vector<double> expected = brute_force_crossings(r, z, a, b, c, ambiguous);
    if (ambiguous) continue;
    std::array<double, 2> angles{};
    const int n = circle_triangle_crossings(r, z, a, b, c, angles);
    ++compared;
    // Near-tangent circles give two roots closer than the sampling step; skip those.
    if (n == 2 && std::abs(wrap_angle(angles[0] - angles[1])) < 1e-3) continue;
    ASSERT_EQ(n, static_cast<int>(expected.size())) << "trial " << trial;
    with_crossings += n > 0;
    for (int i = 0; i < n; ++i) {
      const double best = *std::min_element(expected.begin(), expected.end(), [&](double x, double y) {
        return std::abs(wrap_angle(x - angles[static_cast<std::size_t>(i)])) <
               std::abs(wrap_angle(y - angles[static_cast<std::size_t>(i)]));
      });
      // Bisection to 1e-15 rad; the closed form is exact to rounding (1e-9 is generous for
      // near-grazing roots, where the root is ill-conditioned).
      EXPECT_NEAR(wrap_angle(best - angles[static_cast<std::size_t>(i)]), 0.0, 1e-9);
    }
  }
  EXPECT_GT(compared, 300);
  EXPECT_GT(with_crossings, 50);  // the test exercises real crossings
}

TEST(ArcTriangle, ExactRadialBoundBeatsVertexMinimum) {
  // Thesis Fig. 75: an edge passing closer to the axis than any vertex.
  const Vec3 a(10, -10, 0), b(10, 10, 0), c(20, 0, 1);
  const CylindricalBounds bounds = triangle_cylindrical_bounds(a, b, c);
  EXPECT_DOUBLE_EQ(bounds.r_min, 10.0);  // closest point (10, 0, 0) on edge ab
  EXPECT_EQ(bounds.r_max, 20.0);
  EXPECT_GT(std::hypot(10.0, 10.0), bounds.r_min + 4.0);  // the vertex minimum would be 14.1
  EXPECT_EQ(bounds.z_min, 0.0);
  EXPECT_EQ(bounds.z_max, 1.0);
  // A triangle around the axis has r_min = 0.
  EXPECT_EQ(triangle_cylindrical_bounds(Vec3(-1, -1, 0), Vec3(2, -1, 1), Vec3(0, 2, 2)).r_min, 0.0);
  // Random triangles: r_min is a lower bound of densely sampled points and close to their minimum.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-10.0, 10.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 p(coord(rng), coord(rng), coord(rng)), q(coord(rng), coord(rng), coord(rng)),
        s(coord(rng), coord(rng), coord(rng));
    const CylindricalBounds exact = triangle_cylindrical_bounds(p, q, s);
    double sampled = 1e300;
    constexpr int kSteps = 200;
    for (int i = 0; i <= kSteps; ++i) {
      for (int j = 0; i + j <= kSteps; ++j) {
        const Vec3 x = p + (q - p) * i / kSteps + (s - p) * j / kSteps;
        sampled = std::min(sampled, std::hypot(x.x(), x.y()));
      }
    }
    EXPECT_LE(exact.r_min, sampled + 1e-12);
    // Sampling step <= edge/200 <= 35/200 mm: the sampled minimum is within that of the truth.
    EXPECT_GE(exact.r_min, sampled - 0.2);
    const double d = point_triangle_distance(Vec3::Zero(), p, q, s);
    double sampled_3d = 1e300;
    for (int i = 0; i <= kSteps; ++i) {
      for (int j = 0; i + j <= kSteps; ++j) {
        sampled_3d = std::min(sampled_3d, (p + (q - p) * i / kSteps + (s - p) * j / kSteps).norm());
      }
    }
    EXPECT_LE(d, sampled_3d + 1e-12);
    EXPECT_GE(d, sampled_3d - 0.2);
  }
}

TEST(ArcTriangle, AppendixDVerdictOnAFace) {
  // Face x = 5 of a solid lying at x > 5: outward normal -x. Circle of radius 6: the vertex at
  // theta = 0 is inside (x = 6), the vertex at theta = pi/2 outside.
  const Vec3 normal(-1, 0, 0);
  const double crossing = std::acos(5.0 / 6.0);
  EXPECT_EQ(arc_verdict(6.0, 0.0, 0.0, crossing, normal, 1e-9), ArcVerdict::kPenetrating);
  EXPECT_EQ(arc_verdict(6.0, 0.0, 0.0, -crossing, normal, 1e-9), ArcVerdict::kPenetrating);
  EXPECT_EQ(arc_verdict(6.0, 0.0, kPi / 2, crossing, normal, 1e-9), ArcVerdict::kOutside);
  EXPECT_EQ(arc_verdict(6.0, 0.0, crossing, crossing, normal, 1e-9), ArcVerdict::kTouching);
  // Anticlockwise through the crossing at +acos(5/6) leaves the solid.
  EXPECT_GT(crossing_exit_sign(crossing, normal), 0.0);
  EXPECT_LT(crossing_exit_sign(-crossing, normal), 0.0);
  // Tangent (T.N = 0): circle of radius 5 touching the face at (5, 0, 0).
  EXPECT_EQ(arc_verdict(5.0, 0.0, kPi / 2, 0.0, normal, 1e-9), ArcVerdict::kOutside);
  EXPECT_EQ(arc_verdict(5.0, 0.0, kPi / 2, 0.0, -normal, 1e-9), ArcVerdict::kPenetrating);
  // Arc of pi: T.A = 0 -> default, not penetrating.
  EXPECT_EQ(arc_verdict(6.0, 0.0, kPi, 0.0, Vec3(0, 1, 0), 1e-9), ArcVerdict::kOutside);
}

TEST(ArcTriangle, NearestCrossingIsOrderIndependent) {
  // Exact ties (0.25 is exact in binary): smallest |delta|, then smallest triangle, then delta > 0.
  const std::vector<std::pair<double, std::int32_t>> offers = {
      {0.5, 7}, {-0.25, 9}, {-0.25, 4}, {0.25, 4}, {1.0, 1}, {0.25, 9}};
  NearestCrossing forward, backward;
  for (const auto& [theta, t] : offers) forward.offer(0.0, theta, t);
  for (auto it = offers.rbegin(); it != offers.rend(); ++it) backward.offer(0.0, it->first, it->second);
  EXPECT_EQ(forward.triangle, 4);
  EXPECT_EQ(forward.delta_rad, 0.25);
  EXPECT_EQ(backward.triangle, 4);
  EXPECT_EQ(backward.delta_rad, 0.25);
}

}  // namespace
}  // namespace hipfai::contact
