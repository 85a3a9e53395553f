// hipfai — the files of `estimator validate` (studies/estimator_validate.h), written atomically
// into one folder from an EstimatorValidateResult: loo.csv (per hip, case, e' and method: the mean
// |error| %, flags), estimates.csv (the same per step), hips.csv (per hip: provenance, flag, times,
// PCA scores), model.h5 (trained on every hip), fig73_case1.svg / fig74_case2.svg (mean error vs
// e'), fig72_<hip>.svg (estimate vs FE of CE 20 / alpha 60, when the run has it) and report.md.
#pragma once

#include "studies/estimator_validate.h"

#include <filesystem>

namespace hipfai::studies {

// Returns the path of report.md.
std::filesystem::path write_estimator_validate_report(const EstimatorValidateResult& result,
                                                      const std::filesystem::path& dir);

}  // namespace hipfai::studies
