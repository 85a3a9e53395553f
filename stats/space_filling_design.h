// hipfai — space-filling designs over a box of parameters: where to put the hips of a training set
// so that n of them cover the parameter space evenly (design of computer experiments).
//
// Two designs, both reproducible from a seed:
//   kLatinHypercube  maximin Latin hypercube. Each axis is cut into n equal strata and every stratum
//                    of every axis holds exactly one point (McKay, Beckman & Conover 1979). Which
//                    strata go together is optimised for space filling: starting from random
//                    permutations, two rows' strata of one axis are exchanged whenever that lowers
//                    the phi_p criterion of the cell centres, sum over pairs of d_ij^-p to the 1/p,
//                    d in the unit cube (Morris & Mitchell 1995; p = literature::kMaximinPhiPower),
//                    until no exchange helps (a local optimum; at most 50 passes over all
//                    exchanges, a time budget). Each point is then drawn uniformly inside its cell
//                    (not centred), so two designs share a point with probability zero, and the
//                    strata property holds as stated.
//   kSobol           the Sobol low-discrepancy sequence (GSL gsl_qrng_sobol, at most 40 axes; GSL
//                    skips the all-zero first point), randomised by a digital shift: each
//                    coordinate's 30 binary digits are XOR-ed with a mask drawn from the seed.
//                    A digital shift keeps the sequence's net structure (its dyadic strata stay
//                    balanced), and different seeds or streams give independent shifted sets.
//
// `stream` draws independent sets from one seed (a training set on stream 0, a held-out set on
// stream 1): the random source is seeded from (seed, stream) through splitmix64, so the streams of
// one seed are unrelated sequences. Random numbers come from std::mt19937_64, whose output the C++
// standard fixes, and are turned into uniforms and shuffles here, so the points are the same on
// every platform.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hipfai::stats {

enum class SamplingDesign { kLatinHypercube, kSobol };
inline constexpr std::array<SamplingDesign, 2> kSamplingDesigns{SamplingDesign::kLatinHypercube,
                                                                SamplingDesign::kSobol};
// "lhs", "sobol".
const char* to_string(SamplingDesign design);
// Throws hipfai::Error "unknown design 'x' (known: lhs, sobol)".
SamplingDesign parse_sampling_design(const std::string& name);

// One axis of the box: values from `low` to `high` (low < high, both finite).
struct ParameterRange {
  double low = 0.0;
  double high = 1.0;
};

struct SamplingRequest {
  std::vector<ParameterRange> ranges;  // one per axis, at least one
  int n = 0;                           // number of points, >= 1
  std::uint64_t seed = 0;
  std::uint64_t stream = 0;            // independent sets from one seed (header comment)
  SamplingDesign design = SamplingDesign::kLatinHypercube;
};

struct SamplingResult {
  // n x d: row i is point i, column k its value on axis k, inside [low_k, high_k].
  Eigen::MatrixXd points;
  // The same points in the unit cube [0, 1)^d (value - low) / (high - low), where the design's
  // properties are stated and measured.
  Eigen::MatrixXd unit_points;
  // Latin hypercube only: phi_p of the cell centres before and after the exchanges, and the passes
  // made (0 for Sobol).
  double initial_phi_p = 0.0, final_phi_p = 0.0;
  int passes = 0;
};

// Throws hipfai::Error on n < 1, no axis, a range with low >= high or not finite, or more axes
// than the design supports (Sobol: 40).
SamplingResult draw_design(const SamplingRequest& request);

// Measures of space filling, on points in the unit cube (n x d).
// Smallest Euclidean distance between two points (maximin designs make it large); +inf for n < 2.
double min_pairwise_distance(const Eigen::MatrixXd& unit_points);
// Hickernell's (1998) centred L2 discrepancy, the closed form
//   CD^2 = (13/12)^d - 2/n sum_i prod_k (1 + |z_ik|/2 - z_ik^2/2)
//          + 1/n^2 sum_i sum_j prod_k (1 + |z_ik|/2 + |z_jk|/2 - |x_ik - x_jk|/2),  z = x - 1/2;
// returns CD (small = uniform; low-discrepancy sequences make it small). Throws on n < 1.
double centred_l2_discrepancy(const Eigen::MatrixXd& unit_points);

}  // namespace hipfai::stats
