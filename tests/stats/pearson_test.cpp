#include "stats/pearson.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hipfai::stats {
namespace {

TEST(Pearson, PerfectLinearRelationIsOne) {
  const std::vector<double> x{1, 2, 3, 4, 5};
  const std::vector<double> y{3, 5, 7, 9, 11};
  const auto result = pearson(x, y);
  ASSERT_TRUE(result.defined);
  EXPECT_NEAR(result.r, 1.0, 1e-14);
  EXPECT_EQ(result.p_value, 0.0);
}

// Reference computed by hand: x = 1..6, y = {2, 1, 4, 3, 6, 5}: Sxy = 14.5, Sxx = Syy = 17.5,
// r = 29/35. With 4 degrees of freedom Student's t has the closed-form CDF
// F(t) = 1/2 + (3/4) s (1 - s^2/3), s = t / sqrt(4 + t^2), so p = 2 (1 - F(|t|)) is checked
// without GSL.
TEST(Pearson, MatchesHandComputedValue) {
  const std::vector<double> x{1, 2, 3, 4, 5, 6};
  const std::vector<double> y{2, 1, 4, 3, 6, 5};
  const auto result = pearson(x, y);
  const double r = 29.0 / 35.0;
  EXPECT_NEAR(result.r, r, 1e-14);
  const double t = r * std::sqrt(4.0 / (1.0 - r * r));
  const double s = t / std::sqrt(4.0 + t * t);
  const double p = 2.0 * (1.0 - (0.5 + 0.75 * s * (1.0 - s * s / 3.0)));
  EXPECT_NEAR(result.p_value, p, 1e-10);
}

TEST(Pearson, ConstantSampleIsUndefined) {
  const std::vector<double> x{1, 2, 3, 4};
  const std::vector<double> y{2, 2, 2, 2};
  EXPECT_FALSE(pearson(x, y).defined);
}

TEST(Pearson, BandsFollowChan2003) {
  EXPECT_EQ(correlation_band(0.2), "poor");
  EXPECT_EQ(correlation_band(0.45), "fair");
  EXPECT_EQ(correlation_band(0.55), "moderate");
  EXPECT_EQ(correlation_band(-0.7), "moderately strong");
  EXPECT_EQ(correlation_band(0.91), "very strong");
}

}  // namespace
}  // namespace hipfai::stats
