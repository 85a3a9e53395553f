// hipfai — the leave-one-out validation of the thesis' estimator and its baselines (`hipfai
// estimator validate`, thesis §4.5.3, Tables 12-13, Figs. 72-74). compute_estimator_validation()
// trains on every hip of the run, estimates each hip by models trained on the others and gathers
// the errors, groups and times into an EstimatorValidateResult; write_estimator_validate_report()
// (studies/estimator_validate_report.h) writes loo.csv, estimates.csv, hips.csv, model.h5, the SVG
// figures and report.md from it. validate_estimator() (studies/estimator_study.h) does both.
#pragma once

#include "studies/estimator_study.h"

#include <array>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <vector>

namespace hipfai::studies {

// One held-out hip's leave-one-out estimate by one method at one e', over the steps of a case.
struct EstimatorHipError {
  int hip = 0;      // index into EstimatorValidateResult::model.hips
  int method = 0;   // index into stats::kEstimatorMethods
  int e_prime = 0;  // PCA components used, e'
  // Mean over the case's steps of |estimate - FE| / FE, in %.
  double mean_abs = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> estimate;      // per step of the case, in the FE measure's unit
  std::vector<double> signed_error;  // per step of the case: 100 (estimate - FE) / FE
  std::vector<double> low, high;     // per step of the case: the method's interval (NaN: undefined)
  // The estimator's own flag: the target's PCA scores leave the training range (thesis §4.5.4).
  bool bordering = false;
  double mahalanobis = 0;  // the target's distance over the significant components
  int outside = 0;         // significant components whose training range the target leaves
  // The penetration method finds the hip impinging within the case's steps: 1 / 0; -1 when the FE
  // table gave no depths for one of them.
  int impinging = -1;
};

// Means of the per-hip mean |error| (%) at e' = max over groups of a case's hips; NaN for an empty
// group.
struct EstimatorErrorGroup {
  double all = std::numeric_limits<double>::quiet_NaN();            // every eligible hip
  double grid_interior = std::numeric_limits<double>::quiet_NaN();  // off the run's CE/alpha border
  double grid_border = std::numeric_limits<double>::quiet_NaN();    // at the run's min/max CE or alpha
  double flagged = std::numeric_limits<double>::quiet_NaN();        // flagged bordering by the estimator
  double unflagged = std::numeric_limits<double>::quiet_NaN();      // not flagged
  double thesis_hips = std::numeric_limits<double>::quiet_NaN();    // the hips the thesis' table has a value for
  int thesis_count = 0;                                             // how many of those
};

// One case of the thesis: case 1 the first half of the motion, case 2 all of it.
struct EstimatorValidateCase {
  int steps = 0;  // the case's steps, from the first
  // Hips with a finite, positive FE value at each of the case's steps, in ascending order.
  std::vector<int> eligible;
  // stats::leave_one_out's rows over the eligible hips, every method and e' = 1..max, in its order.
  std::vector<EstimatorHipError> errors;
  // pca_nn with e' chosen without the target: held-out hip -> e' chosen on the other hips
  // (stats::select_e_prime).
  std::map<int, int> chosen_e_prime;
  std::array<EstimatorErrorGroup, stats::kNumEstimatorMethods> groups;  // per method, at e' = max
  EstimatorErrorGroup chosen_group;  // pca_nn at the chosen e' (no thesis column)
  // (hip, method, e') -> index into errors; the last row wins should leave_one_out repeat one.
  std::map<std::tuple<int, int, int>, std::size_t> index;

  // The row of (hip, method, e'), nullptr when the case has none.
  const EstimatorHipError* find(int hip, int method, int e_prime) const;
};

struct EstimatorValidateResult {
  // False on the ranks other than 0 of a validation spread over MPI ranks: the fields below are
  // empty.
  bool holds_results = true;
  // Spread over MPI ranks, the folds that failed ("case 1 ce20_alpha40"); their rows are missing
  // and the other folds are kept. Otherwise a failure throws.
  std::vector<UnitFailure> failed;
  // Trained on every hip of the run (the features, FE values and settings of the study).
  EstimatorModel model;
  // model's estimator trained again from its features, for the time of training alone; its PCA
  // (components, variances, scores, correlations) is what the report describes.
  stats::TrainedEstimator retrained;
  int steps = 0;        // p, the motion's steps
  int components = 0;   // e, PCA components of all hips (retrained.pca.num_components())
  int max_e_prime = 0;  // the e' of the tables (EstimatorValidateOptions::max_e_prime)
  // The run's CE and alpha values; grid_border[i]: hip i has the minimum or maximum of one with at
  // least 3 values (the thesis' "bordering" hips, §4.5.4; fewer values make no interior).
  std::set<double> ces, alphas;
  std::vector<bool> grid_border;
  std::array<EstimatorValidateCase, 2> cases;
  // Times on this machine: the --quick FE sweep (s, 0 without --quick), the whole training
  // pipeline (ms), training with the features given (ms), one prediction per method (ms, NaN for
  // depth_nn without depths), the leave-one-out of both cases (ms) and the choice of e' (ms).
  double quick_fe_s = 0, pipeline_ms = 0, train_ms = 0;
  std::array<double, stats::kNumEstimatorMethods> predict_ms{};
  double loo_ms = 0, selection_ms = 0;
  // What validate_estimator returns, but for the report's path.
  EstimatorValidateSummary summary;
};

// Runs the --quick FE sweep when asked, trains, times, runs leave-one-out for both cases and
// chooses e' per held-out hip. Writes nothing of its own but the --quick sweep (<out_dir>/fe).
// Throws hipfai::Error as train_estimator_model does.
// With options.spread kMpiRanks and two ranks or more (every rank calls it): the --quick FE's hips
// (studies/validation_ranks.h) and then the leave-one-out folds (studies/estimator_fold_ranks.h)
// are spread over the ranks; rank 0 trains and holds the result, with the same numbers.
EstimatorValidateResult compute_estimator_validation(const EstimatorValidateOptions& options);

// Thesis Tables 12 (table_case 0) and 13 (1): mean error (%) of the hip at CE/alpha, NaN when the
// table has no such hip or shows "-".
double thesis_estimator_error(int table_case, double ce, double alpha);
// Mean of a thesis table over its hips (interior: CE 10-30 and alpha 50-70 only).
double thesis_estimator_table_mean(int table_case, bool interior);
// Mean of the finite values, NaN when there are none.
double finite_mean(const std::vector<double>& values);

}  // namespace hipfai::studies
