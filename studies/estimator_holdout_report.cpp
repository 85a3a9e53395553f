#include "studies/estimator_holdout_report.h"

#include "core/atomic_file.h"
#include "core/numbers.h"
#include "core/text_format.h"
#include "studies/reports/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>

namespace hipfai::studies {
namespace {

using hipfai::kNaN;

std::string num(double value, int precision = 10) {
  if (!std::isfinite(value)) return std::isinf(value) ? (value > 0 ? "inf" : "-inf") : "";
  std::ostringstream out;
  out << std::setprecision(precision) << value;
  return out.str();
}

const char* to_string(RefineStrategy strategy) { return strategy == RefineStrategy::kRandom ? "random" : "uncertainty"; }

std::string errors_csv(const HoldoutResult& result) {
  std::ostringstream csv;
  csv << "training_hips,method,case,group,hips,mean_error_percent,max_error_percent\n";
  for (const auto& s : result.summary) {
    csv << s.training_hips << ',' << stats::to_string(s.method) << ',' << s.case_index << ',' << to_string(s.group) << ','
        << s.hips << ',' << num(s.mean_error_percent) << ',' << num(s.max_error_percent) << '\n';
  }
  return csv.str();
}

std::string loo_csv(const HoldoutResult& result) {
  std::ostringstream csv;
  csv << "training_hips,method,case,hips,mean_error_percent\n";
  for (const auto& l : result.loo) {
    csv << l.training_hips << ',' << stats::to_string(l.method) << ',' << l.case_index << ',' << l.hips << ','
        << num(l.mean_error_percent) << '\n';
  }
  return csv.str();
}

std::string hips_csv(const HoldoutResult& result) {
  std::ostringstream csv;
  csv << "training_hips,hip,method,case,impinging,bordering,mean_error_percent\n";
  for (const auto& h : result.hip_errors) {
    csv << h.training_hips << ',' << h.hip << ',' << stats::to_string(h.method) << ',' << h.case_index << ','
        << (h.impinging ? 1 : 0) << ',' << (h.bordering ? 1 : 0) << ',' << num(h.mean_error_percent) << '\n';
  }
  return csv.str();
}

std::string estimates_csv(const HoldoutResult& result) {
  std::ostringstream csv;
  csv << "training_hips,hip,method,step,estimate,fe,error_percent,low,high,conformal_low,conformal_high,"
         "impinging_step,bordering,wide_interval,flagged\n";
  for (const auto& r : result.steps_rows) {
    const double error = r.fe > 0 ? 100.0 * (r.estimate - r.fe) / r.fe : kNaN;
    csv << r.training_hips << ',' << r.hip << ',' << stats::to_string(r.method) << ',' << r.step << ','
        << num(r.estimate) << ',' << num(r.fe) << ',' << num(error) << ',' << num(r.low) << ',' << num(r.high) << ','
        << num(r.conformal_low) << ',' << num(r.conformal_high) << ',' << (r.impinging_step ? 1 : 0) << ','
        << (r.bordering ? 1 : 0) << ',' << (r.wide_interval ? 1 : 0) << ',' << (r.bordering || r.wide_interval ? 1 : 0)
        << '\n';
  }
  return csv.str();
}

std::string coverage_csv(const HoldoutResult& result) {
  std::ostringstream csv;
  csv << "training_hips,method,nominal,half_width_free,half_width_impinging,calibration_rows_free,"
         "calibration_rows_impinging,steps,covered,coverage,acceptance_low,acceptance_high,native_covered,"
         "native_coverage,large_error_steps,flagged_steps,large_error_flagged,flag_recall,bordering_recall\n";
  for (const auto& c : result.coverage) {
    csv << c.training_hips << ',' << stats::to_string(c.method) << ',' << num(result.nominal) << ','
        << num(c.half_width_free) << ',' << num(c.half_width_impinging) << ',' << c.calibration_rows_free << ','
        << c.calibration_rows_impinging << ',' << c.conformal.rows << ',' << c.conformal.covered << ','
        << num(c.conformal.coverage) << ',' << c.acceptance.low << ',' << c.acceptance.high << ','
        << c.native.covered << ',' << num(c.native.coverage) << ',' << c.conformal.large_error << ','
        << c.conformal.flagged << ',' << c.conformal.large_error_flagged << ',' << num(c.conformal.flag_recall) << ','
        << num(c.native.flag_recall) << '\n';
  }
  return csv.str();
}

std::string refine_csv(const HoldoutResult& result) {
  std::ostringstream csv;
  csv << "strategy,criterion,repeat,round,training_hips,method,case,mean_error_percent,added\n";
  for (const auto& r : result.refine) {
    std::string added;
    for (const auto& hip : r.added) {
      if (!added.empty()) added += ';';
      added += hip;
    }
    csv << to_string(r.strategy) << ',' << (r.strategy == RefineStrategy::kUncertainty ? stats::to_string(r.criterion) : "")
        << ',' << r.repeat << ',' << r.round << ',' << r.training_hips << ',' << stats::to_string(r.method) << ','
        << r.case_index << ',' << num(r.mean_error_percent) << ',' << added << '\n';
  }
  return csv.str();
}

std::string timings_csv(const HoldoutResult& result) {
  std::ostringstream csv;
  csv << "training_hips,train_ms,calibrate_ms,predict_ms_per_hip\n";
  for (const auto& t : result.timings) {
    csv << t.training_hips << ',' << num(t.train_ms) << ',' << num(t.calibrate_ms) << ',' << num(t.predict_ms_per_hip) << '\n';
  }
  return csv.str();
}

const HoldoutErrorSummary* find_summary(const HoldoutResult& result, int k, stats::EstimatorMethod method, int c, HipGroup group) {
  for (const auto& s : result.summary) {
    if (s.training_hips == k && s.method == method && s.case_index == c && s.group == group) return &s;
  }
  return nullptr;
}

double loo_error(const HoldoutResult& result, int k, stats::EstimatorMethod method, int c) {
  for (const auto& l : result.loo) {
    if (l.training_hips == k && l.method == method && l.case_index == c) return l.mean_error_percent;
  }
  return kNaN;
}

std::vector<int> sizes_of(const HoldoutResult& result) {
  std::vector<int> sizes;
  for (const auto& t : result.timings) sizes.push_back(t.training_hips);
  return sizes;
}

// Mean over the random draws, and over the uncertainty runs of each criterion, per round.
struct RefineCurve {
  std::string name;
  std::vector<double> hips, error, low, high;
};

std::vector<RefineCurve> refine_curves(const HoldoutResult& result, stats::EstimatorMethod method, int c) {
  std::map<std::string, std::map<int, std::vector<double>>> by_name;  // name -> training hips -> errors
  for (const auto& r : result.refine) {
    if (r.method != method || r.case_index != c) continue;
    const std::string name = r.strategy == RefineStrategy::kRandom ? std::string("random")
                                                                   : std::string("refine: ") + stats::to_string(r.criterion);
    by_name[name][r.training_hips].push_back(r.mean_error_percent);
  }
  std::vector<RefineCurve> curves;
  for (const auto& [name, rounds] : by_name) {
    RefineCurve curve{name, {}, {}, {}, {}};
    for (const auto& [hips, errors] : rounds) {
      double sum = 0;
      for (const double e : errors) sum += e;
      curve.hips.push_back(hips);
      curve.error.push_back(sum / static_cast<double>(errors.size()));
      curve.low.push_back(*std::min_element(errors.begin(), errors.end()));
      curve.high.push_back(*std::max_element(errors.begin(), errors.end()));
    }
    curves.push_back(std::move(curve));
  }
  return curves;
}

void write_figures(const HoldoutResult& result, const HoldoutOptions& options, const std::filesystem::path& out_dir) {
  LineChart sizes;
  sizes.title = "Held-out error vs training-set size (" + result.measure + ", whole motion)";
  sizes.x_label = "training hips";
  sizes.y_label = "mean error over held-out hips (%)";
  for (const stats::EstimatorMethod method : stats::kEstimatorMethods) {
    Series held{std::string(stats::to_string(method)) + " held-out", {}, {}};
    Series loo{std::string(stats::to_string(method)) + " LOO", {}, {}, true};
    for (const int k : sizes_of(result)) {
      if (const auto* s = find_summary(result, k, method, 2, HipGroup::kAll)) {
        held.x.push_back(k);
        held.y.push_back(s->mean_error_percent);
      }
      loo.x.push_back(k);
      loo.y.push_back(loo_error(result, k, method, 2));
    }
    sizes.series.push_back(held);
    sizes.series.push_back(loo);
  }
  sizes.notes.push_back("thesis LOO: " + fixed_or(literature::kEstimatorThesisCase2MeanErrorPercent, 2, "–") + " %");
  write_svg(sizes, out_dir / "fig_error_vs_size.svg");
  if (result.refine.empty()) return;
  LineChart refine;
  refine.title = std::string("Refinement vs random sampling (") + stats::to_string(options.refine_method) + ", whole motion)";
  refine.x_label = "training hips";
  refine.y_label = "mean error over held-out hips (%)";
  for (const auto& curve : refine_curves(result, options.refine_method, 2)) {
    refine.series.push_back({curve.name, curve.hips, curve.error});
    if (curve.name == "random") {
      refine.series.push_back({"random, best", curve.hips, curve.low, true});
      refine.series.push_back({"random, worst", curve.hips, curve.high, true});
    }
  }
  write_svg(refine, out_dir / "fig_refine.svg");
}

std::string report_md(const HoldoutResult& result, const HoldoutOptions& options) {
  std::ostringstream md;
  const std::vector<int> sizes = sizes_of(result);
  md << "# The estimator on hips it has never seen\n\n"
     << "Sample: `" << options.sample_dir.string() << "`: " << result.training_available << " training hips, "
     << result.held_out << " held-out hips (never trained on), " << result.steps << " steps, measure `" << result.measure
     << "`. Methods at e' = e (" << result.components << " components for the largest set). Case 1: the first "
     << (result.steps + 1) / 2 << " steps, case 2: all. A hip is *impinging* in a case when its penetration depth "
     << "(thesis §4.3) is above 0 at one of the case's steps. Training sets: the first k hips of the design.\n\n";
  md << "## Held-out error beside leave-one-out (mean over hips, %)\n\n"
     << "| training hips | method | case 1 held-out | case 1 LOO | case 2 held-out | case 2 LOO | case 1 impinging | case 2 impinging (hips) | case 2 free | thesis LOO (25 grid hips) |\n"
     << "|---:|---|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const int k : sizes) {
    for (const stats::EstimatorMethod method : stats::kEstimatorMethods) {
      const auto* c1 = find_summary(result, k, method, 1, HipGroup::kAll);
      const auto* c2 = find_summary(result, k, method, 2, HipGroup::kAll);
      const auto* i1 = find_summary(result, k, method, 1, HipGroup::kImpinging);
      const auto* i2 = find_summary(result, k, method, 2, HipGroup::kImpinging);
      const auto* f2 = find_summary(result, k, method, 2, HipGroup::kFree);
      md << "| " << k << " | " << stats::to_string(method) << " | " << fixed_or(c1 ? c1->mean_error_percent : kNaN, 2, "–") << " | "
         << fixed_or(loo_error(result, k, method, 1), 2, "–") << " | " << fixed_or(c2 ? c2->mean_error_percent : kNaN, 2, "–") << " | "
         << fixed_or(loo_error(result, k, method, 2), 2, "–") << " | " << fixed_or(i1 ? i1->mean_error_percent : kNaN, 2, "–") << " | "
         << fixed_or(i2 ? i2->mean_error_percent : kNaN, 2, "–") << " (" << (i2 ? i2->hips : 0) << ") | "
         << fixed_or(f2 ? f2->mean_error_percent : kNaN, 2, "–") << " | "
         << (method == stats::EstimatorMethod::kPcaNn
                 ? fixed_or(literature::kEstimatorThesisMeanErrorPercent, 2, "–") + " / " + fixed_or(literature::kEstimatorThesisCase2MeanErrorPercent, 2, "–")
                 : std::string())
         << " |\n";
    }
  }
  md << "\n![error vs size](fig_error_vs_size.svg)\n\n";
  md << "## Intervals and flag (whole motion, every held-out step)\n\n"
     << "Calibrated intervals: estimate ± h × estimate, h the " << fixed_or(100 * result.nominal, 0, "–")
     << " % conformal quantile of the leave-one-out relative errors of the training hips, one h for steps free of "
     << "contact and one for impinging steps (stats/conformal_interval.h). *Acceptance*: the covered counts a true "
     << fixed_or(100 * result.nominal, 0, "–") << " % coverage gives with 95 % probability (binomial). The flag: the hip is "
     << "bordering, or its step's calibrated half-width exceeds " << fixed_or(100 * literature::kEstimatorLargeErrorFraction, 0, "–")
     << " %; recall = flagged share of the steps whose error exceeds " << fixed_or(100 * literature::kEstimatorLargeErrorFraction, 0, "–")
     << " %.\n\n"
     << "| training hips | method | h free | h impinging | coverage (calibrated) | acceptance | coverage (own interval) | steps > 10 % | flagged steps | flag recall | bordering recall |\n"
     << "|---:|---|---:|---:|---:|---|---:|---:|---:|---:|---:|\n";
  for (const auto& c : result.coverage) {
    md << "| " << c.training_hips << " | " << stats::to_string(c.method) << " | " << fixed_or(100 * c.half_width_free, 1, "–")
       << " % | " << fixed_or(100 * c.half_width_impinging, 1, "–") << " % | " << fixed_or(100 * c.conformal.coverage, 1, "–") << " % ("
       << c.conformal.covered << "/" << c.conformal.rows << ") | " << c.acceptance.low << "-" << c.acceptance.high << " | "
       << fixed_or(100 * c.native.coverage, 1, "–") << " % | " << c.conformal.large_error << " | " << c.conformal.flagged << " | "
       << fixed_or(100 * c.conformal.flag_recall, 1, "–") << " % | " << fixed_or(100 * c.native.flag_recall, 1, "–") << " % |\n";
  }
  if (!result.refine.empty()) {
    md << "\n## Refinement vs random sampling (" << stats::to_string(options.refine_method) << ", whole motion)\n\n"
       << "From the first " << result.refine_start << " training hips, " << result.refine_budget
       << " hips added per round from the other training hips: the least certain under the current model, or at random ("
       << result.random_repeats << " draws: mean, best and worst).\n\n"
       << "| training hips | strategy | held-out error (%) | best draw | worst draw |\n|---:|---|---:|---:|---:|\n";
    for (const auto& curve : refine_curves(result, options.refine_method, 2)) {
      for (std::size_t r = 0; r < curve.hips.size(); ++r) {
        md << "| " << curve.hips[r] << " | " << curve.name << " | " << fixed_or(curve.error[r], 2, "–") << " | "
           << (curve.name == "random" ? fixed_or(curve.low[r], 2, "–") : std::string()) << " | "
           << (curve.name == "random" ? fixed_or(curve.high[r], 2, "–") : std::string()) << " |\n";
      }
    }
    md << "\n![refine](fig_refine.svg)\n";
  }
  md << "\n## Times\n\n"
     << "- FE per hip (sample's runs): " << fixed_or(result.fe_s_per_hip, 1, "–") << " s; penetration depths per hip: "
     << fixed_or(result.penetration_ms_per_hip / 1e3, 2, "–") << " s; features per hip: " << fixed_or(result.feature_ms_per_hip, 1, "–")
     << " ms\n\n| training hips | training (ms) | leave-one-out calibration (ms) | prediction per hip, "
     << std::size(stats::kEstimatorMethods) << " methods (ms) |\n|---:|---:|---:|---:|\n";
  for (const auto& t : result.timings) {
    md << "| " << t.training_hips << " | " << fixed_or(t.train_ms, 1, "–") << " | " << fixed_or(t.calibrate_ms, 0, "–") << " | "
       << fixed_or(t.predict_ms_per_hip, 2, "–") << " |\n";
  }
  return md.str();
}

}  // namespace

void write_holdout_report(const HoldoutResult& result, const HoldoutOptions& options, const std::filesystem::path& out_dir) {
  std::filesystem::create_directories(out_dir);
  write_file_atomically(out_dir / "errors.csv", errors_csv(result));
  write_file_atomically(out_dir / "loo.csv", loo_csv(result));
  write_file_atomically(out_dir / "hips.csv", hips_csv(result));
  write_file_atomically(out_dir / "estimates.csv", estimates_csv(result));
  write_file_atomically(out_dir / "coverage.csv", coverage_csv(result));
  write_file_atomically(out_dir / "refine.csv", refine_csv(result));
  write_file_atomically(out_dir / "timings.csv", timings_csv(result));
  write_figures(result, options, out_dir);
  write_file_atomically(out_dir / "report.md", report_md(result, options));
}

std::string holdout_summary(const HoldoutResult& result, const std::filesystem::path& out_dir) {
  std::ostringstream text;
  for (const int k : sizes_of(result)) {
    text << k << " training hips:";
    for (int c = 1; c <= 2; ++c) {
      const HoldoutErrorSummary* best = nullptr;
      for (const stats::EstimatorMethod method : stats::kEstimatorMethods) {
        const auto* s = find_summary(result, k, method, c, HipGroup::kAll);
        if (s && std::isfinite(s->mean_error_percent) && (!best || s->mean_error_percent < best->mean_error_percent)) best = s;
      }
      if (best) text << " case " << c << " best " << stats::to_string(best->method) << " " << fixed_or(best->mean_error_percent, 2, "–") << " %";
    }
    text << " (" << result.held_out << " held-out hips)\n";
  }
  text << "report: " << (out_dir / "report.md").string();
  return text.str();
}

}  // namespace hipfai::studies
