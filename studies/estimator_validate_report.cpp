// hipfai — the files of `estimator validate` from its result (see estimator_validate_report.h).
#include "studies/estimator_validate_report.h"

#include "core/atomic_file.h"
#include "core/literature.h"
#include "core/text_format.h"
#include "core/version.h"
#include "stats/interval_coverage.h"
#include "stats/pearson.h"
#include "studies/estimator_model_file.h"
#include "studies/reports/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace hipfai::studies {

namespace {

using stats::kNumEstimatorMethods;
// The `method` of pca_nn rows whose e' was chosen by leave-one-out inside the training hips.
constexpr const char* kChosenMethod = "pca_nn_cv";

std::string flag_cell(int flag) { return flag < 0 ? std::string() : std::to_string(flag); }

std::string method_name(int method) { return std::string(stats::to_string(stats::kEstimatorMethods[method])); }

const TrainingHip& hip_of(const EstimatorValidateResult& r, int i) { return r.model.hips[static_cast<std::size_t>(i)]; }

const EstimatorHipError* find(const EstimatorValidateResult& r, int c, int hip, int method, int e_prime) {
  return r.cases[static_cast<std::size_t>(c)].find(hip, method, e_prime);
}

// loo.csv (one row per hip, case, e' and method) and estimates.csv (the same per step): each
// case's leave-one-out rows, then its pca_nn rows at the e' chosen without the target.
void write_loo_files(const EstimatorValidateResult& r, const std::filesystem::path& dir) {
  const Eigen::MatrixXd& values = r.model.estimator.values;
  std::ostringstream loo_csv, estimates_csv;
  loo_csv << std::setprecision(10) << "hip,case,e_prime,method,mean_abs_error_percent,bordering,impinging\n";
  estimates_csv << std::setprecision(10) << "hip,case,e_prime,method,step,estimate,fe,error_percent\n";
  const auto write_rows = [&](const EstimatorHipError& e, int c, int steps, const std::string& method) {
    const TrainingHip& hip = hip_of(r, e.hip);
    for (int j = 0; j < steps; ++j) {
      estimates_csv << hip.name << ',' << c + 1 << ',' << e.e_prime << ',' << method << ',' << j + 1 << ','
                    << e.estimate[static_cast<std::size_t>(j)] << ',' << values(e.hip, j) << ','
                    << e.signed_error[static_cast<std::size_t>(j)] << '\n';
    }
    loo_csv << hip.name << ',' << c + 1 << ',' << e.e_prime << ',' << method << ',' << e.mean_abs << ','
            << (e.bordering ? 1 : 0) << ',' << flag_cell(e.impinging) << '\n';
  };
  for (int c = 0; c < 2; ++c) {
    const EstimatorValidateCase& one = r.cases[static_cast<std::size_t>(c)];
    for (const EstimatorHipError& e : one.errors) write_rows(e, c, one.steps, method_name(e.method));
    for (const int target : one.eligible) {
      const auto chosen_e = one.chosen_e_prime.find(target);
      const EstimatorHipError* chosen =
          chosen_e == one.chosen_e_prime.end() ? nullptr : one.find(target, 0, chosen_e->second);
      if (chosen) write_rows(*chosen, c, one.steps, kChosenMethod);
    }
  }
  write_file_atomically(dir / "loo.csv", loo_csv.str());
  write_file_atomically(dir / "estimates.csv", estimates_csv.str());
}

// hips.csv: per hip provenance, flag and times.
void write_hips_csv(const EstimatorValidateResult& r, const std::filesystem::path& dir) {
  std::ostringstream hips_csv;
  hips_csv << std::setprecision(10)
           << "hip,ce_deg,alpha_deg,edge_mm,grid_border,bordering_case1,mahalanobis_case1,outside_components_case1,"
              "feature_ms,load_ms,misses,hash";
  for (int k = 0; k < r.components; ++k) hips_csv << ",score_" << k + 1;  // PCA of all hips of the run
  hips_csv << '\n';
  for (std::size_t i = 0; i < r.model.hips.size(); ++i) {
    const TrainingHip& hip = r.model.hips[i];
    const EstimatorHipError* e = find(r, 0, static_cast<int>(i), 0, r.max_e_prime);
    hips_csv << hip.name << ',' << hip.ce_deg << ',' << hip.alpha_deg << ',' << hip.edge_mm << ','
             << (r.grid_border[i] ? 1 : 0) << ',' << (e ? (e->bordering ? "1" : "0") : "") << ','
             << (e ? fixed_or(e->mahalanobis, 3, "-") : "") << ',' << (e ? std::to_string(e->outside) : "") << ','
             << hip.feature_ms << ',' << hip.load_ms << ',' << hip.misses << ',' << hip.hash;
    for (int k = 0; k < r.components; ++k) hips_csv << ',' << r.retrained.scores(static_cast<Eigen::Index>(i), k);
    hips_csv << '\n';
  }
  write_file_atomically(dir / "hips.csv", hips_csv.str());
}

// Figures 73-74: mean error vs e' per method.
void write_error_curves(const EstimatorValidateResult& r, const std::filesystem::path& dir) {
  const int max_e = r.max_e_prime;
  for (int c = 0; c < 2; ++c) {
    const std::vector<int>& eligible = r.cases[static_cast<std::size_t>(c)].eligible;
    LineChart chart;
    chart.title = c == 0 ? "Fig. 73: mean estimation error vs e', case 1 (first half of the motion)"
                         : "Fig. 74: mean estimation error vs e', case 2 (whole motion)";
    chart.x_label = "e' (effective features used)";
    chart.y_label = "mean |error| over hips (%)";
    for (int method = 0; method < kNumEstimatorMethods; ++method) {
      if (!find(r, c, eligible.empty() ? 0 : eligible.front(), method, 1)) continue;
      Series all{method_name(method) + " all", {}, {}, false, false, false};
      Series interior{method_name(method) + " grid interior", {}, {}, true, false, false};
      for (int e_prime = 1; e_prime <= max_e; ++e_prime) {
        std::vector<double> a, in;
        for (const int i : eligible) {
          const EstimatorHipError* e = find(r, c, i, method, e_prime);
          if (!e) continue;
          a.push_back(e->mean_abs);
          if (!r.grid_border[static_cast<std::size_t>(i)]) in.push_back(e->mean_abs);
        }
        all.x.push_back(e_prime);
        all.y.push_back(finite_mean(a));
        interior.x.push_back(e_prime);
        interior.y.push_back(finite_mean(in));
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
    chart.notes.push_back(std::to_string(eligible.size()) + " hips, leave-one-out, e = " + std::to_string(r.components));
    write_svg(chart, dir / (c == 0 ? "fig73_case1.svg" : "fig74_case2.svg"));
  }
}

// Figure 72: estimate vs FE for CE 20 / alpha 60 (or none), case 2 when it has it. Returns the
// file's name, empty when not written.
std::string write_fig72(const EstimatorValidateResult& r, const std::filesystem::path& dir) {
  const EstimatorModel& model = r.model;
  const int max_e = r.max_e_prime;
  int fig72_hip = -1;
  for (std::size_t i = 0; i < model.hips.size(); ++i) {
    if (model.hips[i].ce_deg == 20 && model.hips[i].alpha_deg == 60) fig72_hip = static_cast<int>(i);
  }
  const int fig72_case = [&] {
    for (int c = 1; c >= 0; --c) {
      if (fig72_hip >= 0 && find(r, c, fig72_hip, 0, max_e)) return c;
    }
    return -1;
  }();
  if (fig72_case < 0) return {};
  const TrainingHip& hip = hip_of(r, fig72_hip);
  const std::string fig72_name = "fig72_" + hip.name + ".svg";
  LineChart chart;
  chart.title = "Fig. 72: " + model.measure + " of " + hip.name + ", estimate (leave-one-out, e'=" +
                std::to_string(max_e) + ") vs FE";
  chart.x_label = "rotation angle (deg)";
  chart.y_label = model.measure + " (MPa)";
  chart.y2_label = "signed error (%)";
  Series fe{"FE", {}, {}, true, false, false};
  for (int j = 0; j < r.cases[static_cast<std::size_t>(fig72_case)].steps; ++j) {
    fe.x.push_back(model.angle_deg[static_cast<std::size_t>(j)]);
    fe.y.push_back(model.estimator.values(fig72_hip, j));
  }
  chart.series.push_back(fe);
  for (int method = 0; method < kNumEstimatorMethods; ++method) {
    const EstimatorHipError* e = find(r, fig72_case, fig72_hip, method, max_e);
    if (!e) continue;
    Series estimate{method_name(method), fe.x, e->estimate, false, false, false};
    chart.series.push_back(estimate);
    if (method == 0) chart.series.push_back({"pca_nn error %", fe.x, e->signed_error, false, true, true});
  }
  write_svg(chart, dir / fig72_name);
  return fig72_name;
}

// report.md: what was run (grid, PCA, methods).
void md_introduction(std::ostringstream& md, const EstimatorValidateResult& r) {
  const EstimatorModel& model = r.model;
  const auto m = model.hips.size();
  md << "# Contact-pressure estimator (thesis §4.5): leave-one-out validation\n\n"
     << "hipfai " << kVersion << " (" << kGitSha << "). FE quantity `" << model.measure << "`, " << m << " hips, "
     << r.steps << " steps of the motion (case 1: steps 1-" << r.cases[0].steps << ", case 2: 1-" << r.cases[1].steps
     << "). "
     << "Features: " << model.grid.num_features() << " (" << model.grid.describe() << "), farthest crossing, miss = 0; "
     << "PCA e = " << r.components << " components of the " << m << " hips ("
     << fixed_or(100.0 * r.retrained.pca.variances.sum() / r.retrained.pca.total_variance, 1, "-")
     << " % of the normalised variance; scale floor " << fixed_or(model.estimator.settings.pca.scale_floor, 2, "-")
     << " mm); Eq. 22 shortlist " << model.estimator.settings.nearest << ". Each hip is estimated by a model trained "
     << "on the others (PCA refitted without it). Error of a hip = mean over the case's steps of "
        "|estimate - FE| / FE. Methods: `pca_nn` the thesis' Eq. 20-23 (weights |CC|), `knn` mean of the "
     << model.estimator.settings.knn_k << " nearest hips on the first e' scores, `ridge` ridge regression on the "
        "first e' scores (lambda by exact leave-one-out on the training hips), `depth_nn` (beyond the thesis, "
        "when the FE table has the penetration depths) the contact-free pressure of the "
     << model.estimator.settings.nearest << " nearest hips on the first e' scores, times the contact-free profile of "
        "the motion, times the impingement factor of the "
     << model.estimator.settings.nearest << " training (hip, step) pairs nearest in (curvilinear, radial) depth "
        "where the target's depths are non-zero, and `depth_aligned` (beyond the thesis) the same level and "
        "profile, but each hip's own contact-free course where it is free of contact, and at the contact steps the "
        "factor of the "
     << model.estimator.settings.nearest << " nearest penetrating hips on the first e' scores, each read off its own "
        "path through the depth plane at the point nearest the target's depths (stats/depth_nn_estimator.h).\n\n";
}

// report.md: the group means at e' = max, per case and method, beside the thesis'.
void md_mean_errors(std::ostringstream& md, const EstimatorValidateResult& r) {
  md << "## Mean error at e' = " << r.max_e_prime << " (%)\n\n"
     << "| case | method | all hips | grid interior | grid border | flagged bordering | not flagged | the thesis' hips | thesis all | thesis interior |\n"
     << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (int c = 0; c < 2; ++c) {
    for (int method = 0; method < kNumEstimatorMethods; ++method) {
      const EstimatorErrorGroup& g = r.cases[static_cast<std::size_t>(c)].groups[static_cast<std::size_t>(method)];
      if (g.all != g.all) continue;  // a method without rows (depth_nn without depths)
      md << "| " << c + 1 << " (" << r.summary.hips[c] << " hips) | " << method_name(method) << " | " << fixed_or(g.all, 2, "-")
         << " | " << fixed_or(g.grid_interior, 2, "-") << " | " << fixed_or(g.grid_border, 2, "-") << " | " << fixed_or(g.flagged, 2, "-") << " | "
         << fixed_or(g.unflagged, 2, "-") << " | " << fixed_or(g.thesis_hips, 2, "-") << " (" << g.thesis_count << ") | "
         << (method == 0 ? (c == 0 ? "5.14" : fixed_or(thesis_estimator_table_mean(1, false), 2, "-") + " (Table 13)") : "")
         << " | "
         << (method == 0 ? fixed_or(thesis_estimator_table_mean(c, true), 2, "-") + (c == 0 ? "" : " (Table 13)") : "")
         << " |\n";
    }
  }
  md << "\nGrid border = the run's minimum/maximum CE or alpha (the thesis' \"bordering\" hips, §4.5.4); flagged "
        "bordering = the estimator's own flag (the target's PCA scores leave the training range on a component "
        "holding >= "
     << fixed_or(100.0 * r.model.estimator.settings.bordering_min_variance_share, 0, "-")
     << " % of the variance, or its Mahalanobis distance over those components exceeds every training hip's). "
        "The thesis' case-2 numbers are the means of its Table 13 (20 hips; interior = CE 10-30 and alpha 50-70); "
        "its case-1 interior mean of Table 12 is " << fixed_or(thesis_estimator_table_mean(0, true), 2, "-") << " %.\n\n";
}

// report.md: pca_nn at the e' chosen without the target.
void md_chosen_e_prime(std::ostringstream& md, const EstimatorValidateResult& r) {
  md << "## pca_nn with e' chosen without the target (`pca_nn_cv`)\n\n"
     << "The thesis fixes e' = 10 after seeing its error curves (Figs. 73-74), i.e. on the hips it then reports. "
        "Here, for each held-out hip, e' in 1.." << r.max_e_prime << " is the one with the smallest leave-one-out error "
        "among the other hips alone (stats::select_e_prime, ties to the smaller e'), and the hip is estimated at that "
        "e'. Rows `pca_nn_cv` of loo.csv and estimates.csv (their e_prime is the chosen one). Selection time "
     << fixed_or(r.selection_ms / 1000.0, 2, "-") << " s.\n\n"
     << "| case | all hips | grid interior | grid border | flagged bordering | not flagged | e' chosen (hips) |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (int c = 0; c < 2; ++c) {
    const EstimatorValidateCase& one = r.cases[static_cast<std::size_t>(c)];
    std::map<int, int> histogram;
    for (const auto& [target, e_prime] : one.chosen_e_prime) ++histogram[e_prime];
    std::string chosen;
    for (const auto& [e_prime, count] : histogram) {
      chosen += (chosen.empty() ? "" : ", ") + std::to_string(e_prime) + " (" + std::to_string(count) + ")";
    }
    const EstimatorErrorGroup& g = one.chosen_group;
    md << "| " << c + 1 << " | " << fixed_or(g.all, 2, "-") << " | " << fixed_or(g.grid_interior, 2, "-") << " | " << fixed_or(g.grid_border, 2, "-")
       << " | " << fixed_or(g.flagged, 2, "-") << " | " << fixed_or(g.unflagged, 2, "-") << " | " << chosen << " |\n";
  }
  md << '\n';
}

// report.md: where the estimator fails, the hips that impinge. The FE's peak pressure jumps when
// cam and rim meet, at a step that depends on both CE and alpha, and no geometric hull test sees
// it; the penetration method does (thesis §4.3: its depths correlate with the FE). Nothing when
// the FE table has no depths.
void md_impinging(std::ostringstream& md, const EstimatorValidateResult& r) {
  const int max_e = r.max_e_prime;
  bool depths_known = false;
  for (int c = 0; c < 2; ++c) {
    for (const int i : r.cases[static_cast<std::size_t>(c)].eligible) {
      const EstimatorHipError* e = find(r, c, i, 0, max_e);
      depths_known = depths_known || (e && e->impinging >= 0);
    }
  }
  if (!depths_known) return;
  md << "## Where it fails: hips that impinge (the penetration method's depths)\n\n"
     << "`impinging` (loo.csv) = the FE table's penetration depth (max of max_curvilinear_mm and max_radial_mm, "
        "`hipfai study validate`) is > 0 at one of the case's steps. Mean error at e' = "
     << max_e << " (%), with the number of hips:\n\n"
     << "| case | method | impinging | not impinging | flagged bordering or impinging | neither |\n"
     << "|---|---|---|---|---|---|\n";
  for (int c = 0; c < 2; ++c) {
    for (int method = 0; method < kNumEstimatorMethods; ++method) {
      std::vector<double> impinging, clear, either, neither;
      for (const int i : r.cases[static_cast<std::size_t>(c)].eligible) {
        const EstimatorHipError* e = find(r, c, i, method, max_e);
        if (!e || e->impinging < 0) continue;
        (e->impinging == 1 ? impinging : clear).push_back(e->mean_abs);
        // The flags of the pca_nn row (the flag is the target's, the same for every method).
        const EstimatorHipError* flag = find(r, c, i, 0, max_e);
        (e->impinging == 1 || (flag && flag->bordering) ? either : neither).push_back(e->mean_abs);
      }
      if (impinging.empty() && clear.empty()) continue;
      const auto cell = [](const std::vector<double>& v) { return fixed_or(finite_mean(v), 2, "-") + " (" + std::to_string(v.size()) + ")"; };
      md << "| " << c + 1 << " | " << method_name(method) << " | " << cell(impinging) << " | " << cell(clear) << " | "
         << cell(either) << " | " << cell(neither) << " |\n";
    }
  }
  md << "\nThe geometric flag (bordering) says the target's features lie outside the training set; it cannot "
        "see a target whose geometry is inside but whose FE response changes regime (impingement begins). The "
        "penetration method computes that regime from the same geometry, in milliseconds, without the FE.\n\n";
}

// report.md: Tables 12 and 13, our pca_nn error per hip on the CE x alpha grid beside the thesis'.
void md_thesis_tables(std::ostringstream& md, const EstimatorValidateResult& r) {
  const int max_e = r.max_e_prime;
  for (int c = 0; c < 2; ++c) {
    md << "## Table " << (c == 0 ? "12" : "13") << ": error per hip, case " << c + 1 << ", e' = " << max_e
       << " (%): ours pca_nn / thesis\n\n| alpha \\ CE |";
    for (const double ce : r.ces) md << ' ' << ce << " |";
    md << "\n|---|";
    for (std::size_t k = 0; k < r.ces.size(); ++k) md << "---|";
    md << '\n';
    for (const double alpha : r.alphas) {
      md << "| " << alpha << " |";
      for (const double ce : r.ces) {
        std::string cell = "n/a";
        for (const int i : r.cases[static_cast<std::size_t>(c)].eligible) {
          const TrainingHip& hip = hip_of(r, i);
          if (hip.ce_deg != ce || hip.alpha_deg != alpha) continue;
          const EstimatorHipError* e = find(r, c, i, 0, max_e);
          cell = fixed_or(e->mean_abs, 2, "-") + (e->bordering ? "*" : "") + (e->impinging == 1 ? "!" : "");
        }
        md << ' ' << cell << " / " << fixed_or(thesis_estimator_error(c, ce, alpha), 2, "-") << " |";
      }
      md << '\n';
    }
    md << "\n`*` flagged bordering; `!` impinging within the case's steps (penetration method); n/a: the hip is not in "
          "the run or has a failed FE step in the case's steps.\n\n";
  }
}

// report.md: per hip, every method's error in both cases, the best one, and the wins.
void md_per_hip(std::ostringstream& md, const EstimatorValidateResult& r) {
  const int max_e = r.max_e_prime;
  md << "## Per hip: methods side by side (e' = " << max_e << ", %)\n\n"
     << "| hip | grid border | flag (case 1) | Mahalanobis |";
  for (int c = 0; c < 2; ++c) {
    for (int method = 0; method < kNumEstimatorMethods; ++method) {
      md << (method == 0 ? " case " + std::to_string(c + 1) + " " : " ") << method_name(method) << " |";
    }
    md << " best |";
  }
  md << "\n|---|---|---|---|";
  for (int column = 0; column < 2 * (kNumEstimatorMethods + 1); ++column) md << "---|";
  md << '\n';
  int wins[2][kNumEstimatorMethods] = {};
  for (std::size_t i = 0; i < r.model.hips.size(); ++i) {
    const int hip = static_cast<int>(i);
    const EstimatorHipError* flag = find(r, 0, hip, 0, max_e);
    md << "| " << r.model.hips[i].name << " | " << (r.grid_border[i] ? "yes" : "no") << " | "
       << (flag ? (flag->bordering ? "bordering" : "interior") : "-") << " | " << (flag ? fixed_or(flag->mahalanobis, 2, "-") : "-")
       << " |";
    for (int c = 0; c < 2; ++c) {
      int best = -1;
      for (int method = 0; method < kNumEstimatorMethods; ++method) {
        const EstimatorHipError* e = find(r, c, hip, method, max_e);
        md << ' ' << (e ? fixed_or(e->mean_abs, 2, "-") : "-") << " |";
        if (e && (best < 0 || e->mean_abs < find(r, c, hip, best, max_e)->mean_abs)) best = method;
      }
      if (best >= 0) ++wins[c][best];
      md << ' ' << (best >= 0 ? method_name(best) : "-") << " |";
    }
    md << '\n';
  }
  md << "\nWins (lowest error per hip): ";
  for (int c = 0; c < 2; ++c) {
    md << "case " << c + 1 << ":";
    for (int method = 0; method < kNumEstimatorMethods; ++method) md << ' ' << method_name(method) << ' ' << wins[c][method];
    md << (c == 0 ? "; " : ".\n\n");
  }
}

// report.md: what the PCA found, each component's share of the variance and its correlation with
// the hips' CE and alpha (the generator's parameters, never given to the estimator).
void md_pca(std::ostringstream& md, const EstimatorValidateResult& r) {
  const stats::TrainedEstimator& pca = r.retrained;
  md << "## The PCA of all " << r.model.hips.size() << " hips\n\n| component | variance share (%) | significant | r with CE | r with alpha "
        "| r with " << r.model.measure << " at the last step |\n|---|---|---|---|---|---|\n";
  std::vector<double> ce, alpha;
  for (const auto& hip : r.model.hips) {
    ce.push_back(hip.ce_deg);
    alpha.push_back(hip.alpha_deg);
  }
  for (int k = 0; k < r.components; ++k) {
    const Eigen::VectorXd score = pca.scores.col(k);
    const std::vector<double> x(score.data(), score.data() + score.size());
    const auto r_ce = stats::pearson(x, ce), r_alpha = stats::pearson(x, alpha);
    md << "| " << k + 1 << " | " << fixed_or(100.0 * pca.pca.variances(k) / pca.pca.total_variance, 1, "-") << " | "
       << (k < pca.significant_components ? "yes" : "no") << " | " << (r_ce.defined ? fixed_or(r_ce.r, 2, "-") : "-") << " | "
       << (r_alpha.defined ? fixed_or(r_alpha.r, 2, "-") : "-") << " | " << fixed_or(pca.correlations(k, r.steps - 1), 2, "-") << " |\n";
  }
}

// How often each method's leave-one-out intervals hold the FE value, and how many of the steps
// with an error above 10 % carry the bordering flag (stats/interval_coverage.h), at e' = max:
// report.md's section and coverage.csv.
void write_coverage(std::ostringstream& md, const EstimatorValidateResult& r, const std::filesystem::path& dir) {
  constexpr double kLargeError = 0.10;
  std::ostringstream csv;
  csv << std::setprecision(10)
      << "case,method,e_prime,steps,undefined_steps,covered,coverage,large_error_steps,large_error_flagged,flag_recall\n";
  md << "\n## Intervals and the flag (leave-one-out, e' = " << r.max_e_prime << ")\n\n"
     << "Share of the (hip, step) pairs whose FE value lies in the method's interval (pca_nn, knn: the range "
        "of the hips the estimate came from; ridge: 95 % predictive; depth_nn: its bounds), and of the steps "
        "whose error exceeds 10 %, how many the bordering flag marks. File: `coverage.csv`.\n\n"
     << "| case | method | steps | FE inside the interval | steps with error > 10 % | flagged of them |\n"
     << "|---|---|---|---|---|---|\n";
  for (int c = 0; c < 2; ++c) {
    const EstimatorValidateCase& one = r.cases[static_cast<std::size_t>(c)];
    for (int m = 0; m < stats::kNumEstimatorMethods; ++m) {
      std::vector<stats::IntervalRow> rows;
      for (const int hip : one.eligible) {
        const EstimatorHipError* e = one.find(hip, m, r.max_e_prime);
        if (e == nullptr) continue;
        for (int j = 0; j < one.steps; ++j) {
          const auto s = static_cast<std::size_t>(j);
          // A step the method leaves undefined (no interval) is skipped and counted.
          const bool defined = std::isfinite(e->low[s]) && std::isfinite(e->high[s]);
          rows.push_back({defined ? e->estimate[s] : std::nan(""), defined ? e->low[s] : 0.0,
                          defined ? e->high[s] : 0.0, r.model.estimator.values(hip, j), e->bordering});
        }
      }
      if (rows.empty()) continue;  // depth_nn without depths
      const stats::CoverageResult cover = stats::interval_coverage(rows, kLargeError);
      csv << c + 1 << ',' << method_name(m) << ',' << r.max_e_prime << ',' << cover.rows << ',' << cover.skipped << ','
          << cover.covered << ','
          << cover.coverage << ',' << cover.large_error << ',' << cover.large_error_flagged << ','
          << cover.flag_recall << '\n';
      md << "| " << c + 1 << " | " << method_name(m) << " | " << cover.rows
         << (cover.skipped > 0 ? " (" + std::to_string(cover.skipped) + " undefined)" : std::string()) << " | "
         << (cover.rows > 0 ? fixed_or(100.0 * cover.coverage, 1, "-") + " %" : std::string("-")) << " | " << cover.large_error
         << " | "
         << (cover.large_error > 0 ? std::to_string(cover.large_error_flagged) + " (" +
                                         fixed_or(100.0 * cover.flag_recall, 1, "-") + " %)"
                                   : std::string("-"))
         << " |\n";
    }
  }
  write_file_atomically(dir / "coverage.csv", csv.str());
}

// report.md: the times on this machine, and the files.
void md_times(std::ostringstream& md, const EstimatorValidateResult& r) {
  std::vector<double> feature_ms, load_ms;
  for (const auto& hip : r.model.hips) {
    feature_ms.push_back(hip.feature_ms);
    load_ms.push_back(hip.load_ms);
  }
  const auto m = r.model.hips.size();
  const auto& predict_ms = r.predict_ms;
  md << "## Times (this machine)\n\n| what | time |\n|---|---|\n";
  if (r.quick_fe_s > 0) md << "| FE sweep (--quick, study validate) | " << fixed_or(r.quick_fe_s, 1, "-") << " s |\n";
  md << "| load one hip's tissues (mean / max) | " << fixed_or(finite_mean(load_ms), 1, "-") << " / "
     << fixed_or(*std::max_element(load_ms.begin(), load_ms.end()), 1, "-") << " ms |\n"
     << "| features of one hip (mean / max; edge " << fixed_or(r.model.hips.front().edge_mm, 1, "-") << " mm) | "
     << fixed_or(finite_mean(feature_ms), 1, "-") << " / " << fixed_or(*std::max_element(feature_ms.begin(), feature_ms.end()), 1, "-")
     << " ms |\n"
     << "| train on " << m << " hips (PCA + correlations, features given) | " << fixed_or(r.train_ms, 2, "-") << " ms |\n"
     << "| one prediction, e' = " << r.components << ", all " << r.steps
     << " steps, depths given:";
  for (int method = 0; method < kNumEstimatorMethods; ++method) md << (method == 0 ? " " : " / ") << method_name(method);
  md << " |";
  for (int method = 0; method < kNumEstimatorMethods; ++method) md << (method == 0 ? " " : " / ") << fixed_or(predict_ms[method], 3, "-");
  md << " ms |\n"
     << "| leave-one-out, both cases, every method x e' 1.." << r.max_e_prime << " | " << fixed_or(r.loo_ms / 1000.0, 2, "-")
     << " s |\n"
     << "| whole training pipeline (load, features, train) | " << fixed_or(r.pipeline_ms / 1000.0, 2, "-") << " s |\n\n"
     << "Files: `loo.csv`, `estimates.csv`, `hips.csv`, `coverage.csv`, `model.h5` (trained on all " << m << " hips).\n";
}

}  // namespace

std::filesystem::path write_estimator_validate_report(const EstimatorValidateResult& result,
                                                      const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  write_estimator_model(result.model, dir / "model.h5");
  write_loo_files(result, dir);
  write_hips_csv(result, dir);
  write_error_curves(result, dir);
  const std::string fig72_name = write_fig72(result, dir);

  std::ostringstream md;
  md_introduction(md, result);
  md_mean_errors(md, result);
  md_chosen_e_prime(md, result);
  md_impinging(md, result);
  md_thesis_tables(md, result);
  md_per_hip(md, result);
  md_pca(md, result);
  write_coverage(md, result, dir);
  md << "\n## Figures\n\n![Fig. 73](fig73_case1.svg)\n\n![Fig. 74](fig74_case2.svg)\n\n";
  if (!fig72_name.empty()) md << "![Fig. 72](" << fig72_name << ")\n\n";
  md_times(md, result);
  const std::filesystem::path report = dir / "report.md";
  write_file_atomically(report, md.str());
  return report;
}

}  // namespace hipfai::studies
