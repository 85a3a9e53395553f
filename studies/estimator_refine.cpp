#include "studies/estimator_refine.h"

#include "core/error.h"

#include "geometry/hip_model.h"
#include "studies/validation_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

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
    if (options.exclude.count(std::filesystem::weakly_canonical(dir))) continue;
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

namespace {

std::size_t measure_index(const std::string& measure) {
  const auto& measures = validation_fe_measures();
  for (std::size_t m = 0; m < measures.size(); ++m) {
    if (fe_measure_name(measures[m]) == measure) return m;
  }
  throw_error("estimator refine: the model's measure ", measure, " is not one the FE tables give");
}

MethodCaseErrors no_errors() {
  MethodCaseErrors errors;
  for (auto& method : errors) method.fill(std::numeric_limits<double>::quiet_NaN());
  return errors;
}

}  // namespace

RefineLoopResult refine_estimator(EstimatorModel model, const RefineLoopOptions& options) {
  if (options.rounds < 1) throw_error("estimator refine: --rounds ", options.rounds, " must be at least 1");
  const int steps = static_cast<int>(model.angle_deg.size());
  const Motion motion = standing_to_sitting(steps);
  for (int j = 0; j < steps; ++j) {
    if (std::abs(motion.steps[static_cast<std::size_t>(j)].angle_deg - model.angle_deg[static_cast<std::size_t>(j)]) > 1e-6) {
      throw_error("estimator refine: the model's motion is not standing-to-sitting in ", steps,
                  " sub-motions, the motion whose FE refine runs");
    }
  }
  const std::size_t measure = measure_index(model.measure);
  std::vector<TrainingHip> held_out;
  if (!options.held_out.empty()) held_out = load_sample_hips(options.held_out, SampleSet::kHeldOut, model.measure, false);
  RefineLoopResult result;
  result.held_out_hips = static_cast<int>(held_out.size());
  const auto measure_model = [&](RefineRound& round) {
    round.training_hips = static_cast<int>(model.hips.size());
    round.held_out_error = held_out.empty() ? no_errors() : held_out_errors(model.estimator, held_out);
  };
  RefineRound start;
  measure_model(start);
  result.rounds.push_back(start);
  RefineOptions pick = options.pick;
  std::set<std::string> trained_hashes;
  for (const TrainingHip& hip : model.hips) trained_hashes.insert(hip.hash);
  // Never a candidate: a hip the model has trained on (same meshes), or a held-out hip.
  for (const TrainingHip& hip : held_out) pick.exclude.insert(std::filesystem::weakly_canonical(hip.dir));
  const std::set<std::string> tissues(model.grid.tissues.begin(), model.grid.tissues.end());
  for (const auto& dir : candidate_folders(pick.candidates)) {
    if (trained_hashes.count(hip_content_hash(geometry::load_hip_model(dir, tissues), model.grid))) {
      pick.exclude.insert(std::filesystem::weakly_canonical(dir));
    }
  }
  SampleFeOptions fe = options.fe;
  fe.steps = steps;
  const stats::EstimatorSettings settings = model.estimator.settings;
  for (int r = 1; r <= options.rounds; ++r) {
    const auto round_start = std::chrono::steady_clock::now();
    RefineRound round;
    round.round = r;
    const RefineResult picked = pick_refine_candidates(model, pick);
    std::vector<std::filesystem::path> dirs;
    for (const std::size_t index : picked.picked) dirs.push_back(picked.candidates[index].dir);
    if (dirs.empty()) break;
    const SampleFeResult truth = run_hips_fe(dirs, fe);
    round.fe_seconds = truth.seconds;
    for (const SampleFeHip& hip : truth.hips) {
      pick.exclude.insert(std::filesystem::weakly_canonical(hip.dir));
      if (!hip.error.empty()) {
        round.failed.push_back(hip.dir.filename().string() + ": " + hip.error);
        continue;
      }
      FeSweepHip values;
      values.edge_mm = std::numeric_limits<double>::quiet_NaN();
      values.values = hip.fe.at(measure);
      values.curvilinear_mm = hip.curvilinear_max_mm;
      values.radial_mm = hip.radial_max_mm;
      TrainingHip training = training_hip_from_folder(hip.dir, std::move(values), model.grid);
      if (!trained_hashes.insert(training.hash).second) continue;  // the same meshes as a training hip
      model.hips.push_back(std::move(training));
      round.added.push_back(hip.dir);
    }
    fit_estimator_model(model, settings);
    measure_model(round);
    round.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - round_start).count();
    result.rounds.push_back(std::move(round));
  }
  result.model = std::move(model);
  return result;
}

}  // namespace hipfai::studies
