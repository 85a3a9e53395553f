#include "stats/pca.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hipfai::stats {
namespace {

// Four points on the diagonal: mean 0, each feature has variance (4 + 1 + 1 + 4) / 3 = 10/3, so
// the z-scores are x / sqrt(10/3) on both axes. All the variance (total 2, one per normalised
// feature) lies along (1, 1) / sqrt(2); the second component has variance 0.
TEST(Pca, DiagonalPointsByHand) {
  Eigen::MatrixXd samples(4, 2);
  samples << -2, -2, -1, -1, 1, 1, 2, 2;
  // Two components asked for; the points span one direction, so one is kept (the second would be
  // a round-off direction, pca.h).
  const Pca pca = fit_pca(samples, {.components = 2, .scale_floor = 0.0});
  ASSERT_EQ(pca.num_components(), 1);
  EXPECT_NEAR(pca.mean(0), 0.0, 1e-15);
  EXPECT_NEAR(pca.scale(0), std::sqrt(10.0 / 3.0), 1e-14);
  EXPECT_NEAR(pca.total_variance, 2.0, 1e-13);
  EXPECT_NEAR(pca.variances(0), 2.0, 1e-13);
  // Sign convention: the largest loading is positive (both equal: the first wins).
  EXPECT_NEAR(pca.basis(0, 0), 1.0 / std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(pca.basis(1, 0), 1.0 / std::sqrt(2.0), 1e-14);
  // Score of (2, 2): |(2, 2)| / sqrt(10/3) = 2 sqrt(2) / sqrt(10/3) along the component.
  const Eigen::MatrixXd scores = pca_scores(pca, samples);
  EXPECT_NEAR(scores(3, 0), 2.0 * std::sqrt(2.0) / std::sqrt(10.0 / 3.0), 1e-13);
  EXPECT_NEAR(scores(0, 0), -scores(3, 0), 1e-13);
  EXPECT_NEAR(score_mahalanobis(pca, scores.row(3).transpose()), scores(3, 0) / std::sqrt(2.0), 1e-13);
}

// Rectangle corners (+-3, +-1): with a floor above both deviations every feature is divided by the
// floor (10), so the PCA is that of the raw data / 10: covariance diag(12, 4/3) / 100; the
// components are the axes, x first.
TEST(Pca, ScaleFloorKeepsRawProportions) {
  Eigen::MatrixXd samples(4, 2);
  samples << 3, 1, 3, -1, -3, 1, -3, -1;
  const Pca pca = fit_pca(samples, {.components = 5, .scale_floor = 10.0});
  ASSERT_EQ(pca.num_components(), 2);  // capped at min(rows - 1, features)
  EXPECT_EQ(pca.scale(0), 10.0);
  EXPECT_EQ(pca.scale(1), 10.0);
  EXPECT_NEAR(pca.variances(0), 0.12, 1e-14);
  EXPECT_NEAR(pca.variances(1), 4.0 / 300.0, 1e-14);
  EXPECT_NEAR(std::abs(pca.basis(0, 0)), 1.0, 1e-14);
  EXPECT_NEAR(std::abs(pca.basis(1, 1)), 1.0, 1e-14);
  // A new point is projected with the training mean, scale and basis (Eq. 19).
  Eigen::MatrixXd target(1, 2);
  target << 6, 0;
  EXPECT_NEAR(pca_scores(pca, target)(0, 0), 0.6, 1e-14);
  // Without the floor the two features are z-scored and carry equal variance.
  const Pca plain = fit_pca(samples, {.components = 2, .scale_floor = 0.0});
  EXPECT_NEAR(plain.variances(0), 1.0, 1e-13);
  EXPECT_NEAR(plain.variances(1), 1.0, 1e-13);
}

TEST(Pca, ConstantFeatureContributesNothing) {
  Eigen::MatrixXd samples(3, 2);
  samples << 1, 5, 2, 5, 3, 5;
  const Pca pca = fit_pca(samples, {.components = 2});
  EXPECT_EQ(pca.scale(1), 1.0);
  EXPECT_NEAR(pca.total_variance, 1.0, 1e-14);
  EXPECT_NEAR(std::abs(pca.basis(0, 0)), 1.0, 1e-14);
}

TEST(Pca, RejectsBadInput) {
  EXPECT_THROW(fit_pca(Eigen::MatrixXd::Ones(1, 3), {}), Error);
  Eigen::MatrixXd nan = Eigen::MatrixXd::Ones(3, 2);
  nan(1, 1) = std::nan("");
  EXPECT_THROW(fit_pca(nan, {}), Error);
  const Pca pca = fit_pca(Eigen::MatrixXd::Random(4, 3), {});
  EXPECT_THROW(pca_scores(pca, Eigen::MatrixXd::Ones(1, 2)), Error);
}

}  // namespace
}  // namespace hipfai::stats

namespace hipfai::stats {
namespace {

// Six samples that are three points, each twice (hips whose sampled tissues are copies): the
// normalised data span two directions, so at most two components are kept whatever is asked, and
// their scores stay O(1) (no round-off direction scaled up). All samples equal: an error.
TEST(Pca, ComponentsCappedAtTheNumericalRank) {
  Eigen::MatrixXd samples(6, 4);
  samples << 1, 2, 3, 4, 1, 2, 3, 4, 2, 2, 5, 1, 2, 2, 5, 1, 0, 7, 1, 1, 0, 7, 1, 1;
  const Pca pca = fit_pca(samples, {.components = 5, .scale_floor = 0.0});
  EXPECT_EQ(pca.num_components(), 2);
  EXPECT_NEAR(pca.variances.sum(), pca.total_variance, 1e-12 * pca.total_variance);
  const Eigen::MatrixXd scores = pca_scores(pca, samples);
  EXPECT_LT(scores.cwiseAbs().maxCoeff(), 10.0);
  const Eigen::MatrixXd same = Eigen::MatrixXd::Constant(3, 4, 2.5);
  EXPECT_THROW(fit_pca(same, {.components = 2, .scale_floor = 0.0}), Error);
}

}  // namespace
}  // namespace hipfai::stats
