#include "stats/depth_nn_estimator.h"

#include "core/error.h"
#include "core/numbers.h"
#include "stats/knn_regression.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hipfai::stats {
namespace {

using hipfai::kNaN;

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

TEST(DepthNnEstimator, UndefinedWithoutAPairInContactAndRefusesBadInputAsDepthAligned) {
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
  // depth_aligned likewise: no hip penetrates, so no factor; the same refusals.
  const auto aligned = depth_aligned_estimate(data.scores, data.values, data.depths, target, impinging, 1, 4);
  EXPECT_TRUE(aligned[2].defined);
  EXPECT_FALSE(aligned[3].defined);
  EXPECT_THROW(depth_aligned_estimate(data.scores, data.values, data.depths, target, unknown, 1, 4), Error);
  EXPECT_THROW(depth_aligned_estimate(data.scores, data.values, data.depths, target, impinging, 0, 4), Error);
  const auto short_target = target_depths({0, 0}, {0, 0});
  EXPECT_THROW(depth_nn_estimate(data.scores, data.values, data.depths, target, short_target, 1, 4), Error);
  EXPECT_THROW(depth_nn_estimate(data.scores, data.values, data.depths, target, impinging, 1, 0), Error);
  EXPECT_THROW(depth_nn_estimate(data.scores, data.values, data.depths, target, impinging, 0, 4), Error);
  PenetrationDepths short_training{data.depths.curvilinear_mm.topRows(3), data.depths.radial_mm.topRows(3)};
  EXPECT_THROW(depth_nn_estimate(data.scores, data.values, short_training, target, impinging, 1, 4), Error);
}

// Hips whose impingement depends on their geometry: two clusters on one score (0: hips 0-5,
// level 2, factor 1 + c + r; 1: hips 6-11, level 3, factor 1 + 4 (c + r)), one contact-free
// profile. Each impinging hip starts at its own step and deepens at its own rate along the line
// r = c / 2, so the clusters' (hip, step) pairs interleave in depth; hips 5 and 11 never impinge.
struct GeometryDependent {
  static constexpr int kHips = 12, kSteps = 8;
  Eigen::MatrixXd scores{kHips, 1}, values{kHips, kSteps};
  PenetrationDepths depths{Eigen::MatrixXd::Zero(kHips, kSteps), Eigen::MatrixXd::Zero(kHips, kSteps)};
  static double profile(int j) { return 1.0 + 0.1 * j; }
  static double factor(int cluster, double c, double r) { return 1.0 + (cluster == 0 ? 1.0 : 4.0) * (c + r); }
  GeometryDependent() {
    for (int i = 0; i < kHips; ++i) {
      const int cluster = i < 6 ? 0 : 1;
      scores(i, 0) = cluster == 0 ? 0.1 * i : 10.0 + 0.1 * i;
      const int onset = 2 + i % 6, member = i % 6;  // members 0-4 impinge from step `onset`
      const double rate = 0.4 + 0.3 * member;
      for (int j = 0; j < kSteps; ++j) {
        if (member < 5 && j >= onset) {
          depths.curvilinear_mm(i, j) = rate * (j - onset + 1);
          depths.radial_mm(i, j) = depths.curvilinear_mm(i, j) / 2.0;
        }
        const double f = factor(cluster, depths.curvilinear_mm(i, j), depths.radial_mm(i, j));
        values(i, j) = (cluster == 0 ? 2.0 : 3.0) * profile(j) * f;
      }
    }
  }
};

TEST(DepthAlignedEstimator, ReadsTheImpingementOffItsGeometricNeighboursPaths) {
  const GeometryDependent data;
  Eigen::VectorXd target(1);
  target << 0.25;  // cluster 0
  // Depths between the training hips' steps, on their line: each neighbour's path holds the
  // linear factor exactly, so the estimate is exact; depth_nn pools cluster 1's steeper pairs.
  const auto impinging = target_depths({0, 0, 0, 0, 0.9, 1.3, 1.7, 2.05}, {0, 0, 0, 0, 0.45, 0.65, 0.85, 1.025});
  const auto aligned = depth_aligned_estimate(data.scores, data.values, data.depths, target, impinging, 1, 4);
  const auto pooled = depth_nn_estimate(data.scores, data.values, data.depths, target, impinging, 1, 4);
  ASSERT_EQ(aligned.size(), 8u);
  double pooled_error = 0.0;
  for (int j = 0; j < 8; ++j) {
    const auto& step = aligned[static_cast<std::size_t>(j)];
    const double want = 2.0 * GeometryDependent::profile(j) *
                        GeometryDependent::factor(0, impinging.curvilinear_mm(0, j), impinging.radial_mm(0, j));
    ASSERT_TRUE(step.defined) << "step " << j;
    EXPECT_NEAR(step.estimate, want, 1e-12) << "step " << j;
    EXPECT_LE(step.low, step.estimate + 1e-12);
    EXPECT_GE(step.high, step.estimate - 1e-12);
    pooled_error = std::max(pooled_error, std::abs(pooled[static_cast<std::size_t>(j)].estimate - want) / want);
  }
  EXPECT_GT(pooled_error, 0.2);

  // Deeper than any neighbour reached: each path's deepest point, no extrapolation.
  const auto deep = target_depths({0, 0, 0, 0, 0, 0, 0, 100}, {0, 0, 0, 0, 0, 0, 0, 50});
  const auto beyond = depth_aligned_estimate(data.scores, data.values, data.depths, target, deep, 1, 4);
  double mean_factor = 0.0;
  for (int i = 1; i <= 4; ++i) {  // the 4 penetrating hips nearest 0.25: 1-4, each deepest at the last step
    mean_factor += GeometryDependent::factor(0, data.depths.curvilinear_mm(i, 7), data.depths.radial_mm(i, 7)) / 4.0;
  }
  EXPECT_NEAR(beyond[7].estimate, 2.0 * GeometryDependent::profile(7) * mean_factor, 1e-12);
}

TEST(DepthAlignedEstimator, FreeStepsFollowTheNeighboursOwnCourse) {
  // Two clusters with different contact-free courses (1 + 0.1 j and 1 + 0.3 j), none impinging
  // except hip 7 (cluster 1) at the last step: a free cluster-1 target follows its cluster's course,
  // and where a neighbour is in contact that neighbour contributes the pooled profile instead.
  constexpr int kHips = 10, kSteps = 5;
  Eigen::MatrixXd scores(kHips, 1), values(kHips, kSteps);
  PenetrationDepths depths{Eigen::MatrixXd::Zero(kHips, kSteps), Eigen::MatrixXd::Zero(kHips, kSteps)};
  for (int i = 0; i < kHips; ++i) {
    const bool second = i >= 5;
    scores(i, 0) = second ? 10.0 + 0.1 * i : 0.1 * i;
    for (int j = 0; j < kSteps; ++j) values(i, j) = (second ? 3.0 : 2.0) * (1.0 + (second ? 0.3 : 0.1) * j);
  }
  depths.curvilinear_mm(7, 4) = 1.0;
  values(7, 4) = 50.0;
  Eigen::VectorXd target(1);
  target << 10.65;  // nearest: hips 6, 7, 5, 8
  const auto free = target_depths({0, 0, 0, 0, 0}, {0, 0, 0, 0, 0});
  const auto steps = depth_aligned_estimate(scores, values, depths, target, free, 1, 4);
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(steps[static_cast<std::size_t>(j)].estimate, 3.0 * (1.0 + 0.3 * j), 1e-12) << "step " << j;
  }
  // Step 5: hips 5, 6, 8 their own course, hip 7 the pooled one (the 9 free hips' mean ratio).
  const double pooled = (5 * 1.4 + 4 * 2.2) / 9.0;
  EXPECT_NEAR(steps[4].estimate, 3.0 * (3 * 2.2 + pooled) / 4.0, 1e-12);
  EXPECT_NEAR(steps[4].low, 3.0 * pooled, 1e-12);
  EXPECT_NEAR(steps[4].high, 3.0 * 2.2, 1e-12);
  // depth_nn reads the pooled course at every step.
  const auto pooled_steps = depth_nn_estimate(scores, values, depths, target, free, 1, 4);
  EXPECT_GT(std::abs(pooled_steps[3].estimate - 3.0 * 1.9), 0.2);
}

}  // namespace
}  // namespace hipfai::stats
