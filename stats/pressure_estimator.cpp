#include "stats/pressure_estimator.h"

#include "core/error.h"
#include "stats/ridge_regression.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hipfai::stats {

const char* to_string(EstimatorMethod method) {
  switch (method) {
    case EstimatorMethod::kPcaNn: return "pca_nn";
    case EstimatorMethod::kKnn: return "knn";
    case EstimatorMethod::kRidge: return "ridge";
    case EstimatorMethod::kDepthNn: return "depth_nn";
    case EstimatorMethod::kDepthAligned: return "depth_aligned";
  }
  return "?";
}

EstimatorMethod parse_estimator_method(const std::string& name) {
  for (const EstimatorMethod method : kEstimatorMethods) {
    if (name == to_string(method)) return method;
  }
  throw_error("unknown estimator method '", name, "' (pca_nn, knn, ridge, depth_nn, depth_aligned)");
}

namespace {

double significant_mahalanobis(const TrainedEstimator& model, const Eigen::VectorXd& scores) {
  double sum = 0.0;
  for (int k = 0; k < model.significant_components; ++k) {
    if (model.pca.variances(k) > 0.0) sum += scores(k) * scores(k) / model.pca.variances(k);
  }
  return std::sqrt(sum);
}

}  // namespace

void derive_estimator(TrainedEstimator& model) {
  model.scores = pca_scores(model.pca, model.features);
  model.correlations = score_value_correlations(model.scores, model.values);
  model.significant_components = 0;
  while (model.significant_components < model.pca.num_components() &&
         model.pca.variances(model.significant_components) >=
             model.settings.bordering_min_variance_share * model.pca.total_variance &&
         model.pca.variances(model.significant_components) > 0.0) {
    ++model.significant_components;
  }
  const int n = model.significant_components;
  model.score_min = model.scores.leftCols(n).colwise().minCoeff().transpose();
  model.score_max = model.scores.leftCols(n).colwise().maxCoeff().transpose();
  model.max_training_mahalanobis = 0.0;
  for (Eigen::Index i = 0; i < model.scores.rows(); ++i) {
    model.max_training_mahalanobis =
        std::max(model.max_training_mahalanobis, significant_mahalanobis(model, model.scores.row(i).transpose()));
  }
}

TrainedEstimator train_estimator(const Eigen::MatrixXd& features, const Eigen::MatrixXd& values,
                                 const EstimatorSettings& settings, const PenetrationDepths& depths) {
  if (features.rows() != values.rows()) {
    throw_error("estimator: ", features.rows(), " feature rows but ", values.rows(), " value rows");
  }
  if (depths.known() &&
      (depths.curvilinear_mm.rows() != values.rows() || depths.curvilinear_mm.cols() != values.cols() ||
       depths.radial_mm.rows() != values.rows() || depths.radial_mm.cols() != values.cols())) {
    throw_error("estimator: penetration depths are ", depths.curvilinear_mm.rows(), " x ", depths.curvilinear_mm.cols(),
                ", values ", values.rows(), " x ", values.cols());
  }
  if (features.rows() < 3) throw_error("estimator: ", features.rows(), " training hips; need at least 3");
  TrainedEstimator model;
  model.settings = settings;
  model.features = features;
  model.values = values;
  model.depths = depths;
  model.pca = fit_pca(features, settings.pca);
  derive_estimator(model);
  return model;
}

EstimateResult estimate(const TrainedEstimator& model, const Eigen::VectorXd& target_features,
                        EstimatorMethod method, int e_prime, const PenetrationDepths& target_depths) {
  if (e_prime < 1) throw_error("estimator: e' = ", e_prime, "; need at least 1");
  const Eigen::VectorXd target = pca_scores(model.pca, target_features.transpose()).row(0).transpose();
  EstimateResult result;
  result.mahalanobis = significant_mahalanobis(model, target);
  // A training hip lies on its own ranges' ends: its scores and distance, computed again, may
  // differ from the stored ones by round-off, which must not flag it (1e-9 of the range).
  constexpr double kRoundOff = 1e-9;
  for (int k = 0; k < model.significant_components; ++k) {
    const double slack = kRoundOff * std::max(1.0, model.score_max(k) - model.score_min(k));
    if (target(k) < model.score_min(k) - slack || target(k) > model.score_max(k) + slack) ++result.outside_components;
  }
  result.bordering = result.outside_components > 0 ||
                     result.mahalanobis > model.max_training_mahalanobis * (1.0 + kRoundOff);
  switch (method) {
    case EstimatorMethod::kPcaNn: {
      PcaNnOptions options;
      options.e_prime = e_prime;
      options.nearest = model.settings.nearest;
      for (const PcaNnStep& step : pca_nn_estimate(model.scores, model.values, model.correlations, target, options)) {
        result.steps.push_back({step.estimate, step.low, step.high, step.defined});
      }
      break;
    }
    case EstimatorMethod::kKnn:
      result.steps = knn_estimate(model.scores, model.values, target, e_prime, model.settings.knn_k);
      break;
    case EstimatorMethod::kRidge:
      result.steps = ridge_estimate(model.scores, model.pca.variances.cwiseSqrt(), model.values, target, e_prime);
      break;
    case EstimatorMethod::kDepthNn:
    case EstimatorMethod::kDepthAligned:
      if (!model.depths.known()) {
        throw_error("estimator: ", to_string(method), " needs the training hips' penetration depths, and this model "
                    "has none (trained from an FE table without max_curvilinear_mm / max_radial_mm)");
      }
      if (!target_depths.known()) throw_error("estimator: ", to_string(method), " needs the target's penetration depths");
      result.steps = method == EstimatorMethod::kDepthNn
                         ? depth_nn_estimate(model.scores, model.values, model.depths, target, target_depths, e_prime,
                                             model.settings.nearest)
                         : depth_aligned_estimate(model.scores, model.values, model.depths, target, target_depths,
                                                  e_prime, model.settings.nearest);
      break;
  }
  return result;
}

std::vector<LeaveOneOutRow> leave_one_out(const Eigen::MatrixXd& features, const Eigen::MatrixXd& values,
                                          const EstimatorSettings& settings, int max_e_prime,
                                          const std::vector<int>& held_out,
                                          const std::vector<EstimatorMethod>& methods_in,
                                          const PenetrationDepths& depths) {
  std::vector<EstimatorMethod> methods = methods_in;
  if (methods.empty()) {
    for (const EstimatorMethod method : kEstimatorMethods) {
      if (!needs_depths(method) || depths.known()) methods.push_back(method);
    }
  }
  const auto hips = static_cast<int>(features.rows());
  std::vector<int> targets = held_out;
  if (targets.empty()) {
    for (int i = 0; i < hips; ++i) targets.push_back(i);
  }
  std::vector<LeaveOneOutRow> rows;
  for (const int target : targets) {
    if (target < 0 || target >= hips) throw_error("leave-one-out: hip ", target, " out of range");
    Eigen::MatrixXd train_features(hips - 1, features.cols());
    Eigen::MatrixXd train_values(hips - 1, values.cols());
    PenetrationDepths train_depths, target_depths;
    if (depths.known()) {
      train_depths = {Eigen::MatrixXd(hips - 1, values.cols()), Eigen::MatrixXd(hips - 1, values.cols())};
      target_depths = {depths.curvilinear_mm.row(target), depths.radial_mm.row(target)};
    }
    for (int i = 0, r = 0; i < hips; ++i) {
      if (i == target) continue;
      train_features.row(r) = features.row(i);
      train_values.row(r) = values.row(i);
      if (depths.known()) {
        train_depths.curvilinear_mm.row(r) = depths.curvilinear_mm.row(i);
        train_depths.radial_mm.row(r) = depths.radial_mm.row(i);
      }
      ++r;
    }
    const TrainedEstimator model = train_estimator(train_features, train_values, settings, train_depths);
    for (const EstimatorMethod method : methods) {
      for (int e_prime = 1; e_prime <= max_e_prime; ++e_prime) {
        rows.push_back({target, method, e_prime,
                        estimate(model, features.row(target).transpose(), method, e_prime, target_depths)});
      }
    }
  }
  return rows;
}

double mean_abs_error_percent(const EstimateResult& result, const Eigen::VectorXd& values) {
  if (result.steps.size() < static_cast<std::size_t>(values.size()) || values.size() == 0) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  double sum = 0.0;
  for (Eigen::Index j = 0; j < values.size(); ++j) {
    if (!(std::isfinite(values[j]) && values[j] > 0.0)) return std::numeric_limits<double>::quiet_NaN();
    sum += std::abs(result.steps[static_cast<std::size_t>(j)].estimate - values[j]) / values[j];
  }
  return 100.0 * sum / static_cast<double>(values.size());
}

EPrimeSelection select_e_prime(const Eigen::MatrixXd& features, const Eigen::MatrixXd& values,
                               const EstimatorSettings& settings, EstimatorMethod method, int max_e_prime) {
  if (max_e_prime < 1) throw_error("e' selection: max e' must be at least 1");
  std::vector<int> complete;
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    bool ok = values.cols() > 0;
    for (Eigen::Index j = 0; j < values.cols(); ++j) ok = ok && std::isfinite(values(i, j)) && values(i, j) > 0.0;
    if (ok) complete.push_back(static_cast<int>(i));
  }
  EPrimeSelection selection;
  selection.e_prime = max_e_prime;
  if (complete.size() < 4) return selection;
  selection.hips = static_cast<int>(complete.size());
  std::vector<double> sum(static_cast<std::size_t>(max_e_prime), 0.0);
  for (const LeaveOneOutRow& row : leave_one_out(features, values, settings, max_e_prime, complete, {method})) {
    sum[static_cast<std::size_t>(row.e_prime - 1)] += mean_abs_error_percent(row.result, values.row(row.hip).transpose());
  }
  for (const double total : sum) selection.mean_error_percent.push_back(total / static_cast<double>(complete.size()));
  // The first smallest: a tie goes to the smaller e' (fewer components, the simpler model).
  const auto best = std::min_element(selection.mean_error_percent.begin(), selection.mean_error_percent.end());
  selection.e_prime = static_cast<int>(best - selection.mean_error_percent.begin()) + 1;
  return selection;
}

}  // namespace hipfai::stats
