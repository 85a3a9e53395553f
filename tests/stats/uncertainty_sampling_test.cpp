#include "stats/uncertainty_sampling.h"

#include "core/error.h"
#include "stats/knn_regression.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hipfai::stats {
namespace {

// A toy training set with a known gap: "hips" at x = 0, 0.1, 0.2, 0.3, 0.4 and 1.0, value x^2 at
// two steps (x^2 and 2 x^2). The kNN baseline (k = 2) gives each candidate the range of its two
// nearest training values as interval. The candidate at x = 0.7, in the gap, sits between 0.4 and
// 1.0: interval [0.16, 1.0] at step 1, the widest by far (the others' neighbours are 0.1 apart,
// widths <= 0.07). It must come first; the next is the one nearest the gap's edge.
TEST(UncertaintySampling, PicksTheCandidateInTheGapOfTheTrainingSet) {
  const std::vector<double> training_x{0.0, 0.1, 0.2, 0.3, 0.4, 1.0};
  Eigen::MatrixXd scores(6, 1), values(6, 2);
  for (int i = 0; i < 6; ++i) {
    scores(i, 0) = training_x[static_cast<std::size_t>(i)];
    values(i, 0) = scores(i, 0) * scores(i, 0);
    values(i, 1) = 2.0 * values(i, 0);
  }
  const std::vector<double> candidate_x{0.05, 0.15, 0.7, 0.25, 0.35};
  std::vector<CandidatePrediction> candidates;
  for (const double x : candidate_x) {
    const auto steps = knn_estimate(scores, values, Eigen::VectorXd::Constant(1, x), 1, 2);
    CandidatePrediction candidate;
    for (const auto& step : steps) {
      candidate.low.push_back(step.low);
      candidate.high.push_back(step.high);
    }
    candidates.push_back(candidate);
  }
  // Step widths of x = 0.7: 1.0 - 0.16 and 2.0 - 0.32; mean 1.26.
  EXPECT_NEAR(uncertainty_score(candidates[2], UncertaintyCriterion::kIntervalWidth), (0.84 + 1.68) / 2, 1e-12);
  const auto picked = least_certain(candidates, UncertaintyCriterion::kIntervalWidth, 2);
  ASSERT_EQ(picked.size(), 2u);
  EXPECT_EQ(picked[0], 2u);  // x = 0.7
  EXPECT_EQ(picked[1], 4u);  // x = 0.35: neighbours 0.3 and 0.4, width 0.07 (the largest of the rest)
}

// Three methods' estimates; the disagreement is the mean over steps of their range.
TEST(UncertaintySampling, MethodDisagreementByHand) {
  CandidatePrediction agree{{}, {}, {{1.0, 2.0}, {1.1, 2.0}, {0.9, 2.2}}};  // ranges 0.2, 0.2
  CandidatePrediction split{{}, {}, {{1.0, 2.0}, {3.0, 2.0}, {1.0, NAN}}};   // ranges 2, 0 (NaN left out)
  CandidatePrediction alone{{}, {}, {{1.0, 2.0}, {NAN, NAN}}};               // one method: no range
  EXPECT_NEAR(uncertainty_score(agree, UncertaintyCriterion::kMethodDisagreement), 0.2, 1e-12);
  EXPECT_NEAR(uncertainty_score(split, UncertaintyCriterion::kMethodDisagreement), 1.0, 1e-12);
  EXPECT_TRUE(std::isnan(uncertainty_score(alone, UncertaintyCriterion::kMethodDisagreement)));
  const auto picked = least_certain({agree, alone, split}, UncertaintyCriterion::kMethodDisagreement, 5);
  EXPECT_EQ(picked, (std::vector<std::size_t>{2, 0}));  // the scoreless candidate is never picked
}

TEST(UncertaintySampling, TiesGoToTheLowerIndexAndBadInputIsRefused) {
  const CandidatePrediction wide{{0.0}, {2.0}, {}}, narrow{{0.0}, {1.0}, {}};
  EXPECT_EQ(least_certain({narrow, wide, wide}, UncertaintyCriterion::kIntervalWidth, 2),
            (std::vector<std::size_t>{1, 2}));
  EXPECT_THROW(least_certain({wide}, UncertaintyCriterion::kIntervalWidth, 0), Error);
  EXPECT_THROW(uncertainty_score({{1.0}, {0.0}, {}}, UncertaintyCriterion::kIntervalWidth), Error);
  EXPECT_THROW(uncertainty_score({{1.0, 2.0}, {3.0}, {}}, UncertaintyCriterion::kIntervalWidth), Error);
  EXPECT_EQ(parse_uncertainty_criterion("width"), UncertaintyCriterion::kIntervalWidth);
  EXPECT_THROW(parse_uncertainty_criterion("entropy"), Error);
}

}  // namespace
}  // namespace hipfai::stats
