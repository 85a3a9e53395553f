// hipfai — k-nearest-neighbour regression on PCA scores: the plain baseline beside the thesis'
// estimator (stats/pca_nn_estimator.h). Same inputs: training scores (m x e), values (m x p, NaN =
// missing), a target's scores. Per step j, among the hips with a value at j, the k nearest to the
// target by Euclidean distance over the first `components` scores (ties: lowest row); the estimate
// is their plain mean, the interval their range (min, max).
#pragma once

#include <Eigen/Core>

#include <vector>

namespace hipfai::stats {

struct RegressionStep {
  double estimate = 0.0;
  double low = 0.0, high = 0.0;  // interval (method-specific; see each header)
  bool defined = false;          // false when there were too few training values at the step
};

// Throws hipfai::Error on shape mismatches, k < 1 or components < 1.
std::vector<RegressionStep> knn_estimate(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values,
                                         const Eigen::VectorXd& target, int components, int k);

}  // namespace hipfai::stats
