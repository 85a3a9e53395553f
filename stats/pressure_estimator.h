// hipfai — a trained contact-pressure estimator (thesis §4.5): the PCA of the training hips'
// features, their scores and FE values, and the ways to estimate a target from them (the thesis'
// PCA nearest-neighbour method, two baselines on the same scores, and depth_nn, which adds the
// penetration depths of thesis §4.3), with the bordering flag. Numbers only: features come from
// studies/pressure_features.h, depths from studies/pipeline/penetration_run.h.
#pragma once

#include "core/literature.h"
#include "stats/depth_nn_estimator.h"
#include "stats/knn_regression.h"
#include "stats/pca.h"
#include "stats/pca_nn_estimator.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace hipfai::stats {

enum class EstimatorMethod { kPcaNn, kKnn, kRidge, kDepthNn, kDepthAligned };

// "pca_nn", "knn", "ridge", "depth_nn", "depth_aligned" (the `method` column of the output files).
const char* to_string(EstimatorMethod method);
// Inverse of to_string; throws hipfai::Error naming the accepted values.
EstimatorMethod parse_estimator_method(const std::string& name);
inline constexpr EstimatorMethod kEstimatorMethods[] = {EstimatorMethod::kPcaNn, EstimatorMethod::kKnn,
                                                        EstimatorMethod::kRidge, EstimatorMethod::kDepthNn,
                                                        EstimatorMethod::kDepthAligned};
inline constexpr int kNumEstimatorMethods = 5;
// depth_nn and depth_aligned need the penetration depths of the training hips and of the target.
inline bool needs_depths(EstimatorMethod method) {
  return method == EstimatorMethod::kDepthNn || method == EstimatorMethod::kDepthAligned;
}

struct EstimatorSettings {
  PcaOptions pca;   // e = pca.components (thesis: 10)
  int nearest = literature::kEstimatorNearestSets;  // Eq. 22 shortlist (thesis: 4)
  int knn_k = literature::kEstimatorNearestSets;    // kNN baseline's k: the thesis' shortlist size, like for like
  // Bordering check: only components carrying at least this share of the total variance count
  // (the others hold mesh jitter, in which every hip is "extreme" somewhere).
  double bordering_min_variance_share = 0.02;
};

struct TrainedEstimator {
  EstimatorSettings settings;
  Pca pca;
  Eigen::MatrixXd features;      // m x f training features (kept for retraining and provenance)
  Eigen::MatrixXd scores;        // m x e
  Eigen::MatrixXd values;        // m x p FE values, NaN = missing
  PenetrationDepths depths;      // m x p each, or empty (unknown: depth_nn unavailable)
  Eigen::MatrixXd correlations;  // e x p, Eq. 20
  // Bordering reference over the significant components (variance share >= the setting):
  int significant_components = 0;            // the first n components (variances decrease)
  Eigen::VectorXd score_min, score_max;      // training range of each significant component
  double max_training_mahalanobis = 0.0;     // largest training distance over those components
};

// Throws hipfai::Error on shape mismatches (rows differ; depths, when given, not m x p), fewer
// than 3 hips, or non-finite features.
TrainedEstimator train_estimator(const Eigen::MatrixXd& features, const Eigen::MatrixXd& values,
                                 const EstimatorSettings& settings, const PenetrationDepths& depths = {});

// Rebuilds the derived members (scores, correlations, distances) of a model read back from a file:
// the same arithmetic as train_estimator, so a reloaded model predicts bit-identically.
void derive_estimator(TrainedEstimator& model);

struct EstimateResult {
  std::vector<RegressionStep> steps;  // one per step of the training values
  // BORDERING (the thesis' word, §4.5.4, for targets without enough training hips around them):
  // on some significant component the target's score lies outside the training range, or its
  // Mahalanobis distance over the significant components exceeds every training hip's. Either
  // puts it outside the training set's hull in PCA space.
  double mahalanobis = 0.0;
  int outside_components = 0;         // significant components whose training range it leaves
  bool bordering = false;
};

// e' components: pca_nn ranks them by |CC| (Eq. 21); knn, ridge and depth_nn take the first e' by
// variance. `target_depths` (1 x p each) is read by depth_nn only. Throws hipfai::Error on a
// feature count different from the training's, e' < 1, or depth_nn without depths (the model's or
// the target's).
EstimateResult estimate(const TrainedEstimator& model, const Eigen::VectorXd& target_features,
                        EstimatorMethod method, int e_prime, const PenetrationDepths& target_depths = {});

struct LeaveOneOutRow {
  int hip = 0;  // row of the held-out hip
  EstimatorMethod method = EstimatorMethod::kPcaNn;
  int e_prime = 1;
  EstimateResult result;
};

// Leave-one-out (thesis §4.5.3.4): each hip of `held_out` (empty: every row) is estimated by a
// model trained on all the other rows (PCA refitted without it), for every method of `methods`
// (empty: all of them; depth_nn only when `depths` are known) and e' = 1..max_e_prime. `values`
// may hold NaN (missing steps); `depths`, when known, is m x p like `values`. Rows ordered hip,
// method, e'.
std::vector<LeaveOneOutRow> leave_one_out(const Eigen::MatrixXd& features, const Eigen::MatrixXd& values,
                                          const EstimatorSettings& settings, int max_e_prime,
                                          const std::vector<int>& held_out = {},
                                          const std::vector<EstimatorMethod>& methods = {},
                                          const PenetrationDepths& depths = {});

// Mean relative error (%) of one leave-one-out estimate: mean over the steps of
// |estimate - value| / value; NaN when a value is missing or not positive.
double mean_abs_error_percent(const EstimateResult& result, const Eigen::VectorXd& values);

// e' chosen from training hips alone (the thesis fixes e' = 10 after looking at its results,
// Figs. 73-74; this chooses without the target): leave-one-out inside the given hips, for
// e' = 1..max_e_prime, keeps the e' with the smallest mean error over the hips whose values are
// all positive (ties: the smaller e'). With fewer than 4 such hips (3 to train one model) there is
// nothing to choose from: max_e_prime, with empty errors.
struct EPrimeSelection {
  int e_prime = 1;
  std::vector<double> mean_error_percent;  // [e' - 1], over the hips used
  int hips = 0;                            // hips the choice was made on
};
EPrimeSelection select_e_prime(const Eigen::MatrixXd& features, const Eigen::MatrixXd& values,
                               const EstimatorSettings& settings, EstimatorMethod method, int max_e_prime);

}  // namespace hipfai::stats
