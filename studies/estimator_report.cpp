// hipfai — `estimator validate`: leave-one-out of the thesis' estimator and its baselines over all
// hips (thesis §4.5.3, Tables 12-13, Figs. 72-74), written as loo.csv, estimates.csv, hips.csv,
// report.md with SVG figures, and model.h5 (trained on every hip of the run).
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/literature.h"
#include "core/version.h"
#include "studies/estimator_study.h"
#include "studies/svg_plot.h"
#include "stats/pearson.h"
#include "studies/validation_study.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace hipfai::studies {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The `method` of pca_nn rows whose e' was chosen by leave-one-out inside the training hips.
constexpr const char* kChosenMethod = "pca_nn_cv";

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

double thesis_value(int table_case, double ce, double alpha) {
  const double col = ce / 10.0, row = (alpha - 40.0) / 10.0;
  if (col != std::round(col) || row != std::round(row) || col < 0 || col > 4 || row < 0 || row > 4) return kNaN;
  const auto& table = table_case == 0 ? kThesisTable12 : kThesisTable13;
  return table[static_cast<int>(row)][static_cast<int>(col)];
}

// Mean of a thesis table over its hips (interior: CE 10-30 and alpha 50-70 only).
double thesis_table_mean(int table_case, bool interior) {
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

double elapsed_ms(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::string fixed(double value, int digits = 2) {
  if (!std::isfinite(value)) return "-";
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

double mean_of(const std::vector<double>& values) {
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

struct HipError {
  int hip = 0;
  int method = 0;
  int e_prime = 0;
  double mean_abs = kNaN;
  std::vector<double> estimate, signed_error;  // per step of the case
  bool bordering = false;
  double mahalanobis = 0;
  int outside = 0;
  int impinging = -1;  // the penetration method finds the hip impinging in the case's steps: 1/0; -1 unknown
};

// 1 when the hip's penetration depth is > 0 at one of the first `steps` steps, 0 when it is 0 at
// every one, -1 when the FE table gave no depths for one of them.
int impinging_within(const TrainingHip& hip, int steps) {
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

std::string flag_cell(int flag) { return flag < 0 ? std::string() : std::to_string(flag); }

}  // namespace

EstimatorValidateSummary validate_estimator(const EstimatorValidateOptions& options_in) {
  EstimatorValidateOptions options = options_in;
  std::filesystem::create_directories(options.out_dir);
  double quick_fe_s = 0;
  if (!options.quick_program.empty()) {
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
    const auto start = std::chrono::steady_clock::now();
    run_validation_study(fe);
    quick_fe_s = elapsed_ms(start) / 1000.0;
    options.train.fe = {fe.out_dir};
    options.train.hips = fe.cache_dir;
  }

  const auto train_start = std::chrono::steady_clock::now();
  const EstimatorModel model = train_estimator_model(options.train);
  const double pipeline_ms = elapsed_ms(train_start);
  write_estimator_model(model, options.out_dir / "model.h5");

  const auto m = static_cast<Eigen::Index>(model.hips.size());
  const Eigen::MatrixXd& features = model.estimator.features;
  const Eigen::MatrixXd& values = model.estimator.values;
  const auto p = static_cast<int>(values.cols());

  // Times of the maths alone (features exist): training on every hip, and one prediction.
  auto start = std::chrono::steady_clock::now();
  const stats::PenetrationDepths depths = training_depths(model.hips, p);
  const stats::TrainedEstimator retrained = stats::train_estimator(features, values, model.estimator.settings, depths);
  const double train_ms = elapsed_ms(start);
  const int e_all = retrained.pca.num_components();
  constexpr int kRepeats = 200;
  constexpr int kMethods = stats::kNumEstimatorMethods;
  std::array<double, kMethods> predict_ms{};
  predict_ms.fill(kNaN);
  for (int method = 0; method < kMethods; ++method) {
    if (stats::needs_depths(stats::kEstimatorMethods[method]) && !depths.known()) continue;
    start = std::chrono::steady_clock::now();
    for (int r = 0; r < kRepeats; ++r) {
      const Eigen::Index row = r % m;
      const stats::PenetrationDepths target =
          depths.known() ? stats::PenetrationDepths{depths.curvilinear_mm.row(row), depths.radial_mm.row(row)}
                         : stats::PenetrationDepths{};
      const auto result = stats::estimate(retrained, features.row(row).transpose(), stats::kEstimatorMethods[method],
                                          e_all, target);
      if (result.steps.empty()) throw_error("estimator: no steps");
    }
    predict_ms[static_cast<std::size_t>(method)] = elapsed_ms(start) / kRepeats;
  }
  std::vector<double> feature_ms, load_ms;
  for (const auto& hip : model.hips) {
    feature_ms.push_back(hip.feature_ms);
    load_ms.push_back(hip.load_ms);
  }

  // The run's grid border (thesis §4.5.4: hips with the maximum/minimum alpha or CE).
  std::set<double> ces, alphas;
  for (const auto& hip : model.hips) {
    ces.insert(hip.ce_deg);
    alphas.insert(hip.alpha_deg);
  }
  // A parameter with fewer than 3 values in the run has no interior and makes no border.
  const auto at_end = [](const std::set<double>& set, double value) {
    return set.size() >= 3 && (value == *set.begin() || value == *set.rbegin());
  };
  const auto grid_border = [&](const TrainingHip& hip) {
    return at_end(ces, hip.ce_deg) || at_end(alphas, hip.alpha_deg);
  };

  const int case_steps[2] = {(p + 1) / 2, p};
  const int max_e = options.max_e_prime;
  std::vector<HipError> errors[2];
  std::vector<int> eligible[2];
  std::ostringstream loo_csv, estimates_csv;
  loo_csv << std::setprecision(10) << "hip,case,e_prime,method,mean_abs_error_percent,bordering,impinging\n";
  estimates_csv << std::setprecision(10) << "hip,case,e_prime,method,step,estimate,fe,error_percent\n";
  double loo_ms = 0, selection_ms = 0;
  std::map<int, int> chosen_e_prime[2];  // case -> target hip -> e' chosen on the other hips
  for (int c = 0; c < 2; ++c) {
    const int steps = case_steps[c];
    const Eigen::MatrixXd case_values = values.leftCols(steps);
    for (Eigen::Index i = 0; i < m; ++i) {
      bool complete = true;
      for (int j = 0; j < steps; ++j) complete = complete && std::isfinite(values(i, j)) && values(i, j) > 0.0;
      if (complete) eligible[c].push_back(static_cast<int>(i));
    }
    if (eligible[c].empty()) continue;
    start = std::chrono::steady_clock::now();
    const stats::PenetrationDepths case_depths =
        depths.known() ? stats::PenetrationDepths{depths.curvilinear_mm.leftCols(steps), depths.radial_mm.leftCols(steps)}
                       : stats::PenetrationDepths{};
    const auto rows = stats::leave_one_out(features, case_values, model.estimator.settings, max_e, eligible[c], {},
                                           case_depths);
    loo_ms += elapsed_ms(start);
    for (const auto& row : rows) {
      HipError error;
      error.hip = row.hip;
      error.method = static_cast<int>(row.method);
      error.e_prime = row.e_prime;
      error.bordering = row.result.bordering;
      error.mahalanobis = row.result.mahalanobis;
      error.outside = row.result.outside_components;
      std::vector<double> absolute;
      const TrainingHip& hip = model.hips[static_cast<std::size_t>(row.hip)];
      error.impinging = impinging_within(hip, steps);
      for (int j = 0; j < steps; ++j) {
        const double estimate = row.result.steps[static_cast<std::size_t>(j)].estimate;
        const double fe = values(row.hip, j);
        const double signed_error = 100.0 * (estimate - fe) / fe;
        error.estimate.push_back(estimate);
        error.signed_error.push_back(signed_error);
        absolute.push_back(std::abs(signed_error));
        estimates_csv << hip.name << ',' << c + 1 << ',' << row.e_prime << ',' << stats::to_string(row.method) << ','
                      << j + 1 << ',' << estimate << ',' << fe << ',' << signed_error << '\n';
      }
      error.mean_abs = mean_of(absolute);
      loo_csv << hip.name << ',' << c + 1 << ',' << row.e_prime << ',' << stats::to_string(row.method) << ','
              << error.mean_abs << ',' << (error.bordering ? 1 : 0) << ',' << flag_cell(error.impinging) << '\n';
      errors[c].push_back(std::move(error));
    }
    // pca_nn with e' chosen without the target (stats::select_e_prime on the other hips): the
    // outer leave-one-out already holds the estimate at every e', so the choice picks a row.
    start = std::chrono::steady_clock::now();
    for (const int target : eligible[c]) {
      Eigen::MatrixXd train_features(m - 1, features.cols()), train_values(m - 1, steps);
      for (Eigen::Index i = 0, r = 0; i < m; ++i) {
        if (i == target) continue;
        train_features.row(r) = features.row(i);
        train_values.row(r++) = case_values.row(i);
      }
      const stats::EPrimeSelection selection = stats::select_e_prime(
          train_features, train_values, model.estimator.settings, stats::EstimatorMethod::kPcaNn, max_e);
      chosen_e_prime[c][target] = selection.e_prime;
      const HipError* chosen = nullptr;
      for (const HipError& e : errors[c]) {
        if (e.hip == target && e.method == 0 && e.e_prime == selection.e_prime) chosen = &e;
      }
      if (!chosen) continue;
      const TrainingHip& hip = model.hips[static_cast<std::size_t>(target)];
      loo_csv << hip.name << ',' << c + 1 << ',' << selection.e_prime << ',' << kChosenMethod << ','
              << chosen->mean_abs << ',' << (chosen->bordering ? 1 : 0) << ',' << flag_cell(chosen->impinging) << '\n';
      for (int j = 0; j < steps; ++j) {
        estimates_csv << hip.name << ',' << c + 1 << ',' << selection.e_prime << ',' << kChosenMethod << ',' << j + 1
                      << ',' << chosen->estimate[static_cast<std::size_t>(j)] << ',' << values(target, j) << ','
                      << chosen->signed_error[static_cast<std::size_t>(j)] << '\n';
      }
    }
    selection_ms += elapsed_ms(start);
  }
  write_file_atomically(options.out_dir / "loo.csv", loo_csv.str());
  write_file_atomically(options.out_dir / "estimates.csv", estimates_csv.str());

  // Lookup: case -> (hip, method, e') -> error.
  std::map<std::tuple<int, int, int>, const HipError*> lookup[2];
  for (int c = 0; c < 2; ++c) {
    for (const auto& e : errors[c]) lookup[c][{e.hip, e.method, e.e_prime}] = &e;
  }
  const auto find = [&](int c, int hip, int method, int e_prime) -> const HipError* {
    const auto it = lookup[c].find({hip, method, e_prime});
    return it == lookup[c].end() ? nullptr : it->second;
  };

  EstimatorValidateSummary summary;
  // Group means at e' = max_e: all, interior (grid), flagged, not flagged.
  struct Group {
    double all = kNaN, grid_interior = kNaN, grid_border = kNaN, flagged = kNaN, unflagged = kNaN;
    double thesis_hips = kNaN;  // over the hips the thesis' table has a value for
    int thesis_count = 0;
  };
  Group groups[2][kMethods];
  Group chosen_group[2];
  for (int c = 0; c < 2; ++c) {
    summary.hips[c] = static_cast<int>(eligible[c].size());
    for (const int i : eligible[c]) {
      const HipError* e = find(c, i, 0, max_e);
      if (e && e->bordering) ++summary.bordering[c];
      if (e && e->impinging == 1) ++summary.impinging[c];
    }
    for (int method = 0; method < kMethods; ++method) {
      std::vector<double> all, interior, border, flagged, unflagged;
      for (const int i : eligible[c]) {
        const HipError* e = find(c, i, method, max_e);
        if (!e) continue;
        all.push_back(e->mean_abs);
        (grid_border(model.hips[static_cast<std::size_t>(i)]) ? border : interior).push_back(e->mean_abs);
        (e->bordering ? flagged : unflagged).push_back(e->mean_abs);
      }
      std::vector<double> thesis_set;
      for (const int i : eligible[c]) {
        const TrainingHip& hip = model.hips[static_cast<std::size_t>(i)];
        const HipError* e = find(c, i, method, max_e);
        if (e && std::isfinite(thesis_value(c, hip.ce_deg, hip.alpha_deg))) thesis_set.push_back(e->mean_abs);
      }
      groups[c][method] = {mean_of(all), mean_of(interior), mean_of(border), mean_of(flagged), mean_of(unflagged),
                           mean_of(thesis_set), static_cast<int>(thesis_set.size())};
      summary.mean_error[c][method] = groups[c][method].all;
      summary.interior_error[c][method] = groups[c][method].grid_interior;
    }
    // pca_nn with e' chosen on the training hips: the same groups.
    std::vector<double> all, interior, border, flagged, unflagged;
    for (const auto& [target, e_prime] : chosen_e_prime[c]) {
      const HipError* e = find(c, target, 0, e_prime);
      if (!e) continue;
      all.push_back(e->mean_abs);
      (grid_border(model.hips[static_cast<std::size_t>(target)]) ? border : interior).push_back(e->mean_abs);
      (e->bordering ? flagged : unflagged).push_back(e->mean_abs);
    }
    chosen_group[c] = {mean_of(all), mean_of(interior), mean_of(border), mean_of(flagged), mean_of(unflagged), kNaN, 0};
    summary.chosen_e_prime_error[c] = chosen_group[c].all;
    summary.chosen_e_prime_interior_error[c] = chosen_group[c].grid_interior;
  }

  // hips.csv: per hip provenance, flag and times.
  std::ostringstream hips_csv;
  hips_csv << std::setprecision(10)
           << "hip,ce_deg,alpha_deg,edge_mm,grid_border,bordering_case1,mahalanobis_case1,outside_components_case1,"
              "feature_ms,load_ms,misses,hash";
  for (int k = 0; k < e_all; ++k) hips_csv << ",score_" << k + 1;  // PCA of all hips of the run
  hips_csv << '\n';
  for (Eigen::Index i = 0; i < m; ++i) {
    const TrainingHip& hip = model.hips[static_cast<std::size_t>(i)];
    const HipError* e = find(0, static_cast<int>(i), 0, max_e);
    hips_csv << hip.name << ',' << hip.ce_deg << ',' << hip.alpha_deg << ',' << hip.edge_mm << ','
             << (grid_border(hip) ? 1 : 0) << ',' << (e ? (e->bordering ? "1" : "0") : "") << ','
             << (e ? fixed(e->mahalanobis, 3) : "") << ',' << (e ? std::to_string(e->outside) : "") << ','
             << hip.feature_ms << ',' << hip.load_ms << ',' << hip.misses << ',' << hip.hash;
    for (int k = 0; k < e_all; ++k) hips_csv << ',' << retrained.scores(i, k);
    hips_csv << '\n';
  }
  write_file_atomically(options.out_dir / "hips.csv", hips_csv.str());

  // Figures 73-74: mean error vs e' per method.
  for (int c = 0; c < 2; ++c) {
    LineChart chart;
    chart.title = c == 0 ? "Fig. 73: mean estimation error vs e', case 1 (first half of the motion)"
                         : "Fig. 74: mean estimation error vs e', case 2 (whole motion)";
    chart.x_label = "e' (effective features used)";
    chart.y_label = "mean |error| over hips (%)";
    for (int method = 0; method < kMethods; ++method) {
      if (!find(c, eligible[c].empty() ? 0 : eligible[c].front(), method, 1)) continue;
      Series all{std::string(stats::to_string(stats::kEstimatorMethods[method])) + " all", {}, {}, false, false, false};
      Series interior{std::string(stats::to_string(stats::kEstimatorMethods[method])) + " grid interior", {}, {}, true,
                      false, false};
      for (int e_prime = 1; e_prime <= max_e; ++e_prime) {
        std::vector<double> a, in;
        for (const int i : eligible[c]) {
          const HipError* e = find(c, i, method, e_prime);
          if (!e) continue;
          a.push_back(e->mean_abs);
          if (!grid_border(model.hips[static_cast<std::size_t>(i)])) in.push_back(e->mean_abs);
        }
        all.x.push_back(e_prime);
        all.y.push_back(mean_of(a));
        interior.x.push_back(e_prime);
        interior.y.push_back(mean_of(in));
      }
      chart.series.push_back(all);
      chart.series.push_back(interior);
    }
    if (c == 0) {
      chart.series.push_back({"thesis all, e'=10", {1.0, static_cast<double>(max_e)},
                              {literature::kEstimatorThesisMeanErrorPercent, literature::kEstimatorThesisMeanErrorPercent},
                              true, false, false});
      chart.series.push_back({"thesis interior, e'=10", {1.0, static_cast<double>(max_e)},
                              {literature::kEstimatorThesisInteriorErrorPercent,
                               literature::kEstimatorThesisInteriorErrorPercent},
                              true, false, false});
    }
    chart.notes.push_back(std::to_string(eligible[c].size()) + " hips, leave-one-out, e = " + std::to_string(e_all));
    write_svg(chart, options.out_dir / (c == 0 ? "fig73_case1.svg" : "fig74_case2.svg"));
  }

  // Figure 72: estimate vs FE for CE 20 / alpha 60 (or the first hip), case 2 when it has it.
  int fig72_hip = -1;
  for (Eigen::Index i = 0; i < m; ++i) {
    if (model.hips[static_cast<std::size_t>(i)].ce_deg == 20 && model.hips[static_cast<std::size_t>(i)].alpha_deg == 60) {
      fig72_hip = static_cast<int>(i);
    }
  }
  const int fig72_case = [&] {
    for (int c = 1; c >= 0; --c) {
      if (fig72_hip >= 0 && find(c, fig72_hip, 0, max_e)) return c;
    }
    return -1;
  }();
  std::string fig72_name;
  if (fig72_case >= 0) {
    const TrainingHip& hip = model.hips[static_cast<std::size_t>(fig72_hip)];
    fig72_name = "fig72_" + hip.name + ".svg";
    LineChart chart;
    chart.title = "Fig. 72: " + model.measure + " of " + hip.name + ", estimate (leave-one-out, e'=" +
                  std::to_string(max_e) + ") vs FE";
    chart.x_label = "rotation angle (deg)";
    chart.y_label = model.measure + " (MPa)";
    chart.y2_label = "signed error (%)";
    Series fe{"FE", {}, {}, true, false, false};
    for (int j = 0; j < case_steps[fig72_case]; ++j) {
      fe.x.push_back(model.angle_deg[static_cast<std::size_t>(j)]);
      fe.y.push_back(values(fig72_hip, j));
    }
    chart.series.push_back(fe);
    for (int method = 0; method < kMethods; ++method) {
      const HipError* e = find(fig72_case, fig72_hip, method, max_e);
      if (!e) continue;
      Series estimate{std::string(stats::to_string(stats::kEstimatorMethods[method])), fe.x, e->estimate, false, false, false};
      chart.series.push_back(estimate);
      if (method == 0) chart.series.push_back({"pca_nn error %", fe.x, e->signed_error, false, true, true});
    }
    write_svg(chart, options.out_dir / fig72_name);
  }

  // report.md
  std::ostringstream md;
  md << "# Contact-pressure estimator (thesis §4.5): leave-one-out validation\n\n"
     << "hipfai " << kVersion << " (" << kGitSha << "). FE quantity `" << model.measure << "`, " << m << " hips, "
     << p << " steps of the motion (case 1: steps 1-" << case_steps[0] << ", case 2: 1-" << case_steps[1] << "). "
     << "Features: " << model.grid.num_features() << " (" << model.grid.describe() << "), farthest crossing, miss = 0; "
     << "PCA e = " << e_all << " components of the " << m << " hips ("
     << fixed(100.0 * retrained.pca.variances.sum() / retrained.pca.total_variance, 1)
     << " % of the normalised variance; scale floor " << fixed(model.estimator.settings.pca.scale_floor, 2)
     << " mm); Eq. 22 shortlist " << model.estimator.settings.nearest << ". Each hip is estimated by a model trained "
     << "on the others (PCA refitted without it). Error of a hip = mean over the case's steps of "
        "|estimate - FE| / FE. Methods: `pca_nn` the thesis' Eq. 20-23 (weights |CC|), `knn` mean of the "
     << model.estimator.settings.knn_k << " nearest hips on the first e' scores, `ridge` ridge regression on the "
        "first e' scores (lambda by exact leave-one-out on the training hips), `depth_nn` (beyond the thesis, "
        "when the FE table has the penetration depths) the contact-free pressure of the "
     << model.estimator.settings.nearest << " nearest hips on the first e' scores, times the contact-free profile of "
        "the motion, times the impingement factor of the "
     << model.estimator.settings.nearest << " training (hip, step) pairs nearest in (curvilinear, radial) depth "
        "where the target's depths are non-zero (stats/depth_nn_estimator.h).\n\n";
  md << "## Mean error at e' = " << max_e << " (%)\n\n"
     << "| case | method | all hips | grid interior | grid border | flagged bordering | not flagged | the thesis' hips | thesis all | thesis interior |\n"
     << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (int c = 0; c < 2; ++c) {
    for (int method = 0; method < kMethods; ++method) {
      const Group& g = groups[c][method];
      if (g.all != g.all) continue;  // a method without rows (depth_nn without depths)
      md << "| " << c + 1 << " (" << summary.hips[c] << " hips) | " << stats::to_string(stats::kEstimatorMethods[method])
         << " | " << fixed(g.all) << " | " << fixed(g.grid_interior) << " | " << fixed(g.grid_border) << " | "
         << fixed(g.flagged) << " | " << fixed(g.unflagged) << " | " << fixed(g.thesis_hips) << " (" << g.thesis_count
         << ") | "
         << (method == 0 ? (c == 0 ? "5.14" : fixed(thesis_table_mean(1, false)) + " (Table 13)") : "") << " | " << (method == 0 ? fixed(thesis_table_mean(c, true)) + (c == 0 ? "" : " (Table 13)") : "")
         << " |\n";
    }
  }
  md << "\nGrid border = the run's minimum/maximum CE or alpha (the thesis' \"bordering\" hips, §4.5.4); flagged "
        "bordering = the estimator's own flag (the target's PCA scores leave the training range on a component "
        "holding >= "
     << fixed(100.0 * model.estimator.settings.bordering_min_variance_share, 0)
     << " % of the variance, or its Mahalanobis distance over those components exceeds every training hip's). "
        "The thesis' case-2 numbers are the means of its Table 13 (20 hips; interior = CE 10-30 and alpha 50-70); "
        "its case-1 interior mean of Table 12 is " << fixed(thesis_table_mean(0, true)) << " %.\n\n";

  md << "## pca_nn with e' chosen without the target (`pca_nn_cv`)\n\n"
     << "The thesis fixes e' = 10 after seeing its error curves (Figs. 73-74), i.e. on the hips it then reports. "
        "Here, for each held-out hip, e' in 1.." << max_e << " is the one with the smallest leave-one-out error "
        "among the other hips alone (stats::select_e_prime, ties to the smaller e'), and the hip is estimated at that "
        "e'. Rows `pca_nn_cv` of loo.csv and estimates.csv (their e_prime is the chosen one). Selection time "
     << fixed(selection_ms / 1000.0, 2) << " s.\n\n"
     << "| case | all hips | grid interior | grid border | flagged bordering | not flagged | e' chosen (hips) |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (int c = 0; c < 2; ++c) {
    std::map<int, int> histogram;
    for (const auto& [target, e_prime] : chosen_e_prime[c]) ++histogram[e_prime];
    std::string chosen;
    for (const auto& [e_prime, count] : histogram) {
      chosen += (chosen.empty() ? "" : ", ") + std::to_string(e_prime) + " (" + std::to_string(count) + ")";
    }
    const Group& g = chosen_group[c];
    md << "| " << c + 1 << " | " << fixed(g.all) << " | " << fixed(g.grid_interior) << " | " << fixed(g.grid_border)
       << " | " << fixed(g.flagged) << " | " << fixed(g.unflagged) << " | " << chosen << " |\n";
  }
  md << '\n';

  // Where the estimator fails: the hips that impinge. The FE's peak pressure jumps when cam and rim
  // meet, at a step that depends on both CE and alpha, and no geometric hull test sees it; the
  // penetration method does (thesis §4.3: its depths correlate with the FE).
  bool depths_known = false;
  for (int c = 0; c < 2; ++c) {
    for (const int i : eligible[c]) {
      const HipError* e = find(c, i, 0, max_e);
      depths_known = depths_known || (e && e->impinging >= 0);
    }
  }
  if (depths_known) {
    md << "## Where it fails: hips that impinge (the penetration method's depths)\n\n"
       << "`impinging` (loo.csv) = the FE table's penetration depth (max of max_curvilinear_mm and max_radial_mm, "
          "`hipfai study validate`) is > 0 at one of the case's steps. Mean error at e' = "
       << max_e << " (%), with the number of hips:\n\n"
       << "| case | method | impinging | not impinging | flagged bordering or impinging | neither |\n"
       << "|---|---|---|---|---|---|\n";
    for (int c = 0; c < 2; ++c) {
      for (int method = 0; method < kMethods; ++method) {
        std::vector<double> impinging, clear, either, neither;
        for (const int i : eligible[c]) {
          const HipError* e = find(c, i, method, max_e);
          if (!e || e->impinging < 0) continue;
          (e->impinging == 1 ? impinging : clear).push_back(e->mean_abs);
          // The flags of the pca_nn row (the flag is the target's, the same for every method).
          const HipError* flag = find(c, i, 0, max_e);
          (e->impinging == 1 || (flag && flag->bordering) ? either : neither).push_back(e->mean_abs);
        }
        if (impinging.empty() && clear.empty()) continue;
        const auto cell = [](const std::vector<double>& v) { return fixed(mean_of(v)) + " (" + std::to_string(v.size()) + ")"; };
        md << "| " << c + 1 << " | " << stats::to_string(stats::kEstimatorMethods[method]) << " | " << cell(impinging)
           << " | " << cell(clear) << " | " << cell(either) << " | " << cell(neither) << " |\n";
      }
    }
    md << "\nThe geometric flag (bordering) says the target's features lie outside the training set; it cannot "
          "see a target whose geometry is inside but whose FE response changes regime (impingement begins). The "
          "penetration method computes that regime from the same geometry, in milliseconds, without the FE.\n\n";
  }

  for (int c = 0; c < 2; ++c) {
    md << "## Table " << (c == 0 ? "12" : "13") << ": error per hip, case " << c + 1 << ", e' = " << max_e
       << " (%): ours pca_nn / thesis\n\n| alpha \\ CE |";
    for (const double ce : ces) md << ' ' << ce << " |";
    md << "\n|---|";
    for (std::size_t k = 0; k < ces.size(); ++k) md << "---|";
    md << '\n';
    for (const double alpha : alphas) {
      md << "| " << alpha << " |";
      for (const double ce : ces) {
        std::string cell = "n/a";
        for (const int i : eligible[c]) {
          const TrainingHip& hip = model.hips[static_cast<std::size_t>(i)];
          if (hip.ce_deg != ce || hip.alpha_deg != alpha) continue;
          const HipError* e = find(c, i, 0, max_e);
          cell = fixed(e->mean_abs) + (e->bordering ? "*" : "") + (e->impinging == 1 ? "!" : "");
        }
        md << ' ' << cell << " / " << fixed(thesis_value(c, ce, alpha)) << " |";
      }
      md << '\n';
    }
    md << "\n`*` flagged bordering; `!` impinging within the case's steps (penetration method); n/a: the hip is not in "
          "the run or has a failed FE step in the case's steps.\n\n";
  }

  md << "## Per hip: methods side by side (e' = " << max_e << ", %)\n\n"
     << "| hip | grid border | flag (case 1) | Mahalanobis | case 1 pca_nn | knn | ridge | depth_nn | best | case 2 pca_nn | knn | ridge | depth_nn | best |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  int wins[2][kMethods] = {};
  for (Eigen::Index i = 0; i < m; ++i) {
    const TrainingHip& hip = model.hips[static_cast<std::size_t>(i)];
    const HipError* flag = find(0, static_cast<int>(i), 0, max_e);
    md << "| " << hip.name << " | " << (grid_border(hip) ? "yes" : "no") << " | "
       << (flag ? (flag->bordering ? "bordering" : "interior") : "-") << " | " << (flag ? fixed(flag->mahalanobis) : "-")
       << " |";
    for (int c = 0; c < 2; ++c) {
      int best = -1;
      for (int method = 0; method < kMethods; ++method) {
        const HipError* e = find(c, static_cast<int>(i), method, max_e);
        md << ' ' << (e ? fixed(e->mean_abs) : "-") << " |";
        if (e && (best < 0 || e->mean_abs < find(c, static_cast<int>(i), best, max_e)->mean_abs)) best = method;
      }
      if (best >= 0) ++wins[c][best];
      md << ' ' << (best >= 0 ? stats::to_string(stats::kEstimatorMethods[best]) : "-") << " |";
    }
    md << '\n';
  }
  md << "\nWins (lowest error per hip): ";
  for (int c = 0; c < 2; ++c) {
    md << "case " << c + 1 << ":";
    for (int method = 0; method < kMethods; ++method) md << ' ' << stats::to_string(stats::kEstimatorMethods[method]) << ' ' << wins[c][method];
    md << (c == 0 ? "; " : ".\n\n");
  }

  // What the PCA found: each component's share of the variance and its correlation with the hips'
  // CE and alpha (the generator's parameters, never given to the estimator).
  md << "## The PCA of all " << m << " hips\n\n| component | variance share (%) | significant | r with CE | r with alpha "
        "| r with " << model.measure << " at the last step |\n|---|---|---|---|---|---|\n";
  {
    std::vector<double> ce, alpha;
    for (const auto& hip : model.hips) {
      ce.push_back(hip.ce_deg);
      alpha.push_back(hip.alpha_deg);
    }
    for (int k = 0; k < e_all; ++k) {
      const Eigen::VectorXd score = retrained.scores.col(k);
      const std::vector<double> x(score.data(), score.data() + score.size());
      const auto r_ce = stats::pearson(x, ce), r_alpha = stats::pearson(x, alpha);
      md << "| " << k + 1 << " | " << fixed(100.0 * retrained.pca.variances(k) / retrained.pca.total_variance, 1) << " | "
         << (k < retrained.significant_components ? "yes" : "no") << " | " << (r_ce.defined ? fixed(r_ce.r) : "-")
         << " | " << (r_alpha.defined ? fixed(r_alpha.r) : "-") << " | " << fixed(retrained.correlations(k, p - 1)) << " |\n";
    }
  }
  md << "\n## Figures\n\n![Fig. 73](fig73_case1.svg)\n\n![Fig. 74](fig74_case2.svg)\n\n";
  if (!fig72_name.empty()) md << "![Fig. 72](" << fig72_name << ")\n\n";

  md << "## Times (this machine)\n\n| what | time |\n|---|---|\n";
  if (quick_fe_s > 0) md << "| FE sweep (--quick, study validate) | " << fixed(quick_fe_s, 1) << " s |\n";
  md << "| load one hip's tissues (mean / max) | " << fixed(mean_of(load_ms), 1) << " / "
     << fixed(*std::max_element(load_ms.begin(), load_ms.end()), 1) << " ms |\n"
     << "| features of one hip (mean / max; edge " << fixed(model.hips.front().edge_mm, 1) << " mm) | "
     << fixed(mean_of(feature_ms), 1) << " / " << fixed(*std::max_element(feature_ms.begin(), feature_ms.end()), 1)
     << " ms |\n"
     << "| train on " << m << " hips (PCA + correlations, features given) | " << fixed(train_ms, 2) << " ms |\n"
     << "| one prediction, e' = " << e_all << ", all " << p << " steps, depths given: pca_nn / knn / ridge / depth_nn | "
     << fixed(predict_ms[0], 3) << " / " << fixed(predict_ms[1], 3) << " / " << fixed(predict_ms[2], 3) << " / " << fixed(predict_ms[3], 3) << " ms |\n"
     << "| leave-one-out, both cases, every method x e' 1.." << max_e << " | " << fixed(loo_ms / 1000.0, 2) << " s |\n"
     << "| whole training pipeline (load, features, train) | " << fixed(pipeline_ms / 1000.0, 2) << " s |\n\n"
     << "Files: `loo.csv`, `estimates.csv`, `hips.csv`, `model.h5` (trained on all " << m << " hips).\n";
  summary.report = options.out_dir / "report.md";
  write_file_atomically(summary.report, md.str());
  return summary;
}

}  // namespace hipfai::studies
