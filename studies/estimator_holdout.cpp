// hipfai — `estimator holdout`: the estimator trained on a sample's training hips and tested on its
// held-out hips (see estimator_holdout.h); the files are written by estimator_holdout_report.cpp.
#include "studies/estimator_holdout.h"

#include "core/csv.h"
#include "core/error.h"
#include "core/numbers.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "stats/conformal_interval.h"
#include "studies/estimator_study.h"
#include "studies/results/table_number.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <random>

namespace hipfai::studies {

const char* to_string(HipGroup group) {
  switch (group) {
    case HipGroup::kAll: return "all";
    case HipGroup::kImpinging: return "impinging";
    case HipGroup::kFree: return "free";
  }
  return "?";
}

namespace {

using hipfai::kNaN;
constexpr int kFreeGroup = 0, kImpingingGroup = 1;

struct Rows {
  Eigen::MatrixXd features, values;
  stats::PenetrationDepths depths;
};

Rows rows_of(const std::vector<TrainingHip>& hips, const std::vector<int>& picked) {
  const auto m = static_cast<Eigen::Index>(picked.size());
  const auto f = hips.front().features.size();
  const auto p = static_cast<Eigen::Index>(hips.front().values.size());
  Rows rows{Eigen::MatrixXd(m, f), Eigen::MatrixXd(m, p), {Eigen::MatrixXd(m, p), Eigen::MatrixXd(m, p)}};
  for (Eigen::Index i = 0; i < m; ++i) {
    const TrainingHip& hip = hips[static_cast<std::size_t>(picked[static_cast<std::size_t>(i)])];
    rows.features.row(i) = hip.features.transpose();
    for (Eigen::Index j = 0; j < p; ++j) {
      rows.values(i, j) = hip.values[static_cast<std::size_t>(j)];
      rows.depths.curvilinear_mm(i, j) = hip.curvilinear_mm[static_cast<std::size_t>(j)];
      rows.depths.radial_mm(i, j) = hip.radial_mm[static_cast<std::size_t>(j)];
    }
  }
  return rows;
}

stats::PenetrationDepths target_depths(const TrainingHip& hip) {
  const auto p = static_cast<Eigen::Index>(hip.values.size());
  stats::PenetrationDepths depths{Eigen::MatrixXd(1, p), Eigen::MatrixXd(1, p)};
  for (Eigen::Index j = 0; j < p; ++j) {
    depths.curvilinear_mm(0, j) = hip.curvilinear_mm[static_cast<std::size_t>(j)];
    depths.radial_mm(0, j) = hip.radial_mm[static_cast<std::size_t>(j)];
  }
  return depths;
}

bool impinging_at(const TrainingHip& hip, std::size_t step) {
  return hip.curvilinear_mm[step] > 0.0 || hip.radial_mm[step] > 0.0;
}

int case_steps(int case_index, int steps) { return case_index == 1 ? (steps + 1) / 2 : steps; }

// Mean |estimate - FE| / FE (%) over the case's first `steps` steps (stats::mean_abs_error_percent);
// NaN when an FE value there is missing or not positive, or the method is undefined at a step.
double case_error_percent(const stats::EstimateResult& result, const Eigen::VectorXd& values) {
  for (Eigen::Index j = 0; j < values.size(); ++j) {
    if (!result.steps[static_cast<std::size_t>(j)].defined) return kNaN;
  }
  return stats::mean_abs_error_percent(result, values);
}

double case_error_percent(const stats::EstimateResult& result, const TrainingHip& hip, int steps) {
  return case_error_percent(result, Eigen::Map<const Eigen::VectorXd>(hip.values.data(), static_cast<Eigen::Index>(steps)));
}

bool impinging_within(const TrainingHip& hip, int steps) {
  for (int j = 0; j < steps; ++j) {
    if (impinging_at(hip, static_cast<std::size_t>(j))) return true;
  }
  return false;
}

// Finite stand-ins for unbounded interval ends (interval_coverage counts them, never as a miss).
double bounded(double value) {
  return std::clamp(value, -std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
}

void add_round(HoldoutResult& result, RefineStrategy strategy, stats::UncertaintyCriterion criterion, int repeat,
               int round, int training_hips, const MethodCaseErrors& errors, const std::vector<std::string>& added) {
  for (int m = 0; m < stats::kNumEstimatorMethods; ++m) {
    for (int c = 1; c <= 2; ++c) {
      result.refine.push_back({strategy, criterion, repeat, round, training_hips, stats::kEstimatorMethods[m], c,
                               errors[static_cast<std::size_t>(m)][static_cast<std::size_t>(c - 1)], added});
    }
  }
}

// The uncertainty of each pool hip under `model`, for least_certain().
std::vector<stats::CandidatePrediction> pool_predictions(const stats::TrainedEstimator& model,
                                                         const std::vector<TrainingHip>& hips,
                                                         const std::vector<int>& pool,
                                                         stats::EstimatorMethod width_method) {
  const int e = model.pca.num_components();
  std::vector<stats::CandidatePrediction> candidates;
  for (const int index : pool) {
    const TrainingHip& hip = hips[static_cast<std::size_t>(index)];
    stats::CandidatePrediction candidate;
    for (const stats::EstimatorMethod method : stats::kEstimatorMethods) {
      const auto result = stats::estimate(model, hip.features, method, e, target_depths(hip));
      std::vector<double> estimates;
      for (const auto& step : result.steps) {
        estimates.push_back(step.defined ? step.estimate : kNaN);
        if (method == width_method) {
          candidate.low.push_back(step.defined ? step.low : kNaN);
          candidate.high.push_back(step.defined ? step.high : kNaN);
        }
      }
      candidate.estimates.push_back(std::move(estimates));
    }
    candidates.push_back(std::move(candidate));
  }
  return candidates;
}

stats::TrainedEstimator train_on(const std::vector<TrainingHip>& hips, const std::vector<int>& picked,
                                 const stats::EstimatorSettings& settings) {
  const Rows rows = rows_of(hips, picked);
  return stats::train_estimator(rows.features, rows.values, settings, rows.depths);
}

void run_refine(HoldoutResult& result, const HoldoutOptions& options, const std::vector<TrainingHip>& train,
                const std::vector<TrainingHip>& held_out, const stats::EstimatorSettings& settings) {
  const int n = static_cast<int>(train.size());
  if (options.refine_rounds < 1 || options.refine_start < 3 || options.refine_start >= n) return;
  const int rounds = std::min(options.refine_rounds, (n - options.refine_start) / std::max(1, options.refine_budget));
  if (rounds < 1) return;
  result.refine_start = options.refine_start;
  result.refine_budget = options.refine_budget;
  result.random_repeats = options.random_repeats;
  std::vector<int> start(static_cast<std::size_t>(options.refine_start));
  std::iota(start.begin(), start.end(), 0);
  std::vector<int> pool_all(static_cast<std::size_t>(n - options.refine_start));
  std::iota(pool_all.begin(), pool_all.end(), options.refine_start);
  const MethodCaseErrors start_errors = held_out_errors(train_on(train, start, settings), held_out);
  ProgressBar bar("refine rounds", static_cast<std::size_t>(rounds) * (options.criteria.size() + static_cast<std::size_t>(options.random_repeats)),
                  options.progress);
  for (const stats::UncertaintyCriterion criterion : options.criteria) {
    std::vector<int> set = start, pool = pool_all;
    add_round(result, RefineStrategy::kUncertainty, criterion, 0, 0, static_cast<int>(set.size()), start_errors, {});
    for (int round = 1; round <= rounds; ++round) {
      const stats::TrainedEstimator model = train_on(train, set, settings);
      const auto picked = stats::least_certain(pool_predictions(model, train, pool, options.refine_method), criterion,
                                               options.refine_budget);
      std::vector<std::string> added;
      std::vector<int> chosen;
      for (const std::size_t k : picked) chosen.push_back(pool[k]);
      for (const int index : chosen) {
        set.push_back(index);
        added.push_back(train[static_cast<std::size_t>(index)].name);
        pool.erase(std::find(pool.begin(), pool.end(), index));
      }
      add_round(result, RefineStrategy::kUncertainty, criterion, 0, round, static_cast<int>(set.size()),
                held_out_errors(train_on(train, set, settings), held_out), added);
      bar.advance();
    }
  }
  for (int repeat = 1; repeat <= options.random_repeats; ++repeat) {
    std::vector<int> order = pool_all;
    std::mt19937_64 random(options.seed * 1000003ULL + static_cast<std::uint64_t>(repeat));
    std::shuffle(order.begin(), order.end(), random);
    std::vector<int> set = start;
    add_round(result, RefineStrategy::kRandom, {}, repeat, 0, static_cast<int>(set.size()), start_errors, {});
    for (int round = 1; round <= rounds; ++round) {
      std::vector<std::string> added;
      for (int k = 0; k < options.refine_budget; ++k) {
        const int index = order[static_cast<std::size_t>((round - 1) * options.refine_budget + k)];
        set.push_back(index);
        added.push_back(train[static_cast<std::size_t>(index)].name);
      }
      add_round(result, RefineStrategy::kRandom, {}, repeat, round, static_cast<int>(set.size()),
                held_out_errors(train_on(train, set, settings), held_out), added);
      bar.advance();
    }
  }
}

// The leave-one-out estimates of the training hips at each method's largest e', as calibration
// rows per method (grouped by the step's contact), and their errors per case into result.loo.
std::array<std::vector<stats::ConformalRow>, stats::kNumEstimatorMethods> calibration_rows(
    const Rows& rows, const stats::EstimatorSettings& settings, int e, HoldoutResult& result) {
  std::array<std::vector<stats::ConformalRow>, stats::kNumEstimatorMethods> out;
  std::array<std::array<std::vector<double>, 2>, stats::kNumEstimatorMethods> errors;
  const auto loo = stats::leave_one_out(rows.features, rows.values, settings, e, {}, {}, rows.depths);
  std::map<std::pair<int, int>, int> largest;  // (hip, method) -> largest e' computed
  for (const auto& row : loo) {
    int& best = largest[{row.hip, static_cast<int>(row.method)}];
    best = std::max(best, row.e_prime);
  }
  for (const auto& row : loo) {
    if (row.e_prime != largest[{row.hip, static_cast<int>(row.method)}]) continue;
    auto& target = out[static_cast<std::size_t>(row.method)];
    for (int c = 1; c <= 2; ++c) {
      const double error = case_error_percent(
          row.result, rows.values.row(row.hip).head(case_steps(c, static_cast<int>(rows.values.cols()))).transpose());
      if (std::isfinite(error)) errors[static_cast<std::size_t>(row.method)][static_cast<std::size_t>(c - 1)].push_back(error);
    }
    for (std::size_t j = 0; j < row.result.steps.size(); ++j) {
      const auto& step = row.result.steps[j];
      const auto col = static_cast<Eigen::Index>(j);
      const bool impinging = rows.depths.curvilinear_mm(row.hip, col) > 0.0 || rows.depths.radial_mm(row.hip, col) > 0.0;
      target.push_back({step.defined ? step.estimate : kNaN, rows.values(row.hip, col),
                        impinging ? kImpingingGroup : kFreeGroup});
    }
  }
  for (int m = 0; m < stats::kNumEstimatorMethods; ++m) {
    for (int c = 1; c <= 2; ++c) {
      const auto& v = errors[static_cast<std::size_t>(m)][static_cast<std::size_t>(c - 1)];
      result.loo.push_back({static_cast<int>(rows.values.rows()), stats::kEstimatorMethods[m], c, static_cast<int>(v.size()),
                            v.empty() ? kNaN : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size())});
    }
  }
  return out;
}

// Everything measured at one training size.
void run_size(HoldoutResult& result, int k, const std::vector<TrainingHip>& train,
              const std::vector<TrainingHip>& held_out, const HoldoutOptions& options,
              const stats::EstimatorSettings& settings) {
  std::vector<int> picked(static_cast<std::size_t>(k));
  std::iota(picked.begin(), picked.end(), 0);
  const Rows rows = rows_of(train, picked);
  HoldoutTiming timing;
  timing.training_hips = k;
  auto start = SteadyClock::now();
  const stats::TrainedEstimator model = stats::train_estimator(rows.features, rows.values, settings, rows.depths);
  timing.train_ms = 1e3 * seconds_since(start);
  const int e = model.pca.num_components();
  result.components = std::max(result.components, e);
  start = SteadyClock::now();
  const auto calibration_by_method = calibration_rows(rows, settings, e, result);
  timing.calibrate_ms = 1e3 * seconds_since(start);
  const int p = result.steps;
  double predict_ms = 0;
  for (int m = 0; m < stats::kNumEstimatorMethods; ++m) {
    const stats::EstimatorMethod method = stats::kEstimatorMethods[m];
    const stats::ConformalCalibration calibration =
        stats::calibrate_conformal(calibration_by_method[static_cast<std::size_t>(m)], 2, options.nominal);
    std::vector<stats::IntervalRow> conformal_rows, native_rows;
    for (const TrainingHip& hip : held_out) {
      start = SteadyClock::now();
      const auto estimate = stats::estimate(model, hip.features, method, e, target_depths(hip));
      predict_ms += 1e3 * seconds_since(start);
      for (int c = 1; c <= 2; ++c) {
        const int steps = case_steps(c, p);
        result.hip_errors.push_back({k, hip.name, method, c, impinging_within(hip, steps), estimate.bordering,
                                     case_error_percent(estimate, hip, steps)});
      }
      for (int j = 0; j < p; ++j) {
        const auto& step = estimate.steps[static_cast<std::size_t>(j)];
        HoldoutStep row;
        row.training_hips = k;
        row.hip = hip.name;
        row.method = method;
        row.step = j + 1;
        row.estimate = step.defined ? step.estimate : kNaN;
        row.fe = hip.values[static_cast<std::size_t>(j)];
        row.low = step.defined ? step.low : kNaN;
        row.high = step.defined ? step.high : kNaN;
        row.impinging_step = impinging_at(hip, static_cast<std::size_t>(j));
        const auto interval =
            stats::conformal_interval(calibration, row.estimate, row.impinging_step ? kImpingingGroup : kFreeGroup);
        row.conformal_low = interval.lower;
        row.conformal_high = interval.upper;
        row.bordering = estimate.bordering;
        row.wide_interval = interval.relative_half_width > literature::kEstimatorLargeErrorFraction;
        conformal_rows.push_back({row.estimate, bounded(row.conformal_low), bounded(row.conformal_high), row.fe,
                                  row.bordering || row.wide_interval});
        // A method's own interval may be undefined where its estimate is not (counted as skipped).
        const bool native_defined = std::isfinite(row.low) && std::isfinite(row.high);
        native_rows.push_back({native_defined ? row.estimate : kNaN, native_defined ? row.low : 0.0,
                               native_defined ? row.high : 0.0, row.fe, row.bordering});
        result.steps_rows.push_back(row);
      }
    }
    HoldoutCoverage coverage;
    coverage.training_hips = k;
    coverage.method = method;
    coverage.half_width_free = calibration.half_width[kFreeGroup];
    coverage.half_width_impinging = calibration.half_width[kImpingingGroup];
    coverage.calibration_rows_free = calibration.rows[kFreeGroup];
    coverage.calibration_rows_impinging = calibration.rows[kImpingingGroup];
    coverage.conformal = stats::interval_coverage(conformal_rows, literature::kEstimatorLargeErrorFraction);
    coverage.native = stats::interval_coverage(native_rows, literature::kEstimatorLargeErrorFraction);
    if (coverage.conformal.rows > 0) {
      coverage.acceptance = stats::binomial_acceptance_interval(options.nominal, coverage.conformal.rows, 0.05);
    }
    result.coverage.push_back(coverage);
  }
  timing.predict_ms_per_hip = predict_ms / static_cast<double>(held_out.size());
  result.timings.push_back(timing);
}

// Per size, method, case and group: the mean and largest held-out error.
void summarise(HoldoutResult& result) {
  std::map<std::tuple<int, int, int, int>, std::vector<double>> groups;
  for (const HoldoutHipError& error : result.hip_errors) {
    if (!std::isfinite(error.mean_error_percent)) continue;
    for (const HipGroup group : kHipGroups) {
      if (group == HipGroup::kImpinging && !error.impinging) continue;
      if (group == HipGroup::kFree && error.impinging) continue;
      groups[{error.training_hips, static_cast<int>(error.method), error.case_index, static_cast<int>(group)}].push_back(
          error.mean_error_percent);
    }
  }
  for (const int k : [&] {
         std::vector<int> sizes;
         for (const auto& t : result.timings) sizes.push_back(t.training_hips);
         return sizes;
       }()) {
    for (int m = 0; m < stats::kNumEstimatorMethods; ++m) {
      for (int c = 1; c <= 2; ++c) {
        for (const HipGroup group : kHipGroups) {
          const auto it = groups.find({k, m, c, static_cast<int>(group)});
          HoldoutErrorSummary summary{k, stats::kEstimatorMethods[m], c, group, 0, kNaN, kNaN};
          if (it != groups.end()) {
            const auto& v = it->second;
            summary.hips = static_cast<int>(v.size());
            summary.mean_error_percent = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
            summary.max_error_percent = *std::max_element(v.begin(), v.end());
          }
          result.summary.push_back(summary);
        }
      }
    }
  }
}

// Mean FE wall time and penetration time per hip of the sample (its timings.csv).
void read_sample_times(HoldoutResult& result, const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  if (!in || !std::getline(in, line)) return;
  const auto header = split_csv_line(line);
  const auto column = [&](const char* name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t fe = column("fe_s"), penetration = column("penetration_ms");
  if (fe == header.size() || penetration == header.size()) return;
  double fe_sum = 0, penetration_sum = 0;
  int fe_count = 0, penetration_count = 0;
  while (std::getline(in, line)) {
    const auto cells = split_csv_line(line);
    if (cells.size() != header.size()) continue;
    if (const double v = table_number(cells[fe]); std::isfinite(v)) fe_sum += v, ++fe_count;
    if (const double v = table_number(cells[penetration]); std::isfinite(v)) penetration_sum += v, ++penetration_count;
  }
  result.fe_s_per_hip = fe_count ? fe_sum / fe_count : kNaN;
  result.penetration_ms_per_hip = penetration_count ? penetration_sum / penetration_count : kNaN;
}

}  // namespace

std::vector<TrainingHip> load_sample_hips(const std::filesystem::path& sample_dir, SampleSet set,
                                          const std::string& measure, bool progress) {
  const std::filesystem::path file = sample_dir / (set == SampleSet::kTrain ? "steps.csv" : "held_out_steps.csv");
  if (!std::filesystem::exists(file)) {
    throw_error(file.string(), ": missing; make the sample's FE tables with `hipfai estimator sample ... --fe-level default`");
  }
  EstimatorTrainOptions train;
  train.fe = {file};
  train.hips = sample_dir;
  train.measure = measure;
  train.progress = progress;
  EstimatorModel model = train_estimator_model(train);
  std::vector<TrainingHip> hips = std::move(model.hips);
  const auto number = [](const TrainingHip& hip) {
    const std::string name = hip.dir.filename().string();
    return std::stol(name.substr(name.find_last_of('_') + 1));
  };
  std::sort(hips.begin(), hips.end(), [&](const TrainingHip& a, const TrainingHip& b) { return number(a) < number(b); });
  for (TrainingHip& hip : hips) hip.name = hip.dir.filename().string();
  if (training_depths(hips, static_cast<Eigen::Index>(hips.front().values.size())).curvilinear_mm.size() == 0) {
    throw_error(file.string(), ": hips without penetration depths (max_curvilinear_mm, max_radial_mm); depth_nn and the "
                "impinging groups need them");
  }
  return hips;
}

MethodCaseErrors held_out_errors(const stats::TrainedEstimator& model, const std::vector<TrainingHip>& held_out) {
  const int e = model.pca.num_components();
  const int p = static_cast<int>(held_out.front().values.size());
  MethodCaseErrors mean{};
  for (int m = 0; m < stats::kNumEstimatorMethods; ++m) {
    for (int c = 1; c <= 2; ++c) {
      double sum = 0;
      int count = 0;
      for (const TrainingHip& hip : held_out) {
        const auto result = stats::estimate(model, hip.features, stats::kEstimatorMethods[m], e, target_depths(hip));
        const double error = case_error_percent(result, hip, case_steps(c, p));
        if (std::isfinite(error)) {
          sum += error;
          ++count;
        }
      }
      mean[static_cast<std::size_t>(m)][static_cast<std::size_t>(c - 1)] = count ? sum / count : kNaN;
    }
  }
  return mean;
}

HoldoutResult run_estimator_holdout(const HoldoutOptions& options) {
  if (!(options.nominal > 0.0 && options.nominal < 1.0)) throw_error("estimator holdout: --nominal must be in (0, 1)");
  if (options.refine_budget < 1) throw_error("estimator holdout: --refine-budget must be at least 1");
  const std::vector<TrainingHip> train = load_sample_hips(options.sample_dir, SampleSet::kTrain, options.measure, options.progress);
  const std::vector<TrainingHip> held_out =
      load_sample_hips(options.sample_dir, SampleSet::kHeldOut, options.measure, options.progress);
  HoldoutResult result;
  result.measure = options.measure;
  result.training_available = static_cast<int>(train.size());
  result.held_out = static_cast<int>(held_out.size());
  result.steps = static_cast<int>(train.front().values.size());
  result.nominal = options.nominal;
  if (static_cast<int>(held_out.front().values.size()) != result.steps) {
    throw_error(options.sample_dir.string(), ": training and held-out tables have different motions");
  }
  double feature_ms = 0;
  for (const auto& hip : train) feature_ms += hip.feature_ms;
  for (const auto& hip : held_out) feature_ms += hip.feature_ms;
  result.feature_ms_per_hip = feature_ms / static_cast<double>(train.size() + held_out.size());
  read_sample_times(result, options.sample_dir / "timings.csv");
  const stats::EstimatorSettings settings = EstimatorTrainOptions{}.settings;
  std::vector<int> sizes;
  for (const int k : options.sizes) {
    if (k >= 3 && k <= result.training_available) sizes.push_back(k);
  }
  if (sizes.empty()) throw_error("estimator holdout: no training size fits the sample's ", result.training_available, " training hips");
  ProgressBar bar("training sizes", sizes.size(), options.progress);
  for (const int k : sizes) {
    run_size(result, k, train, held_out, options, settings);
    bar.advance();
  }
  summarise(result);
  run_refine(result, options, train, held_out, settings);
  return result;
}

}  // namespace hipfai::studies
