// hipfai — ridge regression on PCA scores with a predictive interval: the regression baseline
// beside the thesis' estimator (stats/pca_nn_estimator.h).
//
// Per step j, over the training hips with a value at j: value = b0 + w . z, where z are the first
// `components` scores each divided by its training standard deviation (so one penalty suits all),
// b0 is not penalised (data centred), and w minimises |y - b0 - Z w|^2 + lambda |w|^2. lambda is
// chosen per step from a fixed log grid (1e-3 .. 1e3, 13 values) by the exact leave-one-out error
// of ridge (residual_i / (1 - H_ii)), so nothing is tuned on the target.
// Interval: estimate +- t(0.975, n - 1 - df) * s * sqrt(1 + 1/n + z0' (Z'Z + lambda I)^-1 z0),
// with df = trace of the hat matrix and s^2 = RSS / (n - 1 - df) (the Bayesian predictive form with
// prior variance s^2 / lambda, a little wider than the frequentist one). Undefined (NaN bounds)
// when n - 1 - df < 1 (too few hips for the fit's effective parameters).
#pragma once

#include "stats/knn_regression.h"

#include <Eigen/Core>

#include <vector>

namespace hipfai::stats {

struct RidgeStepFit {
  double lambda = 0.0;
  double loo_rmse = 0.0;  // leave-one-out RMS error of the chosen lambda (training hips)
};

// `score_sd`: standard deviation of each score over the training hips (e.g. sqrt of
// Pca::variances). Throws hipfai::Error on shape mismatches or components < 1.
std::vector<RegressionStep> ridge_estimate(const Eigen::MatrixXd& scores, const Eigen::VectorXd& score_sd,
                                           const Eigen::MatrixXd& values, const Eigen::VectorXd& target,
                                           int components, std::vector<RidgeStepFit>* fits = nullptr);

}  // namespace hipfai::stats
