// hipfai — what `estimator holdout` writes (studies/estimator_holdout.h), each file atomically:
//   errors.csv     training_hips, method, case, group (all, impinging, free), hips,
//                  mean_error_percent, max_error_percent: the held-out error
//   loo.csv        training_hips, method, case, hips, mean_error_percent: leave-one-out inside the
//                  training set, for comparison
//   hips.csv       training_hips, hip, method, case, impinging, bordering, mean_error_percent
//   estimates.csv  training_hips, hip, method, step, estimate, fe, error_percent (signed), low, high
//                  (the method's own interval), conformal_low, conformal_high, impinging_step,
//                  bordering, wide_interval, flagged
//   coverage.csv   training_hips, method, nominal, half_width_free, half_width_impinging (relative),
//                  calibration_rows_free, calibration_rows_impinging, steps, covered, coverage,
//                  acceptance_low, acceptance_high (binomial band of covered at the nominal, 95 %),
//                  native_covered, native_coverage, large_error_steps, flagged_steps,
//                  large_error_flagged, flag_recall, bordering_recall
//   refine.csv     strategy (uncertainty, random), criterion, repeat, round, training_hips, method,
//                  case, mean_error_percent, added (hips added in the round, ';'-separated)
//   timings.csv    training_hips, train_ms, calibrate_ms, predict_ms_per_hip
//   report.md      the tables beside the thesis' 5.14 % / 4.85 %, with fig_error_vs_size.svg and
//                  fig_refine.svg
#pragma once

#include "studies/estimator_holdout.h"

#include <filesystem>
#include <string>

namespace hipfai::studies {

void write_holdout_report(const HoldoutResult& result, const HoldoutOptions& options, const std::filesystem::path& out_dir);

// The closing lines of the command: per training size, the best method's held-out error in both cases.
std::string holdout_summary(const HoldoutResult& result, const std::filesystem::path& out_dir);

}  // namespace hipfai::studies
