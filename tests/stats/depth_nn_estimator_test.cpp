#include "stats/depth_nn_estimator.h"

#include "core/error.h"
#include "stats/knn_regression.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hipfai::stats {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Separable synthetic hips: value(i, j) = level_i x profile(j) x factor(c, r), factor = 1 + c + r
// in contact and 1 without. Two clusters on one score: hips 0-4 at score 0 with level 2, hips 5-9
// at score 10 with level 3. Hips 0-3 and 5-8 impinge identically from step 3 of 6: depth
// (c, r) = (k, k / 2) at step 2 + k, k = 1..3, so every depth the target meets is held by 8
// training pairs. Hips 4 and 9 never impinge.
struct Separable {
  static constexpr int kHips = 10, kSteps = 6;
  Eigen::MatrixXd scores{kHips, 1}, values{kHips, kSteps};
  PenetrationDepths depths{Eigen::MatrixXd::Zero(kHips, kSteps), Eigen::MatrixXd::Zero(kHips, kSteps)};
  static double profile(int j) { return 1.0 + 0.1 * j; }
  static double factor(double c, double r) { return c > 0.0 || r > 0.0 ? 1.0 + c + r : 1.0; }
  Separable() {
    for (int i = 0; i < kHips; ++i) {
      scores(i, 0) = i < 5 ? 0.0 : 10.0;
      const double level = i < 5 ? 2.0 : 3.0;
      const bool impinges = i % 5 != 4;
      for (int j = 0; j < kSteps; ++j) {
        if (impinges && j >= 3) {
          depths.curvilinear_mm(i, j) = j - 2;
          depths.radial_mm(i, j) = (j - 2) / 2.0;
        }
        values(i, j) = level * profile(j) * factor(depths.curvilinear_mm(i, j), depths.radial_mm(i, j));
      }
    }
  }
};

PenetrationDepths target_depths(const std::vector<double>& c, const std::vector<double>& r) {
  PenetrationDepths d{Eigen::MatrixXd(1, static_cast<Eigen::Index>(c.size())),
                      Eigen::MatrixXd(1, static_cast<Eigen::Index>(r.size()))};
  for (std::size_t j = 0; j < c.size(); ++j) {
    d.curvilinear_mm(0, static_cast<Eigen::Index>(j)) = c[j];
    d.radial_mm(0, static_cast<Eigen::Index>(j)) = r[j];
  }
  return d;
}

TEST(DepthNnEstimator, ExactOnSeparableDataInAndOutOfContact) {
  const Separable data;
  Eigen::VectorXd target(1);
  // A cluster-0 hip that impinges like the training hips: level 2, profile, factor of its depth.
  target << 0.2;
  const auto impinging = target_depths({0, 0, 0, 1, 2, 3}, {0, 0, 0, 0.5, 1, 1.5});
  auto steps = depth_nn_estimate(data.scores, data.values, data.depths, target, impinging, 1, 4);
  ASSERT_EQ(steps.size(), 6u);
  for (int j = 0; j < 6; ++j) {
    const double want = 2.0 * Separable::profile(j) *
                        Separable::factor(impinging.curvilinear_mm(0, j), impinging.radial_mm(0, j));
    EXPECT_TRUE(steps[static_cast<std::size_t>(j)].defined);
    EXPECT_NEAR(steps[static_cast<std::size_t>(j)].estimate, want, 1e-12) << "step " << j;
  }
  // Depths a little off the training ones: the nearest pairs (8 at each depth) still decide.
  const auto near = target_depths({0, 0, 0, 1.1, 1.9, 2.9}, {0, 0, 0, 0.45, 1.05, 1.5});
  steps = depth_nn_estimate(data.scores, data.values, data.depths, target, near, 1, 4);
  EXPECT_NEAR(steps[5].estimate, 2.0 * Separable::profile(5) * 5.5, 1e-12);
  EXPECT_NEAR(steps[4].estimate, 2.0 * Separable::profile(4) * 4.0, 1e-12);

  // A cluster-1 hip that never impinges: level 3 and the contact-free profile at every step,
  // where the plain kNN copies its impinging neighbours' jumps.
  target << 9.5;
  const auto free = target_depths({0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0});
  steps = depth_nn_estimate(data.scores, data.values, data.depths, target, free, 1, 4);
  const auto knn = knn_estimate(data.scores, data.values, target, 1, 4);
  for (int j = 0; j < 6; ++j) {
    EXPECT_NEAR(steps[static_cast<std::size_t>(j)].estimate, 3.0 * Separable::profile(j), 1e-12) << "step " << j;
    EXPECT_LE(steps[static_cast<std::size_t>(j)].low, steps[static_cast<std::size_t>(j)].estimate);
    EXPECT_GE(steps[static_cast<std::size_t>(j)].high, steps[static_cast<std::size_t>(j)].estimate);
  }
  EXPECT_GT(knn[5].estimate, 2.0 * steps[5].estimate);
}

TEST(DepthNnEstimator, HipsInContactAtTheFirstStepGiveNoLevel) {
  Separable data;
  // Hip 0 in contact from the first step with an absurd value there: it can be neither the
  // target's level nor a reference of the profile or of a factor.
  data.depths.curvilinear_mm(0, 0) = 0.5;
  data.values(0, 0) = 1000.0;
  Eigen::VectorXd target(1);
  target << 0.0;
  const auto free = target_depths({0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0});
  const auto steps = depth_nn_estimate(data.scores, data.values, data.depths, target, free, 1, 4);
  for (int j = 0; j < 6; ++j) {
    EXPECT_NEAR(steps[static_cast<std::size_t>(j)].estimate, 2.0 * Separable::profile(j), 1e-12) << "step " << j;
  }
}

TEST(DepthNnEstimator, UndefinedWithoutAPairInContactAndRefusesBadInput) {
  Separable data;
  data.depths.curvilinear_mm.setZero();
  data.depths.radial_mm.setZero();
  Eigen::VectorXd target(1);
  target << 0.0;
  const auto impinging = target_depths({0, 0, 0, 1, 2, 3}, {0, 0, 0, 0.5, 1, 1.5});
  const auto steps = depth_nn_estimate(data.scores, data.values, data.depths, target, impinging, 1, 4);
  EXPECT_TRUE(steps[2].defined);
  EXPECT_FALSE(steps[3].defined);  // no training hip ever impinged: no factor to give
  EXPECT_TRUE(std::isnan(steps[3].estimate));

  auto unknown = impinging;
  unknown.radial_mm(0, 2) = kNaN;
  EXPECT_THROW(depth_nn_estimate(data.scores, data.values, data.depths, target, unknown, 1, 4), Error);
  const auto short_target = target_depths({0, 0}, {0, 0});
  EXPECT_THROW(depth_nn_estimate(data.scores, data.values, data.depths, target, short_target, 1, 4), Error);
  EXPECT_THROW(depth_nn_estimate(data.scores, data.values, data.depths, target, impinging, 1, 0), Error);
  EXPECT_THROW(depth_nn_estimate(data.scores, data.values, data.depths, target, impinging, 0, 4), Error);
  PenetrationDepths short_training{data.depths.curvilinear_mm.topRows(3), data.depths.radial_mm.topRows(3)};
  EXPECT_THROW(depth_nn_estimate(data.scores, data.values, short_training, target, impinging, 1, 4), Error);
}

}  // namespace
}  // namespace hipfai::stats
