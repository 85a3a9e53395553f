// Sphere fits (geometry/sphere_fit.h): exact on exact spheres, within the noise on noisy ones,
// and a status, not a number, on points that span no sphere.
#include "geometry/sphere_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace hipfai::geometry {
namespace {

// Points on a spherical cap: polar angle up to cap_deg from `pole`, random directions.
std::vector<Vec3> cap_points(const Vec3& centre, double radius, const Vec3& pole, double cap_deg, int count,
                             std::mt19937& rng, double noise_mm = 0.0) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, noise_mm > 0.0 ? noise_mm : 1.0);
  const Vec3 z = pole.normalized();
  const Vec3 x = z.unitOrthogonal();
  const Vec3 y = z.cross(x);
  const double cos_cap = std::cos(cap_deg * std::numbers::pi / 180.0);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i) {
    const double c = 1.0 - uniform(rng) * (1.0 - cos_cap);  // uniform on the cap's area
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double phi = 2.0 * std::numbers::pi * uniform(rng);
    const Vec3 u = c * z + s * (std::cos(phi) * x + std::sin(phi) * y);
    const double r = radius + (noise_mm > 0.0 ? normal(rng) : 0.0);
    points.push_back(centre + r * u);
  }
  return points;
}

// Points exactly on a sphere: the residual is zero, so centre and radius are exact to round-off
// of coordinates ~ 500 mm (1e-13 relative): 1e-9 mm leaves four orders of margin.
TEST(SphereFit, ExactOnExactSphereFarFromOrigin) {
  std::mt19937 rng(1);
  const Vec3 centre(143.8, 243.46, -432.58);  // CT-frame magnitudes
  for (const double cap : {30.0, 90.0, 180.0}) {
    const auto points = cap_points(centre, 23.0, Vec3(1, 2, 3), cap, 500, rng);
    const SphereFit fit = fit_sphere(points);
    ASSERT_TRUE(fit.ok()) << fit.message;
    EXPECT_LT((fit.center_mm - centre).norm(), 1e-9) << "cap " << cap;
    EXPECT_NEAR(fit.radius_mm, 23.0, 1e-9);
    EXPECT_LT(fit.rms_mm, 1e-9);
    EXPECT_LT(fit.max_abs_mm, 1e-9);
  }
}

// Gaussian radial noise sigma on N points of a hemisphere: the centre's standard error is of
// order sigma * sqrt(3 / N) per axis (about 0.03 mm here); 0.15 mm is five of them. The RMS
// residual estimates sigma.
TEST(SphereFit, WithinNoiseOnNoisySphere) {
  std::mt19937 rng(2);
  const Vec3 centre(10, -20, 30);
  for (const double sigma : {0.5, 1.0, 1.5}) {
    const auto points = cap_points(centre, 25.0, Vec3(0, 0, 1), 90.0, 2000, rng, sigma);
    const SphereFit fit = fit_sphere(points);
    ASSERT_TRUE(fit.ok());
    EXPECT_LT((fit.center_mm - centre).norm(), 0.15 * sigma / 0.5) << "sigma " << sigma;
    EXPECT_NEAR(fit.radius_mm, 25.0, 0.1 * sigma / 0.5);
    EXPECT_NEAR(fit.rms_mm, sigma, 0.1 * sigma);
  }
}

// On a shallow noisy cap the algebraic fit is biased towards a smaller sphere; the geometric fit
// is not (the reason the estimators use it). Same points, two fits.
TEST(SphereFit, GeometricBeatsAlgebraicOnShallowNoisyCap) {
  std::mt19937 rng(3);
  const Vec3 centre(0, 0, 0);
  const auto points = cap_points(centre, 25.0, Vec3(0, 0, 1), 40.0, 4000, rng, 1.5);
  SphereFitOptions algebraic;
  algebraic.geometric = false;
  const SphereFit a = fit_sphere(points, algebraic);
  const SphereFit g = fit_sphere(points);
  EXPECT_LT(g.rms_mm, a.rms_mm + 1e-12);  // the geometric fit minimises exactly this
  EXPECT_LT((g.center_mm - centre).norm(), (a.center_mm - centre).norm());
}

TEST(SphereFit, FlatAndTooFewPointsAreStatuses) {
  std::vector<Vec3> plane;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) plane.emplace_back(i, j, 5.0);
  EXPECT_EQ(fit_sphere(plane).status, FitStatus::kFlat);
  std::vector<Vec3> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(i, 2 * i, 3 * i);
  EXPECT_EQ(fit_sphere(line).status, FitStatus::kFlat);
  EXPECT_EQ(fit_sphere({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}).status, FitStatus::kTooFewPoints);
  // A plane with 1e-4 mm of noise is still no sphere: the fitted radius would dwarf its extent.
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 1e-4);
  for (Vec3& p : plane) p.z() += noise(rng);
  EXPECT_EQ(fit_sphere(plane).status, FitStatus::kFlat);
}

TEST(ConcentricSphereFit, ExactOnTwoExactConcentricCaps) {
  std::mt19937 rng(5);
  const Vec3 centre(143.8, 243.46, -432.58);
  const auto head = cap_points(centre, 23.0, Vec3(1, 0, 0), 100.0, 800, rng);
  const auto socket = cap_points(centre, 27.0, Vec3(-1, 0.2, 0.3), 70.0, 600, rng);
  const ConcentricSphereFit fit = fit_concentric_spheres(head, socket);
  ASSERT_TRUE(fit.ok()) << fit.message;
  EXPECT_LT((fit.center_mm - centre).norm(), 1e-9);
  EXPECT_NEAR(fit.radius_a_mm, 23.0, 1e-9);
  EXPECT_NEAR(fit.radius_b_mm, 27.0, 1e-9);
  EXPECT_LT(fit.max_abs_mm, 1e-9);
}

// Two caps whose centres differ by d: the common centre lies between them, weighted by the
// sets' leverage, and the residual shows the misfit.
TEST(ConcentricSphereFit, NonConcentricCapsGiveACompromiseAndAResidual) {
  std::mt19937 rng(6);
  const auto head = cap_points(Vec3(0, 0, 0), 23.0, Vec3(0, 0, 1), 90.0, 1000, rng);
  const auto socket = cap_points(Vec3(0, 0, 1.0), 27.0, Vec3(0, 0, 1), 90.0, 1000, rng);
  const ConcentricSphereFit fit = fit_concentric_spheres(head, socket);
  ASSERT_TRUE(fit.ok());
  EXPECT_GT(fit.center_mm.z(), 0.05);
  EXPECT_LT(fit.center_mm.z(), 0.95);
  EXPECT_GT(fit.rms_mm, 0.05);
}

}  // namespace
}  // namespace hipfai::geometry
