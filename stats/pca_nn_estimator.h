// hipfai — the nearest-neighbour estimator of thesis §4.5.2 (Eq. 20-23) on PCA scores.
//
// Training: m hips with e PCA scores each (`scores`, m x e, stats/pca.h) and an FE quantity at p
// steps of the motion (`values`, m x p; NaN where a hip has no value at a step, e.g. an FE step that
// did not converge: that hip is left out of step j's correlations and candidate sets).
//
//   Eq. 20  CC(k, j) = Pearson r between score k and the value at step j over the training hips.
//   Eq. 21  HCC(e', j) = the e' components with the largest |CC(k, j)|. PCA leaves each component's
//           sign arbitrary (stats/pca.h), so a signed ranking would depend on that convention: a
//           component anti-correlated with pressure is as informative as a correlated one. Ties
//           and undefined r (zero variance, < 3 hips) rank last, lowest index first.
//   Eq. 22  For each k in HCC: the `nearest` (thesis: 4) training hips with the smallest DIST1 =
//           Euclidean distance over all e scores except k, and among them the one with the
//           smallest DIST2 = |score k difference| (ties: lowest hip index). That hip is CS_k.
//   Eq. 23  estimate(j) = sum_k w_k value(CS_k, j) / sum_k w_k with w_k = |CC(k, j)|: the
//           weighted AVERAGE the text describes (the printed Eq. 23 uses products, which is not an
//           average and not what the text says). Negative CC: weight |CC| (see Eq. 21). If every
//           chosen weight is 0 or undefined, the plain mean of the chosen hips' values.
// The interval reported with an estimate is the range (min, max) of the chosen hips' values at
// step j: the estimate, a convex combination, always lies inside it.
#pragma once

#include "core/literature.h"

#include <Eigen/Core>

#include <vector>

namespace hipfai::stats {

struct PcaNnOptions {
  int e_prime = literature::kEstimatorEffectiveFeatures;  // components used (thesis: 1..10); capped at e
  int nearest = literature::kEstimatorNearestSets;         // DIST1 shortlist size (thesis: 4, "chosen by trial")
};

struct PcaNnStep {
  double estimate = 0.0;
  double low = 0.0, high = 0.0;   // range of the chosen hips' values
  std::vector<int> components;    // HCC(e', j), by decreasing |CC|
  std::vector<int> chosen_hips;   // CS_k for each of `components` (training row index)
  std::vector<double> weights;    // |CC(k, j)| for each of `components`
  bool defined = false;           // false when no training hip has a value at this step
};

// Eq. 20: e x p matrix of Pearson r (NaN where undefined).
Eigen::MatrixXd score_value_correlations(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values);

// Eq. 21: indices of the e' components with the largest |r| in `correlations_at_step` (length e).
std::vector<int> highest_correlated(const Eigen::VectorXd& correlations_at_step, int e_prime);

// Eq. 22: CS_k among the rows `candidates` of `scores`. Throws hipfai::Error if candidates is empty.
int closest_set(const Eigen::MatrixXd& scores, const std::vector<int>& candidates,
                const Eigen::VectorXd& target, int k, int nearest);

// Eq. 21-23 for every step. `correlations` from score_value_correlations(scores, values).
// Throws hipfai::Error on shape mismatches or non-finite scores.
std::vector<PcaNnStep> pca_nn_estimate(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values,
                                       const Eigen::MatrixXd& correlations, const Eigen::VectorXd& target,
                                       const PcaNnOptions& options);

}  // namespace hipfai::stats
