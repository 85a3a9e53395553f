// hipfai — a mesh-objective peak of a sampled field: the largest average over a ball of fixed
// radius (for the mesh convergence of the hip FE model's peak values, docs/fem-levels.md).
//
// Why: the hip model's largest von Mises stresses sit at bonded re-entrant edges (the
// chondrolabral junction, the labrum's base on the rim), where the linear elastic field is
// singular, sigma ~ rho^(lambda - 1) with 0 < lambda < 1 at the distance rho from the edge
// (Williams 1952, J. Appl. Mech. 19:526; Bogy 1971, J. Appl. Mech. 38:377 for bonded materials).
// A Gauss-point maximum there grows without bound as the mesh is refined. The singularity is
// integrable, so the field's mean over a ball of fixed physical radius r has a limit: that is
// the "volume method" of the theory of critical distances (Taylor 2007, The Theory of Critical
// Distances, Elsevier; Sheppard 1991, J. Mech. Des. 113:188), whose peak we report next to
// the raw maximum. The same construction on the contact surface (area-weighted mean of the nodal
// pressure over a ball, i.e. contact force over contact area within the ball) gives a peak
// pressure that does not depend on the size of one node's tributary area.
//
// Definition: for samples (x_i, v_i, w_i), with B(i) = { j : |x_j - x_i| <= r },
//   peak = max_i  sum_{j in B(i)} w_j v_j / sum_{j in B(i)} w_j.
// The ball is closed (a sample at distance exactly r belongs to it) and always holds its own
// centre. Ties go to the lowest sample index. Only the samples given take part: call once per
// tissue so that a ball at a tissue boundary does not reach into the neighbouring tissue.
//
// Cost: samples are binned on a uniform grid of cell size r, so each ball visits the 27 cells
// around its centre: O(N * samples per ball), not O(N^2).
#pragma once

#include "geometry/tri_mesh.h"

#include <cstddef>
#include <vector>

namespace hipfai::fem {

// One sample of a scalar field.
struct FieldSample {
  geometry::Vec3 position_mm = geometry::Vec3::Zero();
  double value = 0.0;   // any unit (MPa for stresses and pressures)
  double weight = 0.0;  // > 0: JxW (mm^3) at a Gauss point, tributary area (mm^2) at a node
};

// The ball around one sample.
struct BallAverage {
  double value = 0.0;       // weighted mean of the values in the ball
  std::size_t samples = 0;  // samples in the ball, including the centre
  double weight = 0.0;      // sum of their weights
};

struct BallPeak {
  bool found = false;      // false only for no samples; then every number below is 0
  double value = 0.0;      // largest ball average, in the unit of the samples' values
  std::size_t sample = 0;  // index of the ball's centre sample
  geometry::Vec3 position_mm = geometry::Vec3::Zero();  // its position
  std::size_t samples_in_ball = 0;                      // including the centre
  double ball_weight = 0.0;                             // sum of the weights in the ball
};

// The ball average around every sample (same order as `samples`).
// @param[in] samples    #N samples; positions and values finite, weights finite and > 0
// @param[in] radius_mm  ball radius, finite and > 0
// Throws hipfai::Error for a radius that is not finite and > 0, a non-finite position or value,
// a weight that is not finite and > 0 (naming the sample), or a radius so small against the
// samples' extent that the grid's cell index would overflow.
std::vector<BallAverage> ball_averages(const std::vector<FieldSample>& samples, double radius_mm);

// The peak ball average of `samples` over balls of radius `radius_mm` (see above): the largest
// of ball_averages(), with its centre. No samples: found = false. Throws as ball_averages().
BallPeak ball_averaged_peak(const std::vector<FieldSample>& samples, double radius_mm);

}  // namespace hipfai::fem
