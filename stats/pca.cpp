#include "stats/pca.h"

#include "core/error.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>

namespace hipfai::stats {

Pca fit_pca(const Eigen::MatrixXd& samples, const PcaOptions& options) {
  const Eigen::Index rows = samples.rows();
  const Eigen::Index cols = samples.cols();
  if (rows < 2) throw_error("PCA: ", rows, " samples; need at least 2");
  if (cols < 1) throw_error("PCA: no features");
  if (options.components < 1) throw_error("PCA: ", options.components, " components requested");
  if (!samples.allFinite()) throw_error("PCA: a feature value is not finite");
  if (!(options.scale_floor >= 0.0)) throw_error("PCA: scale floor ", options.scale_floor, " < 0");

  Pca pca;
  pca.mean = samples.colwise().mean().transpose();
  Eigen::MatrixXd centred = samples.rowwise() - pca.mean.transpose();
  pca.scale.resize(cols);
  for (Eigen::Index l = 0; l < cols; ++l) {
    const double sd = std::sqrt(centred.col(l).squaredNorm() / static_cast<double>(rows - 1));
    double scale = std::max(sd, options.scale_floor);
    if (scale == 0.0) scale = 1.0;  // a constant feature: its normalised values are all 0
    pca.scale(l) = scale;
  }
  const Eigen::MatrixXd normalised = centred.array().rowwise() / pca.scale.transpose().array();
  pca.total_variance = normalised.squaredNorm() / static_cast<double>(rows - 1);

  Eigen::JacobiSVD<Eigen::MatrixXd> svd(normalised, Eigen::ComputeThinV);
  // Directions past the numerical rank carry round-off, not data: their scores are noise that a
  // ranking by correlation could pick and a per-component scaling would blow up (e.g. hips whose
  // sampled tissues are identical copies). They are not kept. Rank = singular values above 1e-9
  // of the largest (variance ratio 1e-18): round-off of the SVD and of the centring sits near
  // 1e-15, and no feature that varies by data (>= the 1e-3 mm of a mesh coordinate against tens of
  // mm) comes near 1e-9.
  svd.setThreshold(1e-9);
  const Eigen::Index rank = svd.rank();
  if (rank == 0) throw_error("PCA: the ", rows, " samples are identical (to rounding); nothing varies");
  const Eigen::Index keep =
      std::min<Eigen::Index>({static_cast<Eigen::Index>(options.components), rows - 1, cols, rank});
  pca.basis = svd.matrixV().leftCols(keep);
  pca.variances = svd.singularValues().head(keep).array().square() / static_cast<double>(rows - 1);
  for (Eigen::Index k = 0; k < keep; ++k) {
    Eigen::Index largest = 0;
    for (Eigen::Index l = 1; l < cols; ++l) {
      if (std::abs(pca.basis(l, k)) > std::abs(pca.basis(largest, k))) largest = l;
    }
    if (pca.basis(largest, k) < 0.0) pca.basis.col(k) *= -1.0;
  }
  return pca;
}

Eigen::MatrixXd pca_scores(const Pca& pca, const Eigen::MatrixXd& samples) {
  if (samples.cols() != pca.num_features()) {
    throw_error("PCA: ", samples.cols(), " features given, the PCA was fitted on ", pca.num_features());
  }
  const Eigen::MatrixXd normalised =
      (samples.rowwise() - pca.mean.transpose()).array().rowwise() / pca.scale.transpose().array();
  return normalised * pca.basis;
}

double score_mahalanobis(const Pca& pca, const Eigen::VectorXd& scores) {
  if (scores.size() != pca.num_components()) {
    throw_error("PCA: ", scores.size(), " scores given, the PCA has ", pca.num_components(), " components");
  }
  double sum = 0.0;
  for (Eigen::Index k = 0; k < scores.size(); ++k) {
    if (pca.variances(k) > 0.0) sum += scores(k) * scores(k) / pca.variances(k);
  }
  return std::sqrt(sum);
}

}  // namespace hipfai::stats
