#include "stats/pearson.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

namespace hipfai::stats {
namespace {

// Anscombe's quartet (F. J. Anscombe, "Graphs in statistical analysis", Am. Stat. 27 (1973) 17-21,
// Table 1; also R's datasets::anscombe): four sets of 11 points with the same summary statistics.
const std::vector<double> kAnscombeX123{10, 8, 13, 9, 11, 14, 6, 4, 12, 7, 5};
const std::vector<double> kAnscombeY1{8.04, 6.95, 7.58, 8.81, 8.33, 9.96, 7.24, 4.26, 10.84, 4.82, 5.68};
const std::vector<double> kAnscombeY2{9.14, 8.14, 8.74, 8.77, 9.26, 8.10, 6.13, 3.10, 9.13, 7.26, 4.74};
const std::vector<double> kAnscombeY3{7.46, 6.77, 12.74, 7.11, 7.81, 8.84, 6.08, 5.39, 8.15, 6.42, 5.73};
const std::vector<double> kAnscombeX4{8, 8, 8, 8, 8, 8, 8, 19, 8, 8, 8};
const std::vector<double> kAnscombeY4{6.58, 5.76, 7.71, 8.84, 8.47, 7.04, 5.25, 12.50, 5.56, 7.91, 6.89};

// Two-sided p = 1 - A(t|nu) of Student's t for an ODD number of degrees of freedom nu, from the
// closed form of Abramowitz & Stegun, Handbook of Mathematical Functions, 26.7.4: with
// theta = atan(t / sqrt(nu)),
//   A(t|1)  = 2 theta / pi,
//   A(t|nu) = 2/pi [theta + sin theta cos theta (1 + 2/3 cos^2 theta + (2 4)/(3 5) cos^4 theta + ...
//             + (2 4 ... (nu-3)) / (3 5 ... (nu-2)) cos^(nu-3) theta)]   for nu odd > 1,
// A(t|nu) being P(|T| <= t). Term k of the series (k = 0 .. (nu-3)/2) is the previous one times
// 2k / (2k + 1) cos^2 theta. Independent of GSL: the library's p is checked against it.
double two_sided_p_odd_dof(double t, int nu) {
  const double theta = std::atan(std::abs(t) / std::sqrt(static_cast<double>(nu)));
  if (nu == 1) return 1.0 - 2.0 * theta / std::numbers::pi;
  const double c2 = std::cos(theta) * std::cos(theta);
  double term = 1.0, series = 1.0;
  for (int k = 1; k <= (nu - 3) / 2; ++k) {
    term *= 2.0 * k / (2.0 * k + 1.0) * c2;
    series += term;
  }
  const double a = 2.0 / std::numbers::pi * (theta + std::sin(theta) * std::cos(theta) * series);
  return 1.0 - a;
}

// t statistic of r with n - 2 degrees of freedom, as the library forms it.
double t_of(double r, int n) { return r * std::sqrt((n - 2.0) / (1.0 - r * r)); }

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

// Anscombe 1973: the four sets share r = 0.816 (three decimals; but see set IV); set I's r = 0.81642051634484 (as R's
// cor(anscombe$x1, anscombe$y1) = 0.8164205163448...); its p-value 0.00217 as R's
// cor.test(anscombe$x1, anscombe$y1) and summary(lm(y1 ~ x1)) print it (3 significant digits).
TEST(Pearson, AnscombeQuartetMatchesPublishedValues) {
  const auto one = pearson(kAnscombeX123, kAnscombeY1);
  ASSERT_TRUE(one.defined);
  EXPECT_EQ(one.n, 11);
  EXPECT_NEAR(one.r, 0.81642051634484, 1e-6);
  EXPECT_NEAR(one.p_value, 0.00217, 5e-6);
  const auto two = pearson(kAnscombeX123, kAnscombeY2);
  const auto three = pearson(kAnscombeX123, kAnscombeY3);
  const auto four = pearson(kAnscombeX4, kAnscombeY4);
  for (const auto& result : {one, two, three}) {
    ASSERT_TRUE(result.defined);
    EXPECT_NEAR(result.r, 0.816, 5e-4);
  }
  // Set IV's r is 0.8165214..., which rounds to 0.817 (as e.g. Minitab prints it), not to the
  // 0.816 usually quoted for all four sets: it agrees with 0.816 to 1e-3 only.
  ASSERT_TRUE(four.defined);
  EXPECT_NEAR(four.r, 0.817, 5e-4);
  EXPECT_NEAR(four.r, 0.816, 1e-3);
  // The argument order does not matter.
  EXPECT_NEAR(pearson(kAnscombeY4, kAnscombeX4).r, four.r, 1e-14);
}

// The closed form itself against known values: nu = 1 is the Cauchy distribution,
// P(|T| > 1) = 1/2; the tabulated two-sided 5 % critical values t(0.975; 3) = 3.182446,
// t(0.975; 5) = 2.570582, t(0.975; 9) = 2.262157 (6 decimals, so p = 0.05 to ~1e-7).
TEST(Pearson, OddDegreesOfFreedomClosedFormReproducesKnownValues) {
  EXPECT_NEAR(two_sided_p_odd_dof(1.0, 1), 0.5, 1e-15);
  EXPECT_NEAR(two_sided_p_odd_dof(0.0, 7), 1.0, 1e-15);
  EXPECT_NEAR(two_sided_p_odd_dof(3.182446, 3), 0.05, 1e-6);
  EXPECT_NEAR(two_sided_p_odd_dof(2.570582, 5), 0.05, 1e-6);
  EXPECT_NEAR(two_sided_p_odd_dof(2.262157, 9), 0.05, 1e-6);
  // nu = 3 written out: A = 2/pi (theta + sin theta cos theta).
  const double theta = std::atan(2.0 / std::sqrt(3.0));
  EXPECT_NEAR(two_sided_p_odd_dof(2.0, 3),
              1.0 - 2.0 / std::numbers::pi * (theta + std::sin(theta) * std::cos(theta)), 1e-15);
}

// The library's p (GSL) against A&S 26.7.4 for nu = 3, 5, 9, 21, 29: deterministic series
// y = +-x + a sin(1.7 x), x = 1..n, with p from ~1e-8 to ~0.1, and the four Anscombe sets (nu = 9).
TEST(Pearson, PValueMatchesClosedFormForOddDegreesOfFreedom) {
  struct Case {
    int n;
    double amplitude, slope;
  };
  for (const Case c : {Case{5, 1.5, 1.0}, Case{7, 2.0, -1.0}, Case{23, 15.0, 1.0}, Case{31, 9.0, -1.0},
                       Case{31, 30.0, 1.0}}) {
    std::vector<double> x, y;
    for (int i = 1; i <= c.n; ++i) {
      x.push_back(i);
      y.push_back(c.slope * i + c.amplitude * std::sin(1.7 * i));
    }
    const auto result = pearson(x, y);
    ASSERT_TRUE(result.defined);
    EXPECT_NEAR(result.p_value, two_sided_p_odd_dof(t_of(result.r, c.n), c.n - 2), 1e-10) << "n = " << c.n;
    EXPECT_GT(result.p_value, 1e-9);  // not vacuous: far from 0 ...
    EXPECT_LT(result.p_value, 0.2);   // ... and from 1
  }
  const std::vector<std::pair<const std::vector<double>*, const std::vector<double>*>> anscombe{
      {&kAnscombeX123, &kAnscombeY1}, {&kAnscombeX123, &kAnscombeY2}, {&kAnscombeX123, &kAnscombeY3},
      {&kAnscombeX4, &kAnscombeY4}};
  for (const auto& [x, y] : anscombe) {
    const auto result = pearson(*x, *y);
    EXPECT_NEAR(result.p_value, two_sided_p_odd_dof(t_of(result.r, 11), 9), 1e-10);
  }
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
