#include "stats/conformal_interval.h"

#include "core/error.h"
#include "stats/interval_coverage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace hipfai::stats {
namespace {

// Rows with a relative normal error: truth = prediction (1 + sigma Z), sigma per group.
std::vector<ConformalRow> rows_with_errors(std::size_t n, const std::vector<double>& sigma, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::uniform_real_distribution<double> level(1.0, 5.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_int_distribution<int> group(0, static_cast<int>(sigma.size()) - 1);
  std::vector<ConformalRow> rows;
  for (std::size_t i = 0; i < n; ++i) {
    ConformalRow row;
    row.group = group(engine);
    row.prediction = level(engine);
    row.truth = row.prediction * (1.0 + sigma[static_cast<std::size_t>(row.group)] * noise(engine));
    rows.push_back(row);
  }
  return rows;
}

// The k-th smallest score, k = ceil((n + 1) * nominal), worked by hand: scores 0.1 .. 0.9 (n = 9),
// nominal 0.8 -> k = ceil(8.0) = 8 -> 0.8; nominal 0.85 -> k = ceil(8.5) = 9 -> 0.9; nominal 0.95
// -> k = ceil(9.5) = 10 > 9 -> unbounded.
TEST(ConformalInterval, QuantileIsTheKthSmallestScore) {
  std::vector<ConformalRow> rows;
  for (int i = 9; i >= 1; --i) rows.push_back({10.0, 10.0 + i, 0});  // score i / 10, given in reverse order
  EXPECT_DOUBLE_EQ(calibrate_conformal(rows, 1, 0.8).half_width[0], 0.8);
  EXPECT_DOUBLE_EQ(calibrate_conformal(rows, 1, 0.85).half_width[0], 0.9);
  EXPECT_TRUE(std::isinf(calibrate_conformal(rows, 1, 0.95).half_width[0]));
  const ConformalInterval interval = conformal_interval(calibrate_conformal(rows, 1, 0.8), 2.0, 0);
  EXPECT_DOUBLE_EQ(interval.lower, 2.0 - 1.6);
  EXPECT_DOUBLE_EQ(interval.upper, 2.0 + 1.6);
}

// Calibrated on one draw, the intervals hold the truth of a fresh draw from the same distribution
// at the nominal rate, in each group separately although the groups' errors differ fivefold: the
// covered count must lie in the binomial band of the nominal (99.9 %). A single interval for both
// groups would over-cover the quiet group and under-cover the noisy one.
TEST(ConformalInterval, FreshRowsAreCoveredAtTheNominalRatePerGroup) {
  const std::vector<double> sigma{0.02, 0.10};
  const ConformalCalibration calibration = calibrate_conformal(rows_with_errors(4000, sigma, 1), 2, 0.9);
  EXPECT_NEAR(calibration.half_width[0], 1.6448536269514722 * 0.02, 0.004);
  EXPECT_NEAR(calibration.half_width[1], 1.6448536269514722 * 0.10, 0.02);
  for (int group = 0; group < 2; ++group) {
    std::vector<IntervalRow> test;
    for (const ConformalRow& row : rows_with_errors(8000, sigma, 2)) {
      if (row.group != group) continue;
      const ConformalInterval interval = conformal_interval(calibration, row.prediction, group);
      test.push_back({row.prediction, interval.lower, interval.upper, row.truth, false});
    }
    const CoverageResult coverage = interval_coverage(test, 0.1);
    const CountInterval band = binomial_acceptance_interval(0.9, coverage.rows, 0.001);
    EXPECT_GE(coverage.covered, band.low) << "group " << group;
    EXPECT_LE(coverage.covered, band.high) << "group " << group;
  }
}

TEST(ConformalInterval, UnusableRowsAreLeftOutAndBadInputIsRefused) {
  const std::vector<ConformalRow> rows{{0.0, 1.0, 0}, {std::nan(""), 1.0, 0}, {1.0, std::nan(""), 0}, {2.0, 2.2, 0}};
  const ConformalCalibration calibration = calibrate_conformal(rows, 1, 0.4);
  EXPECT_EQ(calibration.rows[0], 1u);
  EXPECT_NEAR(calibration.half_width[0], 0.1, 1e-12);
  EXPECT_THROW(calibrate_conformal(rows, 1, 1.0), Error);
  EXPECT_THROW(calibrate_conformal(rows, 0, 0.9), Error);
  EXPECT_THROW(calibrate_conformal({{1.0, 1.0, 2}}, 2, 0.9), Error);
  EXPECT_THROW(conformal_interval(calibration, 1.0, 1), Error);
}

}  // namespace
}  // namespace hipfai::stats
