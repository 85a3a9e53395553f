#include "stats/interval_coverage.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace hipfai::stats {
namespace {

// Standard normal quantiles (to 16 digits): Phi^-1(0.95) and Phi^-1(0.975).
constexpr double kZ95 = 1.6448536269514722;
constexpr double kZ975 = 1.9599639845400540;

// Predictions with a known normal error: truth = prediction + sigma Z, sigma 10 % of the
// prediction; intervals prediction +- half_width_in_sigmas sigma.
std::vector<IntervalRow> normal_rows(std::size_t n, double half_width_in_sigmas, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::uniform_real_distribution<double> level(1.0, 5.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<IntervalRow> rows;
  for (std::size_t i = 0; i < n; ++i) {
    IntervalRow row;
    row.prediction = level(engine);
    const double sigma = 0.1 * row.prediction;
    row.lower = row.prediction - half_width_in_sigmas * sigma;
    row.upper = row.prediction + half_width_in_sigmas * sigma;
    row.truth = row.prediction + sigma * noise(engine);
    rows.push_back(row);
  }
  return rows;
}

// Intervals at the exact 5 % and 95 % quantiles of the truth's distribution hold it 90 % of the
// time: the count of covered rows must lie in Binomial(n, 0.9)'s central 99.9 % interval. The same
// check must reject intervals whose real coverage is 68.3 % (+-1 sigma) or 95 % (+-1.96 sigma):
// with n = 4000 the tolerance is about +-1.6 points, so it tells 90 % from 95 %.
TEST(IntervalCoverage, NinetyPercentNormalIntervalsCoverNinetyPercent) {
  constexpr std::size_t n = 4000;
  const CountInterval accepted = binomial_acceptance_interval(0.9, n, 0.001);
  std::printf("Binomial(%zu, 0.9) 99.9 %% interval: %zu..%zu covered rows\n", n, accepted.low, accepted.high);
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const CoverageResult exact = interval_coverage(normal_rows(n, kZ95, seed), 0.1);
    EXPECT_EQ(exact.rows, n);
    std::printf("seed %d: 90 %% intervals cover %.4f\n", static_cast<int>(seed), exact.coverage);
    EXPECT_GE(exact.covered, accepted.low);
    EXPECT_LE(exact.covered, accepted.high);
    const CoverageResult narrow = interval_coverage(normal_rows(n, 1.0, seed), 0.1);
    EXPECT_LT(narrow.covered, accepted.low) << "68 % intervals pass for 90 %: " << narrow.coverage;
    const CoverageResult wide = interval_coverage(normal_rows(n, kZ975, seed), 0.1);
    EXPECT_GT(wide.covered, accepted.high) << "95 % intervals pass for 90 %: " << wide.coverage;
  }
}

// Ten rows whose coverage and flag recall are known by construction (threshold 10 %).
TEST(IntervalCoverage, KnownByConstruction) {
  const double nan = std::nan("");
  const std::vector<IntervalRow> rows{
      {10, 9, 11, 10, false},   // covered, error 0
      {10, 9, 11, 11, false},   // on the upper end: covered; error 1/11 < 10 %
      {10, 9, 11, 9, true},     // on the lower end: covered; error 1/9 > 10 %, flagged
      {10, 9, 11, 12, true},    // above: not covered; error 1/6, flagged
      {10, 9, 11, 5, false},    // below: not covered; error 100 %, not flagged
      {1, 0, 2, 0, true},       // truth 0, prediction 1: error infinite, flagged; covered
      {0, 0, 0, 0, false},      // a point interval on the truth: covered, error 0
      {nan, 0, 1, 1, true},     // no prediction: skipped
      {1, 0, 2, nan, true},     // no truth (failed FE step): skipped
      {3, 2, 4, 3.2, true},     // covered, error 6.25 %, flagged although small
  };
  const CoverageResult result = interval_coverage(rows, 0.1);
  EXPECT_EQ(result.rows, 8u);
  EXPECT_EQ(result.skipped, 2u);
  EXPECT_EQ(result.covered, 6u);
  EXPECT_DOUBLE_EQ(result.coverage, 0.75);
  EXPECT_EQ(result.flagged, 4u);
  EXPECT_EQ(result.large_error, 4u);
  EXPECT_EQ(result.large_error_flagged, 3u);
  EXPECT_DOUBLE_EQ(result.flag_recall, 0.75);
  // A higher threshold leaves only the 100 % and infinite errors large: one of two flagged.
  const CoverageResult strict = interval_coverage(rows, 0.5);
  EXPECT_EQ(strict.large_error, 2u);
  EXPECT_DOUBLE_EQ(strict.flag_recall, 0.5);
}

// Binomial(10, 0.5): P(X <= 1) = 11/1024 <= 0.025 < P(X <= 2) = 56/1024, and symmetrically, so the
// 95 % interval is 2..8.
TEST(IntervalCoverage, BinomialAcceptanceIntervalByHand) {
  const CountInterval interval = binomial_acceptance_interval(0.5, 10, 0.05);
  EXPECT_EQ(interval.low, 2u);
  EXPECT_EQ(interval.high, 8u);
  EXPECT_THROW(binomial_acceptance_interval(1.0, 10, 0.05), Error);
  EXPECT_THROW(binomial_acceptance_interval(0.9, 0, 0.05), Error);
  EXPECT_THROW(binomial_acceptance_interval(0.9, 10, 0.0), Error);
}

TEST(IntervalCoverage, EmptyAndBadInput) {
  const CoverageResult empty = interval_coverage({}, 0.1);
  EXPECT_EQ(empty.rows, 0u);
  EXPECT_TRUE(std::isnan(empty.coverage));
  EXPECT_TRUE(std::isnan(empty.flag_recall));
  EXPECT_THROW(interval_coverage({{1, 2, 0, 1, false}}, 0.1), Error);
  EXPECT_THROW(interval_coverage({{1, 0, 2, 1, false}}, -0.1), Error);
}

}  // namespace
}  // namespace hipfai::stats
