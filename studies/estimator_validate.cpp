// hipfai — `estimator validate`: the leave-one-out of the thesis' estimator and its baselines over
// all hips (see estimator_validate.h); the files are written by estimator_validate_report.cpp.
#include "studies/estimator_validate.h"

#include "core/error.h"
#include "studies/estimator_fold.h"
#include "studies/estimator_validate_report.h"
#include "studies/validation_study.h"

#ifdef HIPFAI_WITH_FEM
#include "core/numbers.h"
#include "core/stopwatch.h"
#include "studies/estimator_fold_ranks.h"
#endif

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

namespace hipfai::studies {

namespace {

using hipfai::kNaN;
using stats::kNumEstimatorMethods;

// Thesis Tables 12 and 13 (Arbabi 2009, §4.5.3.5): mean estimation error (%) per hip at e' = 10,
// rows alpha 40..80, columns CE 0..40; NaN = "-" (hip not run over the whole motion, Table 11).
constexpr double kThesisTable12[5][5] = {{4.64, 3.75, 1.58, 1.78, 1.85},
                                         {4.52, 2.79, 1.84, 1.21, 43.59},
                                         {4.93, 1.22, 0.78, 1.00, 1.69},
                                         {4.42, 3.00, 1.65, 1.11, 5.34},
                                         {8.66, 1.71, 2.41, 0.90, 22.17}};
constexpr double kThesisTable13[5][5] = {{5.48, 1.66, 1.63, 2.05, 4.99},
                                         {5.52, 2.57, 3.21, 6.93, 17.66},
                                         {4.98, 1.82, 0.72, 6.16, kNaN},
                                         {5.06, 5.74, 8.42, 8.06, kNaN},
                                         {1.24, 3.15, kNaN, kNaN, kNaN}};

// 1 when the hip's penetration depth is > 0 at one of the first `steps` steps, 0 when it is 0 at
// every one, -1 when the FE table gave no depths for one of them.
int impinging_flag(const TrainingHip& hip, int steps) {
  if (hip.curvilinear_mm.size() < static_cast<std::size_t>(steps) || hip.radial_mm.size() < static_cast<std::size_t>(steps)) {
    return -1;
  }
  bool any = false;
  for (int j = 0; j < steps; ++j) {
    const double c = hip.curvilinear_mm[static_cast<std::size_t>(j)], r = hip.radial_mm[static_cast<std::size_t>(j)];
    if (!std::isfinite(c) || !std::isfinite(r)) return -1;
    any = any || c > 0.0 || r > 0.0;
  }
  return any ? 1 : 0;
}

// --quick: the FE results made from nothing by the validation study, which options.train then
// reads. Returns the sweep's wall time (s).
double run_quick_fe(EstimatorValidateOptions& options) {
  ValidationOptions fe;
  fe.out_dir = options.out_dir / "fe";
  fe.cache_dir = options.quick_cache;
  // Five hips spread over the grid: the normal hip, the thesis' Fig. 60 hip, a dysplastic, the
  // Fig. 72 hip and a mixed one (leave-one-out needs at least 4: 3 to train).
  fe.hips = {{20, 40}, {40, 60}, {0, 50}, {20, 60}, {30, 70}};
  fe.edge_mm = 3.0;
  fe.sub_motions = 6;
  fe.fe_level = FeLevel::kCoarse;
  fe.program = options.quick_program;
  fe.progress = options.train.progress;
  fe.spread = options.spread;
  const auto start = std::chrono::steady_clock::now();
  const ValidationResult made = run_validation_study(fe);
  // Spread over MPI ranks, a hip that failed is in `made.failed` (one process: it threw).
  throw_if_units_failed("estimator validate: --quick FE", made.failed, made.hips.size(), "hips", fe.out_dir);
  options.train.fe = {fe.out_dir};
  options.train.hips = fe.cache_dir;
  return milliseconds_since(start) / 1000.0;
}

// Times of the maths alone (features exist): training on every hip, and one prediction per
// method (the mean of 200, cycling through the hips).
void time_estimator(EstimatorValidateResult& result, const stats::PenetrationDepths& depths) {
  const Eigen::MatrixXd& features = result.model.estimator.features;
  const auto m = static_cast<Eigen::Index>(result.model.hips.size());
  auto start = std::chrono::steady_clock::now();
  result.retrained = stats::train_estimator(features, result.model.estimator.values, result.model.estimator.settings, depths);
  result.train_ms = milliseconds_since(start);
  result.components = result.retrained.pca.num_components();
  constexpr int kRepeats = 200;
  result.predict_ms.fill(kNaN);
  for (int method = 0; method < kNumEstimatorMethods; ++method) {
    if (stats::needs_depths(stats::kEstimatorMethods[method]) && !depths.known()) continue;
    start = std::chrono::steady_clock::now();
    for (int r = 0; r < kRepeats; ++r) {
      const Eigen::Index row = r % m;
      const stats::PenetrationDepths target =
          depths.known() ? stats::PenetrationDepths{depths.curvilinear_mm.row(row), depths.radial_mm.row(row)}
                         : stats::PenetrationDepths{};
      const auto estimate = stats::estimate(result.retrained, features.row(row).transpose(),
                                            stats::kEstimatorMethods[method], result.components, target);
      if (estimate.steps.empty()) throw_error("estimator: no steps");
    }
    result.predict_ms[static_cast<std::size_t>(method)] = milliseconds_since(start) / kRepeats;
  }
}

// The run's grid border (thesis §4.5.4: hips with the maximum/minimum alpha or CE).
void find_grid_border(EstimatorValidateResult& result) {
  for (const auto& hip : result.model.hips) {
    result.ces.insert(hip.ce_deg);
    result.alphas.insert(hip.alpha_deg);
  }
  // A parameter with fewer than 3 values in the run has no interior and makes no border.
  const auto at_end = [](const std::set<double>& set, double value) {
    return set.size() >= 3 && (value == *set.begin() || value == *set.rbegin());
  };
  for (const auto& hip : result.model.hips) {
    result.grid_border.push_back(at_end(result.ces, hip.ce_deg) || at_end(result.alphas, hip.alpha_deg));
  }
}

// One leave-one-out row as the case's error of that hip, method and e'.
EstimatorHipError hip_error(const EstimatorValidateResult& result, const stats::LeaveOneOutRow& row, int steps) {
  EstimatorHipError error;
  error.hip = row.hip;
  error.method = static_cast<int>(row.method);
  error.e_prime = row.e_prime;
  error.bordering = row.result.bordering;
  error.mahalanobis = row.result.mahalanobis;
  error.outside = row.result.outside_components;
  error.impinging = impinging_flag(result.model.hips[static_cast<std::size_t>(row.hip)], steps);
  std::vector<double> absolute;
  for (int j = 0; j < steps; ++j) {
    const stats::RegressionStep& step = row.result.steps[static_cast<std::size_t>(j)];
    const double estimate = step.estimate;
    error.low.push_back(step.defined ? step.low : std::numeric_limits<double>::quiet_NaN());
    error.high.push_back(step.defined ? step.high : std::numeric_limits<double>::quiet_NaN());
    const double fe = result.model.estimator.values(row.hip, j);
    const double signed_error = 100.0 * (estimate - fe) / fe;
    error.estimate.push_back(estimate);
    error.signed_error.push_back(signed_error);
    absolute.push_back(std::abs(signed_error));
  }
  error.mean_abs = finite_mean(absolute);
  return error;
}

// The hips of case c with a finite, positive FE value at each of its steps.
std::vector<int> eligible_hips(const EstimatorValidateResult& result, int c) {
  const Eigen::MatrixXd& values = result.model.estimator.values;
  std::vector<int> eligible;
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(result.model.hips.size()); ++i) {
    bool complete = true;
    for (int j = 0; j < result.cases[static_cast<std::size_t>(c)].steps; ++j) {
      complete = complete && std::isfinite(values(i, j)) && values(i, j) > 0.0;
    }
    if (complete) eligible.push_back(static_cast<int>(i));
  }
  return eligible;
}

// What the folds read, from the trained model.
EstimatorFoldProblem fold_problem(const EstimatorValidateResult& result, const stats::PenetrationDepths& depths) {
  EstimatorFoldProblem problem;
  problem.features = result.model.estimator.features;
  problem.values = result.model.estimator.values;
  problem.depths = depths;
  problem.settings = result.model.estimator.settings;
  problem.max_e_prime = result.max_e_prime;
  for (int c = 0; c < 2; ++c) {
    problem.case_steps[static_cast<std::size_t>(c)] = result.cases[static_cast<std::size_t>(c)].steps;
    problem.eligible[static_cast<std::size_t>(c)] = eligible_hips(result, c);
  }
  return problem;
}

// A fold's rows as its case's errors (leave-one-out order: hip, method, e') and its chosen e'.
void add_fold(EstimatorValidateResult& result, const EstimatorFoldUnit& unit, const EstimatorFold& fold) {
  EstimatorValidateCase& one = result.cases[static_cast<std::size_t>(unit.case_index)];
  for (const auto& row : fold.rows) {
    one.index[{row.hip, static_cast<int>(row.method), row.e_prime}] = one.errors.size();
    one.errors.push_back(hip_error(result, row, one.steps));
  }
  one.chosen_e_prime[unit.hip] = fold.chosen_e_prime;
  result.loo_ms += fold.loo_ms;
  result.selection_ms += fold.selection_ms;
}

// "case 1 ce20_alpha40".
std::string fold_name(const EstimatorValidateResult& result, const EstimatorFoldUnit& unit) {
  return "case " + std::to_string(unit.case_index + 1) + " " + result.model.hips[static_cast<std::size_t>(unit.hip)].name;
}

// The group means of case c at e' = max (per method and for the chosen e'), and the summary's.
void case_groups(EstimatorValidateResult& result, int c) {
  EstimatorValidateCase& one = result.cases[static_cast<std::size_t>(c)];
  EstimatorValidateSummary& summary = result.summary;
  const int max_e = result.max_e_prime;
  summary.hips[c] = static_cast<int>(one.eligible.size());
  for (const int i : one.eligible) {
    const EstimatorHipError* e = one.find(i, 0, max_e);
    if (e && e->bordering) ++summary.bordering[c];
    if (e && e->impinging == 1) ++summary.impinging[c];
  }
  for (int method = 0; method < kNumEstimatorMethods; ++method) {
    std::vector<double> all, interior, border, flagged, unflagged, thesis_set;
    for (const int i : one.eligible) {
      const EstimatorHipError* e = one.find(i, method, max_e);
      if (!e) continue;
      all.push_back(e->mean_abs);
      (result.grid_border[static_cast<std::size_t>(i)] ? border : interior).push_back(e->mean_abs);
      (e->bordering ? flagged : unflagged).push_back(e->mean_abs);
      const TrainingHip& hip = result.model.hips[static_cast<std::size_t>(i)];
      if (std::isfinite(thesis_estimator_error(c, hip.ce_deg, hip.alpha_deg))) thesis_set.push_back(e->mean_abs);
    }
    EstimatorErrorGroup& group = one.groups[static_cast<std::size_t>(method)];
    group = {finite_mean(all),       finite_mean(interior),   finite_mean(border),
             finite_mean(flagged),   finite_mean(unflagged),  finite_mean(thesis_set),
             static_cast<int>(thesis_set.size())};
    summary.mean_error[c][method] = group.all;
    summary.interior_error[c][method] = group.grid_interior;
  }
  // pca_nn with e' chosen on the training hips: the same groups.
  std::vector<double> all, interior, border, flagged, unflagged;
  for (const auto& [target, e_prime] : one.chosen_e_prime) {
    const EstimatorHipError* e = one.find(target, 0, e_prime);
    if (!e) continue;
    all.push_back(e->mean_abs);
    (result.grid_border[static_cast<std::size_t>(target)] ? border : interior).push_back(e->mean_abs);
    (e->bordering ? flagged : unflagged).push_back(e->mean_abs);
  }
  one.chosen_group = {finite_mean(all),     finite_mean(interior), finite_mean(border), finite_mean(flagged),
                      finite_mean(unflagged), kNaN,                0};
  summary.chosen_e_prime_error[c] = one.chosen_group.all;
  summary.chosen_e_prime_interior_error[c] = one.chosen_group.grid_interior;
}

}  // namespace

const EstimatorHipError* EstimatorValidateCase::find(int hip, int method, int e_prime) const {
  const auto it = index.find({hip, method, e_prime});
  return it == index.end() ? nullptr : &errors[it->second];
}

double thesis_estimator_error(int table_case, double ce, double alpha) {
  const double col = ce / 10.0, row = (alpha - 40.0) / 10.0;
  if (col != std::round(col) || row != std::round(row) || col < 0 || col > 4 || row < 0 || row > 4) return kNaN;
  const auto& table = table_case == 0 ? kThesisTable12 : kThesisTable13;
  return table[static_cast<int>(row)][static_cast<int>(col)];
}

double thesis_estimator_table_mean(int table_case, bool interior) {
  double sum = 0;
  int count = 0;
  for (int row = 0; row < 5; ++row) {
    for (int col = 0; col < 5; ++col) {
      const double value = (table_case == 0 ? kThesisTable12 : kThesisTable13)[row][col];
      if (std::isnan(value) || (interior && (row == 0 || row == 4 || col == 0 || col == 4))) continue;
      sum += value;
      ++count;
    }
  }
  return sum / count;
}

double finite_mean(const std::vector<double>& values) {
  double sum = 0;
  int count = 0;
  for (const double v : values) {
    if (std::isfinite(v)) {
      sum += v;
      ++count;
    }
  }
  return count ? sum / count : kNaN;
}

EstimatorValidateResult compute_estimator_validation(const EstimatorValidateOptions& options_in) {
  EstimatorValidateOptions options = options_in;
#ifdef HIPFAI_WITH_FEM
  const bool over_ranks = options.spread == UnitSpread::kMpiRanks && join_mpi_world().size > 1;
  const bool rank_zero = !over_ranks || join_mpi_world().rank == 0;
#else
  const bool over_ranks = false, rank_zero = true;
#endif
  std::filesystem::create_directories(options.out_dir);
  EstimatorValidateResult result;
#ifdef HIPFAI_WITH_FEM
  if (!rank_zero) {
    if (!options.quick_program.empty()) run_quick_fe(options);
    serve_estimator_folds();
    result.holds_results = false;
    return result;
  }
#endif
  EstimatorFoldProblem problem;
  try {
    if (!options.quick_program.empty()) result.quick_fe_s = run_quick_fe(options);
    const auto train_start = std::chrono::steady_clock::now();
    result.model = train_estimator_model(options.train);
    result.pipeline_ms = milliseconds_since(train_start);
    result.steps = static_cast<int>(result.model.estimator.values.cols());
    result.max_e_prime = options.max_e_prime;

    const stats::PenetrationDepths depths = training_depths(result.model.hips, result.steps);
    time_estimator(result, depths);
    find_grid_border(result);
    // Case 1: the first half of the motion (the middle step included when p is odd); case 2: all.
    result.cases[0].steps = (result.steps + 1) / 2;
    result.cases[1].steps = result.steps;
    problem = fold_problem(result, depths);
  } catch (...) {
#ifdef HIPFAI_WITH_FEM
    if (over_ranks) release_estimator_fold_workers();
#endif
    throw;
  }
  for (int c = 0; c < 2; ++c) result.cases[static_cast<std::size_t>(c)].eligible = problem.eligible[static_cast<std::size_t>(c)];
  const std::vector<EstimatorFoldUnit> units = estimator_fold_units(problem);
  std::vector<std::optional<EstimatorFold>> folds;
#ifdef HIPFAI_WITH_FEM
  if (over_ranks) {
    std::vector<UnitResult<EstimatorFold>> spread = run_estimator_folds_over_ranks(problem);
    for (std::size_t k = 0; k < units.size(); ++k) {
      folds.push_back(std::move(spread[k].reply));
      if (!folds.back()) result.failed.push_back({fold_name(result, units[k]), spread[k].error});
    }
  }
#endif
  if (!over_ranks) {
    for (const EstimatorFoldUnit& unit : units) folds.push_back(run_estimator_fold(problem, unit));
  }
  for (std::size_t k = 0; k < units.size(); ++k) {
    if (folds[k]) add_fold(result, units[k], *folds[k]);
  }
  for (int c = 0; c < 2; ++c) case_groups(result, c);
  return result;
}

EstimatorValidateSummary validate_estimator(const EstimatorValidateOptions& options) {
  const EstimatorValidateResult result = compute_estimator_validation(options);
  EstimatorValidateSummary summary = result.summary;
  summary.wrote_report = result.holds_results;
  if (!result.holds_results) return summary;
  summary.report = write_estimator_validate_report(result, options.out_dir);
  // A fold that failed on a worker rank is named in one line, after the others' report.
  const std::size_t folds = result.cases[0].eligible.size() + result.cases[1].eligible.size();
  throw_if_units_failed("estimator validate", result.failed, folds - result.failed.size(), "folds", options.out_dir);
  return summary;
}

}  // namespace hipfai::studies
