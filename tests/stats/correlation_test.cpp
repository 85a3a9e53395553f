// Spearman's rho, average ranks and the Fisher-z interval against values computed by hand.
#include "stats/correlation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hipfai::stats {
namespace {

TEST(AverageRanks, TiesShareTheMeanRank) {
  const std::vector<double> v{10, 20, 20, 5, 20, 7};
  const std::vector<double> expected{3, 5, 5, 1, 5, 2};  // 20 x3 spans ranks 4, 5, 6
  EXPECT_EQ(average_ranks(v), expected);
}

// Ten subjects, IQ against hours of television (a textbook example): no ties, so
// rho = 1 - 6 sum d^2 / (n (n^2 - 1)) with sum d^2 = 194: rho = -29/165.
TEST(Spearman, MatchesTheClosedFormWithoutTies) {
  const std::vector<double> iq{106, 86, 100, 101, 99, 103, 97, 113, 112, 110};
  const std::vector<double> tv{7, 0, 27, 50, 28, 29, 20, 12, 6, 17};
  const auto result = spearman(iq, tv);
  ASSERT_TRUE(result.defined);
  EXPECT_NEAR(result.r, -29.0 / 165.0, 1e-14);
  EXPECT_EQ(result.n, 10);
  // p from t = rho sqrt(8 / (1 - rho^2)) with 8 degrees of freedom; Student's t with an even
  // number of degrees of freedom has a closed-form CDF: for nu = 8, with s = t / sqrt(8 + t^2),
  // F(t) = 1/2 + s/2 (1 + c/2 + 3 c^2/8 + 5 c^3/16), c = 1 - s^2.
  const double rho = -29.0 / 165.0;
  const double t = std::abs(rho) * std::sqrt(8.0 / (1.0 - rho * rho));
  const double s = t / std::sqrt(8.0 + t * t);
  const double c = 1.0 - s * s;
  const double cdf = 0.5 + 0.5 * s * (1.0 + c / 2.0 + 3.0 * c * c / 8.0 + 5.0 * c * c * c / 16.0);
  EXPECT_NEAR(result.p_value, 2.0 * (1.0 - cdf), 1e-10);
}

TEST(Spearman, IsInvariantUnderMonotoneMapsAndHandlesTies) {
  const std::vector<double> x{1, 2, 3, 4, 5, 6};
  std::vector<double> y;
  for (double v : x) y.push_back(std::exp(v));  // monotone: rho = 1 although Pearson r < 1
  EXPECT_NEAR(spearman(x, y).r, 1.0, 1e-14);
  EXPECT_LT(pearson(x, y).r, 0.95);
  // With ties: x ranks {1, 2.5, 2.5, 4}, y ranks {1, 2, 3, 4}: Pearson of the ranks by hand,
  // Sxy = 4.5, Sxx = 4.5, Syy = 5: rho = 4.5 / sqrt(22.5).
  const std::vector<double> tx{1, 2, 2, 3}, ty{10, 20, 30, 40};
  EXPECT_NEAR(spearman(tx, ty).r, 4.5 / std::sqrt(22.5), 1e-14);
}

// Fisher's interval for r = 0.5, n = 28: z = atanh(0.5), standard error 1 / 5, the 97.5 %
// normal quantile 1.959963984540054.
TEST(FisherInterval, MatchesTheClosedForm) {
  const auto ci = fisher_interval(0.5, 28);
  ASSERT_TRUE(ci.defined);
  const double z = std::atanh(0.5), q = 1.959963984540054;
  EXPECT_NEAR(ci.low, std::tanh(z - q / 5.0), 1e-9);
  EXPECT_NEAR(ci.high, std::tanh(z + q / 5.0), 1e-9);
  EXPECT_FALSE(fisher_interval(0.5, 3).defined);
  EXPECT_FALSE(fisher_interval(1.0, 30).defined);
}

TEST(Correlate, LabelsConstantAndShortSeries) {
  const std::vector<double> depth{0, 0, 0, 0, 0}, stress{1, 2, 3, 4, 5};
  EXPECT_EQ(correlate(depth, stress).status, "constant");
  EXPECT_EQ(correlate(std::vector<double>{1, 2}, std::vector<double>{3, 4}).status, "too few");
  const auto ok = correlate(stress, std::vector<double>{2, 4, 5, 4, 5});
  EXPECT_EQ(ok.status, "ok");
  EXPECT_TRUE(ok.interval.defined);
  EXPECT_LT(ok.interval.low, ok.pearson.r);
  EXPECT_GT(ok.interval.high, ok.pearson.r);
}

}  // namespace
}  // namespace hipfai::stats
