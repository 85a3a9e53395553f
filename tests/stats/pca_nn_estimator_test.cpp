#include "stats/pca_nn_estimator.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hipfai::stats {
namespace {

// Toy set (e = 2 scores), target t = (2, 0), hips A..E with values 1..5 at step 0:
//   A (0, 0)  B (1, 3)  C (2.5, -2)  D (3, 0.5)  E (10, 10)
// k = 0: DIST1 = |score 1 difference|: A 0, B 3, C 2, D 0.5, E 10.
//        nearest 2 -> {A, D}; DIST2 = |score 0 difference|: A 2, D 1 -> CS_0 = D (value 4).
//        nearest 4 -> {A, D, C, B}; DIST2: A 2, D 1, C 0.5, B 1 -> CS_0 = C (value 3).
// k = 1: DIST1 = |score 0 difference|: A 2, B 1, C 0.5, D 1, E 8.
//        nearest 2 -> {C, B} (B and D tie at 1: lower row B); DIST2 = |score 1|: C 2, B 3 -> CS_1 = C.
// With CC = (-0.8, 0.4): HCC(2) = {0, 1} (by |CC|), weights 0.8 and 0.4, so (nearest 2)
//   estimate = (0.8 * 4 + 0.4 * 3) / 1.2 = 11/3, inside the chosen values' range [3, 4].
// (The product form printed as Eq. 23 would give (0.8*4 * 0.4*3) / (0.8 * 0.4) = 12.)
struct Toy {
  Eigen::MatrixXd scores{5, 2};
  Eigen::MatrixXd values{5, 2};
  Eigen::MatrixXd correlations{2, 2};
  Eigen::VectorXd target{2};
  Toy() {
    scores << 0, 0, 1, 3, 2.5, -2, 3, 0.5, 10, 10;
    values << 1, 1, 2, 2, 3, 3, 4, 4, 5, 5;
    correlations << -0.8, 0.1, 0.4, 0.9;
    target << 2, 0;
  }
};

TEST(PcaNnEstimator, ClosestSetByHand) {
  const Toy toy;
  const std::vector<int> all{0, 1, 2, 3, 4};
  EXPECT_EQ(closest_set(toy.scores, all, toy.target, 0, 2), 3);
  EXPECT_EQ(closest_set(toy.scores, all, toy.target, 0, 4), 2);
  EXPECT_EQ(closest_set(toy.scores, all, toy.target, 1, 2), 2);
  // Candidate order does not matter (ties go to the lower row, not the first listed).
  EXPECT_EQ(closest_set(toy.scores, {4, 3, 2, 1, 0}, toy.target, 1, 2), 2);
  EXPECT_THROW(closest_set(toy.scores, {}, toy.target, 0, 4), Error);
}

TEST(PcaNnEstimator, WeightedAverageByHand) {
  const Toy toy;
  const auto steps = pca_nn_estimate(toy.scores, toy.values, toy.correlations, toy.target, {.e_prime = 2, .nearest = 2});
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].components, (std::vector<int>{0, 1}));
  EXPECT_EQ(steps[0].chosen_hips, (std::vector<int>{3, 2}));
  EXPECT_NEAR(steps[0].estimate, 11.0 / 3.0, 1e-14);
  EXPECT_EQ(steps[0].low, 3.0);
  EXPECT_EQ(steps[0].high, 4.0);
  // Step 1: CC = (0.1, 0.9) -> component 1 first; same hips, weights 0.9 and 0.1.
  EXPECT_EQ(steps[1].components, (std::vector<int>{1, 0}));
  EXPECT_NEAR(steps[1].estimate, (0.9 * 3 + 0.1 * 4) / 1.0, 1e-14);
  // e' = 1: only the most correlated component's hip.
  const auto one = pca_nn_estimate(toy.scores, toy.values, toy.correlations, toy.target, {.e_prime = 1, .nearest = 2});
  EXPECT_DOUBLE_EQ(one[0].estimate, 4.0);
  EXPECT_DOUBLE_EQ(one[1].estimate, 3.0);
}

TEST(PcaNnEstimator, MissingValuesLeaveTheHipOut) {
  Toy toy;
  toy.values(3, 0) = std::numeric_limits<double>::quiet_NaN();  // D has no value at step 0
  const auto steps = pca_nn_estimate(toy.scores, toy.values, toy.correlations, toy.target, {.e_prime = 1, .nearest = 2});
  // k = 0 without D: nearest 2 by DIST1 -> {A (0), C (2)}; DIST2: A 2, C 0.5 -> C (value 3).
  EXPECT_EQ(steps[0].chosen_hips, (std::vector<int>{2}));
  EXPECT_DOUBLE_EQ(steps[0].estimate, 3.0);
  EXPECT_DOUBLE_EQ(steps[1].estimate, 3.0);  // step 1: component 1 -> C as before
}

TEST(PcaNnEstimator, RanksByAbsoluteCorrelationUndefinedLast) {
  Eigen::VectorXd r(4);
  r << 0.2, -0.9, std::numeric_limits<double>::quiet_NaN(), 0.5;
  EXPECT_EQ(highest_correlated(r, 4), (std::vector<int>{1, 3, 0, 2}));
  EXPECT_EQ(highest_correlated(r, 2), (std::vector<int>{1, 3}));
  EXPECT_EQ(highest_correlated(r, 9).size(), 4u);
}

TEST(PcaNnEstimator, CorrelationsArePearson) {
  Eigen::MatrixXd scores(4, 2);
  scores << 1, 4, 2, 3, 3, 2, 4, 1;
  Eigen::MatrixXd values(4, 1);
  values << 10, 20, 30, 40;
  const Eigen::MatrixXd r = score_value_correlations(scores, values);
  EXPECT_NEAR(r(0, 0), 1.0, 1e-14);
  EXPECT_NEAR(r(1, 0), -1.0, 1e-14);
}

}  // namespace
}  // namespace hipfai::stats
