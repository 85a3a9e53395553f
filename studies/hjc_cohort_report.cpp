// hipfai — the files of `study hjc-cohort` from its result (see hjc_cohort_report.h).
#include "studies/hjc_cohort_report.h"

#include "core/atomic_file.h"
#include "core/text_format.h"
#include "core/version.h"
#include "geometry/hjc.h"
#include "studies/results/results_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace hipfai::studies {
namespace {

std::string csv_escape(const std::string& s) {
  return s.find(',') == std::string::npos ? s : "\"" + s + "\"";
}

void write_rows_csv(const HjcCohortResult& result, const std::filesystem::path& path) {
  std::ostringstream rows_csv;
  rows_csv << "hip,surface,perturbation,replicate,method,ok,error_mm,error_x_mm,error_y_mm,error_z_mm,fit_rms_mm,"
              "fit_max_mm,residual_motion_rms_mm\n";
  rows_csv.precision(6);
  for (const auto& r : result.rows) {
    rows_csv << r.hip << ',' << r.surface << ',' << csv_escape(r.perturbation) << ',' << r.replicate << ',' << r.method
             << ',' << (r.ok ? 1 : 0) << ',' << r.error_mm << ',' << r.error_vector_mm.x() << ','
             << r.error_vector_mm.y() << ',' << r.error_vector_mm.z() << ',' << r.rms_mm << ',' << r.max_mm << ','
             << r.residual_motion_rms_mm << '\n';
  }
  write_file_atomically(path, rows_csv.str());
}

void write_summary_csv(const HjcCohortResult& result, const std::filesystem::path& path) {
  std::ostringstream summary_csv;
  summary_csv << "surface,perturbation,method,n,failed,mean_error_mm,sd_error_mm,max_error_mm\n";
  for (const auto& s : result.summary) {
    summary_csv << s.surface << ',' << csv_escape(s.perturbation) << ',' << s.method << ',' << s.count << ','
                << s.failed << ',' << fixed_or(s.mean_mm, 4, "-") << ',' << fixed_or(s.sd_mm, 4, "-") << ',' << fixed_or(s.max_mm, 4, "-") << '\n';
  }
  write_file_atomically(path, summary_csv.str());
}

// The summary of one group; a group whose every estimate failed has none, only its failures.
HjcCohortSummary group(const HjcCohortResult& result, const std::string& surface, const std::string& perturbation,
                       const std::string& method) {
  for (const auto& s : result.summary) {
    if (s.surface == surface && s.perturbation == perturbation && s.method == method) return s;
  }
  HjcCohortSummary failed{surface, perturbation, method};
  for (const auto& r : result.rows) {
    if (r.surface == surface && r.perturbation == perturbation && r.method == method && !r.ok) ++failed.failed;
  }
  return failed;
}

// One perturbation's row: the methods' mean +- SD (max), then the winner and its margin over the
// runner-up.
void write_perturbation_row(std::ostream& md, const HjcCohortResult& result, const std::string& surface,
                            const std::string& perturbation) {
  std::vector<std::pair<double, std::string>> ranking;
  int n = 0;
  md << "| " << perturbation << " |";
  std::ostringstream cells;
  for (const auto& m : geometry::hjc_method_names()) {
    const HjcCohortSummary t = group(result, surface, perturbation, m);
    n = std::max(n, t.count + t.failed);
    if (t.count == 0) { cells << " failed |"; continue; }
    cells << ' ' << fixed_or(t.mean_mm, 2, "-") << " +- " << fixed_or(t.sd_mm, 2, "-") << " (" << fixed_or(t.max_mm, 2, "-") << ")"
          << (t.failed ? " [" + std::to_string(t.failed) + " failed]" : "") << " |";
    ranking.push_back({t.mean_mm, m});
  }
  std::sort(ranking.begin(), ranking.end());
  md << ' ' << n << " |" << cells.str();
  if (ranking.size() >= 2) {
    md << ' ' << ranking[0].second << " | " << fixed_or(ranking[1].first - ranking[0].first, 2, "-") << " mm vs "
       << ranking[1].second << " |\n";
  } else {
    md << " - | - |\n";
  }
}

void write_surface_table(std::ostream& md, const HjcCohortResult& result, const std::string& surface) {
  md << "## " << (surface == "articular" ? "Articular surfaces (femoral and acetabular cartilage)"
                                         : "Bones (femur bone, acetabular bone)")
     << "\n\n| perturbation | n |";
  for (const auto& m : geometry::hjc_method_names()) md << ' ' << m << " |";
  md << " best | margin to 2nd |\n|---|---|";
  for (std::size_t i = 0; i < geometry::hjc_method_names().size() + 2; ++i) md << "---|";
  md << '\n';
  std::vector<std::string> seen;
  for (const auto& s : result.summary) {
    if (s.surface != surface || std::find(seen.begin(), seen.end(), s.perturbation) != seen.end()) continue;
    seen.push_back(s.perturbation);
    write_perturbation_row(md, result, surface, s.perturbation);
  }
  md << '\n';
}

// One table per surface, perturbations as rows, methods as columns; then the overall error per method.
std::string cohort_markdown(const HjcCohortResult& result) {
  const HjcCohortOptions& options = result.options;
  std::ostringstream md;
  md << "# HJC estimators against a known centre\n\n"
     << "Generated hips CE " ;
  for (std::size_t i = 0; i < options.ce_deg.size(); ++i) md << (i ? ", " : "") << options.ce_deg[i];
  md << " deg (alpha 40; cam: alpha 80), " << options.edge_mm << " mm edges (coarse " << options.coarse_edge_mm
     << ", fine " << options.fine_edge_mm << " mm, CE " << options.ce_deg[options.ce_deg.size() / 2]
     << " only); random perturbations " << options.replicates
     << " replicates per hip. Error = |estimate - true centre| in mm: mean +- SD (max). Code " << kGitSha
     << ". Definitions: studies/hjc_cohort.h.\n\n";
  for (const std::string surface : {"articular", "bone"}) write_surface_table(md, result, surface);
  md << "## Overall (every perturbation, both surfaces)\n\n| method | n | mean error (mm) | SD | max |\n|---|---|---|---|---|\n";
  for (const auto& s : result.overall) {
    md << "| " << s.method << " | " << s.count << " | " << fixed_or(s.mean_mm, 3, "-") << " | " << fixed_or(s.sd_mm, 3, "-") << " | "
       << fixed_or(s.max_mm, 3, "-") << " |\n";
  }
  return md.str();
}

void write_cohort_h5(const HjcCohortResult& result, const std::filesystem::path& path) {
  ResultsFile h5(path);
  h5.set_attribute("/", "units", "mm");
  h5.set_attribute("/", "git_sha", kGitSha);
  h5.set_attribute("/", "study", "hjc cohort: HJC estimators against a known centre");
  std::vector<std::string> hip, surface, perturbation, method;
  std::vector<double> values;
  for (const auto& r : result.rows) {
    hip.push_back(r.hip);
    surface.push_back(r.surface);
    perturbation.push_back(r.perturbation);
    method.push_back(r.method);
    values.insert(values.end(), {r.error_mm, r.error_vector_mm.x(), r.error_vector_mm.y(), r.error_vector_mm.z(),
                                 r.rms_mm, r.max_mm, r.residual_motion_rms_mm, static_cast<double>(r.replicate)});
  }
  h5.write_strings("/rows/hip", hip);
  h5.write_strings("/rows/surface", surface);
  h5.write_strings("/rows/perturbation", perturbation);
  h5.write_strings("/rows/method", method);
  h5.write("/rows/values", values, 8, "mm");
  h5.set_attribute("/rows/values", "columns",
                   "error_mm,error_x_mm,error_y_mm,error_z_mm,fit_rms_mm,fit_max_mm,residual_motion_rms_mm,replicate");
  h5.commit();
}

}  // namespace

std::filesystem::path write_hjc_cohort_report(const HjcCohortResult& result, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  write_rows_csv(result, dir / "cohort.csv");
  write_summary_csv(result, dir / "cohort_summary.csv");
  const std::filesystem::path report = dir / "cohort.md";
  write_file_atomically(report, cohort_markdown(result));
  write_cohort_h5(result, dir / "cohort.h5");
  return report;
}

}  // namespace hipfai::studies
