// hipfai — refining an estimator where it is weak. The selection step: among candidate hips (model
// folders not yet trained on, e.g. from `estimator sample`), the `budget` whose predictions by a
// trained model are least certain (stats/uncertainty_sampling.h): the widest intervals of one
// method, or the largest disagreement between the model's methods (pca_nn, knn, ridge, and depth_nn
// when the model has the training hips' penetration depths). The loop (refine_estimator): pick,
// run the picked hips' penetration depths and FE (studies/estimator_sample_fe.h, through the FE
// cache), add them to the model, retrain, and measure the error on a held-out set after each round.
#pragma once

#include "stats/pressure_estimator.h"
#include "stats/uncertainty_sampling.h"
#include "studies/estimator_holdout.h"
#include "studies/estimator_sample_fe.h"
#include "studies/estimator_study.h"

#include <set>

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

struct RefineOptions {
  std::filesystem::path candidates;  // a folder of hip folders (model.json; *.partial skipped)
  int budget = 1;
  stats::UncertaintyCriterion criterion = stats::UncertaintyCriterion::kIntervalWidth;
  stats::EstimatorMethod method = stats::EstimatorMethod::kPcaNn;  // whose interval kIntervalWidth reads
  std::set<std::filesystem::path> exclude;  // candidate folders not to consider (trained on already)
};

struct RefineCandidate {
  std::filesystem::path dir;
  double score = 0.0;  // the criterion's value (MPa for pressure); NaN when undefined
  int rank = 0;        // 1 = least certain; 0 = not picked
};

struct RefineResult {
  std::vector<RefineCandidate> candidates;  // in folder-name order
  std::vector<std::size_t> picked;          // indices into candidates, least certain first
};

// Throws hipfai::Error when the folder holds no hip folder, on budget < 1, or when a candidate
// cannot be predicted (its message names the folder).
RefineResult pick_refine_candidates(const EstimatorModel& model, const RefineOptions& options);

struct RefineLoopOptions {
  RefineOptions pick;              // candidates, budget per round, criterion, method
  int rounds = 1;
  SampleFeOptions fe;              // level, cache, jobs, program (steps: the model's motion)
  // An `estimator sample` folder with FE whose held-out hips (held_out_steps.csv) measure the
  // model after each round; empty: no measurement.
  std::filesystem::path held_out;
};

struct RefineRound {
  int round = 0;                                // 0: the model as given
  int training_hips = 0;
  std::vector<std::filesystem::path> added;     // hips picked and trained on in this round
  std::vector<std::string> failed;              // picked hips whose FE failed (not trained on)
  MethodCaseErrors held_out_error{};            // NaN when no held-out set
  double fe_seconds = 0, seconds = 0;
};

struct RefineLoopResult {
  EstimatorModel model;             // the model after the last round
  std::vector<RefineRound> rounds;  // round 0 first
  int held_out_hips = 0;
};

// Throws hipfai::Error on rounds < 1, a model whose motion is not standing-to-sitting (the FE runs
// it), or an unusable held-out folder; a picked hip whose FE fails is reported in its round and
// left out.
RefineLoopResult refine_estimator(EstimatorModel model, const RefineLoopOptions& options);

}  // namespace hipfai::studies
