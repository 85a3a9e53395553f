#include "studies/estimator_refine.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>

namespace hipfai::studies {
namespace {

std::vector<std::filesystem::path> candidate_folders(const std::filesystem::path& folder) {
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) throw_error(folder.string(), ": no such folder of candidate hips");
  std::vector<std::filesystem::path> dirs;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (!entry.is_directory() || entry.path().extension() == ".partial") continue;
    if (std::filesystem::is_regular_file(entry.path() / "model.json", ec)) dirs.push_back(entry.path());
  }
  std::sort(dirs.begin(), dirs.end());
  if (dirs.empty()) throw_error(folder.string(), ": no hip folder (with model.json) among its candidates");
  return dirs;
}

std::vector<stats::EstimatorMethod> methods_of(const EstimatorModel& model) {
  std::vector<stats::EstimatorMethod> methods;
  for (const stats::EstimatorMethod method : stats::kEstimatorMethods) {
    if (!stats::needs_depths(method) || model.estimator.depths.known()) methods.push_back(method);
  }
  return methods;
}

}  // namespace

RefineResult pick_refine_candidates(const EstimatorModel& model, const RefineOptions& options) {
  if (options.budget < 1) throw_error("estimator refine: --budget ", options.budget, " must be at least 1");
  const int e_prime = model.estimator.pca.num_components();
  const std::vector<stats::EstimatorMethod> methods =
      options.criterion == stats::UncertaintyCriterion::kIntervalWidth ? std::vector{options.method}
                                                                        : methods_of(model);
  RefineResult result;
  std::vector<stats::CandidatePrediction> predictions;
  for (const auto& dir : candidate_folders(options.candidates)) {
    stats::CandidatePrediction prediction;
    for (const stats::EstimatorMethod method : methods) {
      const HipPrediction hip = predict_hip(model, dir, method, e_prime);
      std::vector<double> estimates;
      for (const auto& step : hip.result.steps) {
        estimates.push_back(step.defined ? step.estimate : std::nan(""));
        if (method == options.method) {
          prediction.low.push_back(step.defined ? step.low : std::nan(""));
          prediction.high.push_back(step.defined ? step.high : std::nan(""));
        }
      }
      prediction.estimates.push_back(std::move(estimates));
    }
    result.candidates.push_back({dir, stats::uncertainty_score(prediction, options.criterion), 0});
    predictions.push_back(std::move(prediction));
  }
  result.picked = stats::least_certain(predictions, options.criterion, options.budget);
  for (std::size_t r = 0; r < result.picked.size(); ++r) result.candidates[result.picked[r]].rank = static_cast<int>(r) + 1;
  return result;
}

}  // namespace hipfai::studies
