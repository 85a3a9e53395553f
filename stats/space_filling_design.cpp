#include "stats/space_filling_design.h"

#include "core/error.h"
#include "core/literature.h"

#include <gsl/gsl_qrng.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>

namespace hipfai::stats {
namespace {

// The passes of the exchange search are a time budget, not a tuning: a pass tries every exchange of
// every axis; the search stops earlier at a local optimum (no exchange lowers phi_p), which designs
// of the sizes used here reach in a few passes.
constexpr int kMaximinMaxPasses = 50;
// GSL's Sobol generator keeps 30 binary digits per coordinate (SOBOL_BIT_COUNT in gsl/qrng/sobol.c):
// every value it returns is an integer over 2^30.
constexpr int kSobolBits = 30;
constexpr unsigned kSobolMaxAxes = 40;

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// A generator for (seed, stream): two splitmix64 steps mix both into the engine's seed.
std::mt19937_64 make_engine(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t state = seed;
  const std::uint64_t a = splitmix64(state);
  state ^= stream * 0xD1B54A32D192ED03ULL;
  const std::uint64_t b = splitmix64(state);
  std::seed_seq sequence{static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(a >> 32),
                         static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(b >> 32)};
  return std::mt19937_64(sequence);
}

// Uniform on [0, 1) from the top 53 bits (the standard's distributions are not portable).
double uniform01(std::mt19937_64& engine) { return static_cast<double>(engine() >> 11) * 0x1.0p-53; }

// Uniform integer in [0, bound), by rejection (no modulo bias).
std::uint64_t uniform_below(std::mt19937_64& engine, std::uint64_t bound) {
  const std::uint64_t limit = std::numeric_limits<std::uint64_t>::max() -
                              std::numeric_limits<std::uint64_t>::max() % bound;
  for (;;) {
    const std::uint64_t draw = engine();
    if (draw < limit) return draw % bound;
  }
}

// x^-e for a squared distance x and an integer e = p / 2, by squaring.
double inverse_power(double squared_distance, int exponent) {
  double result = 1.0, base = squared_distance;
  for (int e = exponent; e > 0; e >>= 1) {
    if (e & 1) result *= base;
    base *= base;
  }
  return 1.0 / result;
}

void check_request(const SamplingRequest& request) {
  if (request.n < 1) throw_error("sampling design: n = ", request.n, " must be at least 1");
  if (request.ranges.empty()) throw_error("sampling design: no parameter to vary");
  for (std::size_t k = 0; k < request.ranges.size(); ++k) {
    const ParameterRange& range = request.ranges[k];
    if (!std::isfinite(range.low) || !std::isfinite(range.high) || !(range.low < range.high)) {
      throw_error("sampling design: axis ", k + 1, " has range [", range.low, ", ", range.high,
                  "]; low must be below high, both finite");
    }
  }
  if (request.design == SamplingDesign::kSobol && request.ranges.size() > kSobolMaxAxes) {
    throw_error("sampling design: sobol supports at most ", kSobolMaxAxes, " parameters, not ",
                request.ranges.size());
  }
}

// Maximin Latin hypercube in the unit cube (header comment).
Eigen::MatrixXd latin_hypercube(int n, int axes, std::mt19937_64& engine, SamplingResult& result) {
  // strata(i, k): the stratum of point i on axis k; each column a permutation of 0..n-1.
  Eigen::MatrixXi strata(n, axes);
  for (int k = 0; k < axes; ++k) {
    for (int i = 0; i < n; ++i) strata(i, k) = i;
    for (int i = n - 1; i > 0; --i) {
      std::swap(strata(i, k), strata(static_cast<int>(uniform_below(engine, static_cast<std::uint64_t>(i) + 1)), k));
    }
  }
  auto centre = [n](int stratum) { return (stratum + 0.5) / n; };
  constexpr int half_power = literature::kMaximinPhiPower / 2;
  auto centre_distance2 = [&](int i, int j) {
    double d2 = 0.0;
    for (int k = 0; k < axes; ++k) d2 += std::pow(centre(strata(i, k)) - centre(strata(j, k)), 2);
    return d2;
  };
  Eigen::MatrixXd squared = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) squared(i, j) = squared(j, i) = centre_distance2(i, j);
  }
  auto phi_sum = [&] {
    double total = 0.0;
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) total += inverse_power(squared(i, j), half_power);
    }
    return total;
  };
  double sum = phi_sum();
  auto phi = [](double s) { return std::pow(s, 1.0 / literature::kMaximinPhiPower); };
  result.initial_phi_p = n > 1 ? phi(sum) : 0.0;
  // Exchanging the strata of rows a and b on axis k changes only the distances from a and from b.
  for (int pass = 0; pass < kMaximinMaxPasses && n > 2; ++pass) {
    bool improved = false;
    ++result.passes;
    for (int k = 0; k < axes; ++k) {
      for (int a = 0; a < n; ++a) {
        for (int b = a + 1; b < n; ++b) {
          const double ca = centre(strata(a, k)), cb = centre(strata(b, k));
          double delta = 0.0;
          for (int m = 0; m < n; ++m) {
            if (m == a || m == b) continue;
            const double cm = centre(strata(m, k));
            const double shift = (cb - cm) * (cb - cm) - (ca - cm) * (ca - cm);
            delta += inverse_power(squared(a, m) + shift, half_power) - inverse_power(squared(a, m), half_power) +
                     inverse_power(squared(b, m) - shift, half_power) - inverse_power(squared(b, m), half_power);
          }
          // Only a clear improvement counts: round-off of the sum must not make the search cycle.
          if (delta < -1e-10 * sum) {
            std::swap(strata(a, k), strata(b, k));
            // Recomputed, not updated by differences: the terms span many orders of magnitude
            // (d^-50), and a running sum would lose the small ones to cancellation.
            for (const int row : {a, b}) {
              for (int m = 0; m < n; ++m) {
                if (m != row) squared(row, m) = squared(m, row) = centre_distance2(row, m);
              }
            }
            sum = phi_sum();
            improved = true;
          }
        }
      }
    }
    if (!improved) break;
  }
  result.final_phi_p = n > 1 ? phi(sum) : 0.0;
  Eigen::MatrixXd unit(n, axes);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < axes; ++k) unit(i, k) = (strata(i, k) + uniform01(engine)) / n;
  }
  return unit;
}

// Sobol points 1..n (GSL skips point 0), digitally shifted by a mask per axis.
Eigen::MatrixXd sobol(int n, int axes, std::mt19937_64& engine) {
  constexpr double scale = 0x1.0p30;
  static_assert(kSobolBits == 30);
  std::vector<std::uint32_t> masks(static_cast<std::size_t>(axes));
  for (auto& mask : masks) mask = static_cast<std::uint32_t>(engine() >> (64 - kSobolBits));
  std::unique_ptr<gsl_qrng, decltype(&gsl_qrng_free)> generator(
      gsl_qrng_alloc(gsl_qrng_sobol, static_cast<unsigned>(axes)), &gsl_qrng_free);
  if (!generator) throw_error("sampling design: GSL cannot make a Sobol generator of ", axes, " axes");
  Eigen::MatrixXd unit(n, axes);
  std::vector<double> point(static_cast<std::size_t>(axes));
  for (int i = 0; i < n; ++i) {
    if (gsl_qrng_get(generator.get(), point.data()) != 0) {
      throw_error("sampling design: GSL's Sobol sequence ended at point ", i + 1);
    }
    for (int k = 0; k < axes; ++k) {
      const double digits = point[static_cast<std::size_t>(k)] * scale;
      // GSL's values are integers over 2^30 (see kSobolBits); anything else breaks the shift.
      if (digits != std::floor(digits) || digits < 0.0 || digits >= scale) {
        throw_error("sampling design: GSL's Sobol value ", point[static_cast<std::size_t>(k)],
                    " is not a 30-digit binary fraction");
      }
      const auto shifted = static_cast<std::uint32_t>(digits) ^ masks[static_cast<std::size_t>(k)];
      unit(i, k) = static_cast<double>(shifted) / scale;
    }
  }
  return unit;
}

}  // namespace

const char* to_string(SamplingDesign design) {
  switch (design) {
    case SamplingDesign::kLatinHypercube: return "lhs";
    case SamplingDesign::kSobol: return "sobol";
  }
  return "?";
}

SamplingDesign parse_sampling_design(const std::string& name) {
  for (const SamplingDesign design : kSamplingDesigns) {
    if (name == to_string(design)) return design;
  }
  throw_error("unknown design '", name, "' (known: lhs, sobol)");
}

SamplingResult draw_design(const SamplingRequest& request) {
  check_request(request);
  const int axes = static_cast<int>(request.ranges.size());
  std::mt19937_64 engine = make_engine(request.seed, request.stream);
  SamplingResult result;
  result.unit_points = request.design == SamplingDesign::kLatinHypercube
                           ? latin_hypercube(request.n, axes, engine, result)
                           : sobol(request.n, axes, engine);
  result.points.resize(request.n, axes);
  for (int k = 0; k < axes; ++k) {
    const ParameterRange& range = request.ranges[static_cast<std::size_t>(k)];
    for (int i = 0; i < request.n; ++i) {
      // Clamped: low + u (high - low) can round up to high for u just below 1.
      result.points(i, k) = std::min(range.high, range.low + result.unit_points(i, k) * (range.high - range.low));
    }
  }
  return result;
}

double min_pairwise_distance(const Eigen::MatrixXd& unit_points) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < unit_points.rows(); ++i) {
    for (Eigen::Index j = i + 1; j < unit_points.rows(); ++j) {
      best = std::min(best, (unit_points.row(i) - unit_points.row(j)).squaredNorm());
    }
  }
  return std::sqrt(best);
}

double centred_l2_discrepancy(const Eigen::MatrixXd& unit_points) {
  const Eigen::Index n = unit_points.rows(), axes = unit_points.cols();
  if (n < 1) throw_error("centred L2 discrepancy: no points");
  double single = 0.0, pairs = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    double product = 1.0;
    for (Eigen::Index k = 0; k < axes; ++k) {
      const double z = std::abs(unit_points(i, k) - 0.5);
      product *= 1.0 + 0.5 * z - 0.5 * z * z;
    }
    single += product;
    for (Eigen::Index j = 0; j < n; ++j) {
      double pair = 1.0;
      for (Eigen::Index k = 0; k < axes; ++k) {
        pair *= 1.0 + 0.5 * std::abs(unit_points(i, k) - 0.5) + 0.5 * std::abs(unit_points(j, k) - 0.5) -
                0.5 * std::abs(unit_points(i, k) - unit_points(j, k));
      }
      pairs += pair;
    }
  }
  const double nd = static_cast<double>(n);
  const double squared = std::pow(13.0 / 12.0, static_cast<double>(axes)) - 2.0 / nd * single + pairs / (nd * nd);
  return std::sqrt(std::max(0.0, squared));
}

}  // namespace hipfai::stats
