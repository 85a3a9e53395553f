#include "stats/space_filling_design.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

namespace hipfai::stats {
namespace {

SamplingRequest request_of(SamplingDesign design, int n, std::uint64_t seed, std::vector<ParameterRange> ranges,
                           std::uint64_t stream = 0) {
  SamplingRequest request;
  request.design = design;
  request.n = n;
  request.seed = seed;
  request.stream = stream;
  request.ranges = std::move(ranges);
  return request;
}

// The study's box (CE 0-45, alpha 40-80) and a 4-axis box with a negative range.
const std::vector<ParameterRange> kHipBox{{0.0, 45.0}, {40.0, 80.0}};
const std::vector<ParameterRange> kFourAxes{{0.0, 45.0}, {40.0, 80.0}, {110.0, 146.2}, {-10.0, 40.0}};

// n uniform random points in the unit cube (the plain Monte Carlo set a design must beat).
Eigen::MatrixXd uniform_points(int n, int axes, std::mt19937_64& engine) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::MatrixXd points(n, axes);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < axes; ++k) points(i, k) = uniform(engine);
  }
  return points;
}

template <class Measure>
double median_over_random_sets(int n, int axes, int sets, Measure measure) {
  std::mt19937_64 engine(20260127);
  std::vector<double> values;
  for (int s = 0; s < sets; ++s) values.push_back(measure(uniform_points(n, axes, engine)));
  std::nth_element(values.begin(), values.begin() + sets / 2, values.end());
  return values[static_cast<std::size_t>(sets / 2)];
}

TEST(SpaceFillingDesign, SameSeedSamePointsOtherSeedOrStreamOtherPoints) {
  for (const SamplingDesign design : kSamplingDesigns) {
    SCOPED_TRACE(to_string(design));
    const auto a = draw_design(request_of(design, 20, 7, kFourAxes));
    const auto again = draw_design(request_of(design, 20, 7, kFourAxes));
    EXPECT_TRUE(a.points == again.points) << "not reproducible from the seed";
    const auto other_seed = draw_design(request_of(design, 20, 8, kFourAxes));
    const auto other_stream = draw_design(request_of(design, 20, 7, kFourAxes, 1));
    // Not one coordinate in common: the sets are unrelated, not shifted copies of each other.
    for (const auto* other : {&other_seed, &other_stream}) {
      int common = 0;
      for (Eigen::Index i = 0; i < a.points.rows(); ++i) {
        for (Eigen::Index j = 0; j < other->points.rows(); ++j) common += a.points.row(i) == other->points.row(j);
      }
      EXPECT_EQ(common, 0);
      EXPECT_FALSE(a.points == other->points);
    }
  }
}

TEST(SpaceFillingDesign, EveryPointInsideTheBox) {
  for (const SamplingDesign design : kSamplingDesigns) {
    for (const int n : {1, 2, 13, 64}) {
      const auto result = draw_design(request_of(design, n, 3, kFourAxes));
      ASSERT_EQ(result.points.rows(), n);
      ASSERT_EQ(result.points.cols(), 4);
      for (int k = 0; k < 4; ++k) {
        EXPECT_GE(result.points.col(k).minCoeff(), kFourAxes[k].low) << to_string(design) << " n " << n;
        EXPECT_LE(result.points.col(k).maxCoeff(), kFourAxes[k].high) << to_string(design) << " n " << n;
        EXPECT_GE(result.unit_points.col(k).minCoeff(), 0.0);
        EXPECT_LT(result.unit_points.col(k).maxCoeff(), 1.0);
      }
    }
  }
}

// McKay et al.'s property: on every axis, each of the n equal strata holds exactly one point.
TEST(SpaceFillingDesign, LatinHypercubeHasOnePointPerStratumOnEveryAxis) {
  for (const int n : {1, 2, 7, 50}) {
    const auto result = draw_design(request_of(SamplingDesign::kLatinHypercube, n, 11, kFourAxes));
    for (int k = 0; k < 4; ++k) {
      std::vector<int> count(static_cast<std::size_t>(n), 0);
      for (int i = 0; i < n; ++i) {
        // The stratum from the point in the parameter's own units.
        const double u = (result.points(i, k) - kFourAxes[k].low) / (kFourAxes[k].high - kFourAxes[k].low);
        ++count[static_cast<std::size_t>(std::min(n - 1, static_cast<int>(std::floor(u * n))))];
      }
      EXPECT_EQ(std::count(count.begin(), count.end(), 1), n) << "n " << n << " axis " << k;
    }
  }
}

// A maximin design spreads its points: its smallest pairwise distance must beat the median of the
// same count of uniform random points (31 sets: the median is a typical random set). Measured on
// 2 and 4 axes; the exchanges must also have lowered phi_p.
TEST(SpaceFillingDesign, LatinHypercubeMinimumDistanceBeatsRandomPoints) {
  for (const auto& [n, axes] : std::vector<std::pair<int, int>>{{10, 2}, {30, 2}, {30, 4}, {60, 4}}) {
    const std::vector<ParameterRange> box(kFourAxes.begin(), kFourAxes.begin() + axes);
    const auto design = draw_design(request_of(SamplingDesign::kLatinHypercube, n, 5, box));
    const double ours = min_pairwise_distance(design.unit_points);
    const double random = median_over_random_sets(n, axes, 31, min_pairwise_distance);
    std::printf("lhs n %d, %d axes: min distance %.4f, random median %.4f; phi_p %.3f -> %.3f (%d passes)\n", n,
                axes, ours, random, design.initial_phi_p, design.final_phi_p, design.passes);
    EXPECT_GT(ours, random) << "n " << n << " axes " << axes;
    EXPECT_LT(design.final_phi_p, design.initial_phi_p);
  }
}

// phi_p (p = 50) of the cell centres of a Latin hypercube's strata, computed directly.
double centre_phi_p(const Eigen::MatrixXi& strata) {
  const int n = static_cast<int>(strata.rows());
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double d2 = ((strata.row(i) - strata.row(j)).cast<double>() / n).squaredNorm();
      sum += std::pow(d2, -25.0);
    }
  }
  return std::pow(sum, 1.0 / 50.0);
}

// The exchange search ends at a local optimum: the reported phi_p is that of the result's cell
// centres, and no single exchange of two rows' strata on one axis lowers it (checked by trying
// them all).
TEST(SpaceFillingDesign, LatinHypercubeEndsAtALocalOptimumOfPhiP) {
  for (const auto& [n, axes] : std::vector<std::pair<int, int>>{{30, 2}, {40, 3}}) {
    const std::vector<ParameterRange> box(kFourAxes.begin(), kFourAxes.begin() + axes);
    const auto design = draw_design(request_of(SamplingDesign::kLatinHypercube, n, 9, box));
    ASSERT_LT(design.passes, 50) << "stopped by the pass budget, not at an optimum";
    Eigen::MatrixXi strata(n, axes);
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < axes; ++k) strata(i, k) = static_cast<int>(std::floor(design.unit_points(i, k) * n));
    }
    const double phi = centre_phi_p(strata);
    EXPECT_NEAR(design.final_phi_p, phi, 1e-12 * phi);
    double best = phi;
    for (int k = 0; k < axes; ++k) {
      for (int a = 0; a < n; ++a) {
        for (int b = a + 1; b < n; ++b) {
          std::swap(strata(a, k), strata(b, k));
          best = std::min(best, centre_phi_p(strata));
          std::swap(strata(a, k), strata(b, k));
        }
      }
    }
    EXPECT_GE(best, phi * (1.0 - 1e-9)) << "an exchange still lowers phi_p: n " << n << " axes " << axes;
  }
}

// A low-discrepancy sequence fills the box evenly: its centred L2 discrepancy must beat the median
// of uniform random sets of the same size.
TEST(SpaceFillingDesign, SobolDiscrepancyBeatsRandomPoints) {
  for (const auto& [n, axes] : std::vector<std::pair<int, int>>{{16, 2}, {50, 2}, {64, 4}, {100, 4}}) {
    const std::vector<ParameterRange> box(kFourAxes.begin(), kFourAxes.begin() + axes);
    for (const std::uint64_t seed : {1u, 2u}) {
      const auto design = draw_design(request_of(SamplingDesign::kSobol, n, seed, box));
      const double ours = centred_l2_discrepancy(design.unit_points);
      const double random = median_over_random_sets(n, axes, 31, centred_l2_discrepancy);
      std::printf("sobol n %d, %d axes, seed %d: CL2 discrepancy %.4f, random median %.4f\n", n, axes,
                  static_cast<int>(seed), ours, random);
      EXPECT_LT(ours, random) << "n " << n << " axes " << axes;
    }
  }
}

TEST(SpaceFillingDesign, MeasuresByHand) {
  Eigen::MatrixXd points(3, 2);
  points << 0.0, 0.0, 0.3, 0.4, 1.0, 1.0;
  EXPECT_DOUBLE_EQ(min_pairwise_distance(points), 0.5);
  EXPECT_TRUE(std::isinf(min_pairwise_distance(points.topRows(1))));
  // One point, one axis: CD^2 = 13/12 - 2 (1 + z/2 - z^2/2) + (1 + z) with z = |x - 1/2|:
  // x = 1/2 gives 1/12, x = 0 gives 13/12 - 9/4 + 3/2 = 1/3.
  Eigen::MatrixXd one(1, 1);
  one << 0.5;
  EXPECT_NEAR(centred_l2_discrepancy(one), std::sqrt(1.0 / 12.0), 1e-15);
  one << 0.0;
  EXPECT_NEAR(centred_l2_discrepancy(one), std::sqrt(1.0 / 3.0), 1e-15);
}

TEST(SpaceFillingDesign, BadRequestsAreRefused) {
  EXPECT_THROW(draw_design(request_of(SamplingDesign::kLatinHypercube, 0, 1, kHipBox)), Error);
  EXPECT_THROW(draw_design(request_of(SamplingDesign::kSobol, -3, 1, kHipBox)), Error);
  EXPECT_THROW(draw_design(request_of(SamplingDesign::kSobol, 4, 1, {})), Error);
  EXPECT_THROW(draw_design(request_of(SamplingDesign::kLatinHypercube, 4, 1, {{5.0, 5.0}})), Error);
  EXPECT_THROW(draw_design(request_of(SamplingDesign::kLatinHypercube, 4, 1, {{0.0, NAN}})), Error);
  EXPECT_THROW(draw_design(request_of(SamplingDesign::kSobol, 4, 1, std::vector<ParameterRange>(41))), Error);
  EXPECT_EQ(parse_sampling_design("lhs"), SamplingDesign::kLatinHypercube);
  EXPECT_EQ(parse_sampling_design("sobol"), SamplingDesign::kSobol);
  try {
    parse_sampling_design("halton");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "unknown design 'halton' (known: lhs, sobol)");
  }
}

}  // namespace
}  // namespace hipfai::stats
