// hipfai — the selection step of refining an estimator: among candidate hips (model folders not
// yet trained on, e.g. from `estimator sample`), the `budget` whose predictions by a trained model
// are least certain (stats/uncertainty_sampling.h): the widest intervals of one method, or the
// largest disagreement between the model's methods (pca_nn, knn, ridge, and depth_nn when the model
// has the training hips' penetration depths). Their FE is what to run next; training on them is
// `estimator train --base`.
#pragma once

#include "stats/pressure_estimator.h"
#include "stats/uncertainty_sampling.h"
#include "studies/estimator_study.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

struct RefineOptions {
  std::filesystem::path candidates;  // a folder of hip folders (model.json; *.partial skipped)
  int budget = 1;
  stats::UncertaintyCriterion criterion = stats::UncertaintyCriterion::kIntervalWidth;
  stats::EstimatorMethod method = stats::EstimatorMethod::kPcaNn;  // whose interval kIntervalWidth reads
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

}  // namespace hipfai::studies
