// hipfai — principal component analysis of a feature matrix (thesis §4.5.2.1, Eq. 18-19).
//
// Rows are samples (hips), columns features. fit_pca() normalises every feature (subtracts its
// training mean, divides by its training standard deviation floored at `scale_floor`, see
// PcaOptions) and keeps the `components` directions of largest variance, from the thin SVD of the
// normalised matrix (Eigen::JacobiSVD; exact for the few dozen rows a study has). The SAME mean,
// scale and basis are then applied to any other sample (Eq. 19: the target is projected with the
// training PCA, never refitted).
//
// Sign convention: SVD leaves each component's sign free; we flip each basis vector so that its
// entry of largest magnitude is positive (ties: lowest index), so a refit on the same data gives
// the same scores. Nothing downstream may depend on the sign (the estimator ranks by |r|).
#pragma once

#include "core/literature.h"

#include <Eigen/Core>

namespace hipfai::stats {

struct PcaOptions {
  // e (thesis: 10); capped at min(rows - 1, columns) and at the numerical rank of the normalised
  // samples (fewer components when the samples span fewer directions).
  int components = literature::kEstimatorEffectiveFeatures;
  // Features whose training standard deviation is below this are divided by it instead (units of
  // the features). 0 = plain z-scores. A positive floor keeps features that vary only by noise
  // (mesh discretisation) from being blown up to unit variance.
  double scale_floor = 0.0;
};

struct Pca {
  Eigen::VectorXd mean;       // f, training mean of each feature
  Eigen::VectorXd scale;      // f, divisor of each feature (std floored at scale_floor, or 1 if 0)
  Eigen::MatrixXd basis;      // f x e, orthonormal columns, by decreasing variance
  Eigen::VectorXd variances;  // e, variance of each score over the training rows (n - 1 divisor)
  double total_variance = 0;  // sum of the variances of all normalised features

  int num_features() const { return static_cast<int>(mean.size()); }
  int num_components() const { return static_cast<int>(basis.cols()); }
};

// Fits the PCA of `samples` (n x f). Throws hipfai::Error when n < 2, f < 1, a value is not
// finite, or options.components < 1.
Pca fit_pca(const Eigen::MatrixXd& samples, const PcaOptions& options);

// Scores (Eq. 18-19) of each row of `samples` (n x f) -> n x e. Throws hipfai::Error on a column
// count different from the fit's.
Eigen::MatrixXd pca_scores(const Pca& pca, const Eigen::MatrixXd& samples);

// Mahalanobis distance of one score vector (length e) from the training centre in the PCA's own
// metric: sqrt(sum_k score_k^2 / variance_k) (components with zero variance are skipped). The
// estimators flag a target whose distance exceeds every training hip's as bordering.
double score_mahalanobis(const Pca& pca, const Eigen::VectorXd& scores);

}  // namespace hipfai::stats
