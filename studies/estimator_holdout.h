// hipfai — the estimator on hips it has never seen: trained on the training hips of an `estimator
// sample` (its steps.csv), tested on its held-out hips (held_out_steps.csv), which no model here
// trains on. It computes:
//   - the held-out error of every method at e' = e (the thesis' setting), per case (1: first half of
//     the motion, 2: all of it) and per group of hips (impinging within the case's steps or not),
//     for training sets of growing size: the first k training hips of the design (a Sobol design's
//     prefixes are themselves spread over the space), k in `sizes`;
//   - intervals with a stated coverage (stats/conformal_interval.h): each method calibrated on the
//     leave-one-out estimates of its training hips, one group for the steps where the hip is free
//     of contact and one for the steps where it impinges (its penetration depths, thesis §4.3); the
//     share of held-out steps they hold, beside the nominal and the binomial acceptance band;
//   - the flag, checked against the held-out steps whose error exceeds 10 %
//     (literature::kEstimatorLargeErrorFraction): raised on a step when the hip is bordering
//     (stats/pressure_estimator.h) or when the step's calibrated interval is wider than ±10 %
//     (its group's leave-one-out errors say the method is that uncertain there);
//   - refinement against random sampling at the same budget: from the first `refine_start`
//     training hips, `refine_rounds` rounds each adding `refine_budget` hips of the remaining
//     training hips (their FE is known), picked as least certain (stats/uncertainty_sampling.h)
//     or at random (`random_repeats` draws from `seed`); the held-out error after every round;
//   - the times: FE and penetration per hip (the sample's timings.csv), features per hip, training
//     per size, prediction per hip.
// The report (studies/estimator_holdout_report.h) writes the tables and figures.
#pragma once

#include "core/literature.h"
#include "stats/interval_coverage.h"
#include "stats/pressure_estimator.h"
#include "stats/uncertainty_sampling.h"
#include "studies/estimator_sample.h"
#include "studies/estimator_study.h"

#include <array>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

struct HoldoutOptions {
  std::filesystem::path sample_dir;          // `estimator sample --fe-level ...` output
  std::vector<int> sizes{25, 50, 100, 200};  // training-set sizes; those above the sample's are skipped
  double nominal = literature::kEstimatorNominalCoverage;
  int refine_start = 25;
  int refine_budget = 25;
  int refine_rounds = 3;
  std::vector<stats::UncertaintyCriterion> criteria{stats::UncertaintyCriterion::kIntervalWidth,
                                                    stats::UncertaintyCriterion::kMethodDisagreement};
  stats::EstimatorMethod refine_method = stats::EstimatorMethod::kDepthNn;  // whose interval `width` reads
  int random_repeats = 10;
  std::uint64_t seed = 1;
  std::string measure = "pressure_max_mpa";
  bool progress = true;
};

enum class HipGroup { kAll, kImpinging, kFree };
inline constexpr HipGroup kHipGroups[] = {HipGroup::kAll, HipGroup::kImpinging, HipGroup::kFree};
const char* to_string(HipGroup group);  // "all", "impinging", "free"

// One held-out hip's error at one training size, method and case.
struct HoldoutHipError {
  int training_hips = 0;
  std::string hip;  // held_out_007
  stats::EstimatorMethod method{};
  int case_index = 0;           // 1 or 2
  bool impinging = false;       // a penetration depth > 0 within the case's steps
  bool bordering = false;
  double mean_error_percent = 0;
};

// Mean over hips of HoldoutHipError, per training size, method, case and group.
struct HoldoutErrorSummary {
  int training_hips = 0;
  stats::EstimatorMethod method{};
  int case_index = 0;
  HipGroup group = HipGroup::kAll;
  int hips = 0;
  double mean_error_percent = 0;  // NaN without hips
  double max_error_percent = 0;
};

// One held-out step's estimate (case 2: every step), with both intervals and the flags.
struct HoldoutStep {
  int training_hips = 0;
  std::string hip;
  stats::EstimatorMethod method{};
  int step = 0;                    // 1-based
  double estimate = 0, fe = 0;
  double low = 0, high = 0;        // the method's own interval
  double conformal_low = 0, conformal_high = 0;
  bool impinging_step = false;     // the step's group
  bool bordering = false;
  bool wide_interval = false;      // calibrated half-width above the large-error fraction
};

struct HoldoutCoverage {
  int training_hips = 0;
  stats::EstimatorMethod method{};
  double half_width_free = 0, half_width_impinging = 0;  // calibrated, relative
  std::size_t calibration_rows_free = 0, calibration_rows_impinging = 0;
  stats::CoverageResult conformal;      // flag = bordering or wide interval
  stats::CoverageResult native;         // the method's own interval; flag = bordering only
  stats::CountInterval acceptance;      // binomial band of covered counts at the nominal (alpha 0.05)
};

enum class RefineStrategy { kUncertainty, kRandom };
struct RefineRoundError {
  RefineStrategy strategy = RefineStrategy::kRandom;
  stats::UncertaintyCriterion criterion{};  // kUncertainty only
  int repeat = 0;                            // kRandom: the draw
  int round = 0;                             // 0: the start set
  int training_hips = 0;
  stats::EstimatorMethod method{};
  int case_index = 0;
  double mean_error_percent = 0;             // over the held-out hips
  std::vector<std::string> added;            // hips added in this round
};

// The leave-one-out error inside one training set (each training hip estimated by a model trained
// on the others), the figure the held-out error is compared with.
struct HoldoutLooError {
  int training_hips = 0;
  stats::EstimatorMethod method{};
  int case_index = 0;
  int hips = 0;
  double mean_error_percent = 0;
};

struct HoldoutTiming {
  int training_hips = 0;
  double train_ms = 0;            // PCA and derived members
  double calibrate_ms = 0;        // leave-one-out over the training hips, all methods
  double predict_ms_per_hip = 0;  // estimate(), all methods, mean over held-out hips
};

struct HoldoutResult {
  std::string measure;
  int training_available = 0, held_out = 0, steps = 0;
  int components = 0;  // e of the largest training set
  double nominal = 0;
  std::vector<HoldoutHipError> hip_errors;
  std::vector<HoldoutErrorSummary> summary;
  std::vector<HoldoutLooError> loo;
  std::vector<HoldoutStep> steps_rows;
  std::vector<HoldoutCoverage> coverage;
  std::vector<RefineRoundError> refine;
  std::vector<HoldoutTiming> timings;
  double fe_s_per_hip = 0, penetration_ms_per_hip = 0, feature_ms_per_hip = 0;
  int refine_start = 0, refine_budget = 0, random_repeats = 0;
};

// The hips of one set of an `estimator sample` with FE (steps.csv or held_out_steps.csv), with
// features, FE values of `measure` and depths, in design order; name = the hip's folder name.
// Throws hipfai::Error when the table is missing, has fewer than 3 hips or no depths.
std::vector<TrainingHip> load_sample_hips(const std::filesystem::path& sample_dir, SampleSet set,
                                          const std::string& measure, bool progress);

// The mean held-out error (%) of each method ([index in stats::kEstimatorMethods][case - 1]) of a
// trained model at e' = e, over the hips whose error is defined; NaN when none is.
using MethodCaseErrors = std::array<std::array<double, 2>, stats::kNumEstimatorMethods>;
MethodCaseErrors held_out_errors(const stats::TrainedEstimator& model, const std::vector<TrainingHip>& held_out);

// Throws hipfai::Error when the sample has no FE tables, fewer than 3 training hips for a size,
// or no held-out hip.
HoldoutResult run_estimator_holdout(const HoldoutOptions& options);

}  // namespace hipfai::studies
