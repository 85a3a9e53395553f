// hipfai — the correlation report of the FAI validation (thesis §4.3.3.1, Tables 8-9, Figs. 60-61),
// made from a validation folder's stored results only (steps.csv, timings.csv; written by
// studies/validation_study.h), so it is re-made in seconds.
//
// Per hip, depth kind (curvilinear, radial) and FE measure: Pearson r and its two-sided p, Spearman
// rho and the Fisher-z 95 % interval of r over the steps of the motion (stats/correlation.h);
// "n.p." when the hip never penetrates (the depth is 0 at every step), "constant" when the FE
// measure does not vary. Steps whose FE did not converge (empty cells) are left out of the pairs.
//
// Writes into the folder:
//   correlation.csv   ce_deg, alpha_deg, depth, measure, n, r, p, spearman, ci_low, ci_high, status
//   report.md         Table 8 and Table 9 in the thesis' layout beside the thesis' values, the
//                     summary, the across-hip correlation of the maxima, the classification,
//                     time per stage and the figures below
//   fig60_<hip>.svg   depth and the primary FE measure over the motion (two axes)
//   scatter_<depth>.svg, rmap_<depth>.svg, fig61/<hip>_end_pose.vtm (when the study wrote fig61/)
#pragma once

#include "stats/correlation.h"
#include "studies/results/validation_results_file.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

struct ValidationCorrelation {
  double ce_deg = 0, alpha_deg = 0;
  std::string depth;    // "curvilinear" | "radial"
  std::string measure;  // an FE measure column
  stats::CorrelationSummary summary;
  std::string status;   // "ok", "n.p.", "constant" or "too few"
};

// Every hip x depth kind x measure.
std::vector<ValidationCorrelation> correlate_validation(const ValidationData& data);

// Leave-one-out classification of the hips into the thesis' pathologies (fai_study.h
// pathology_of) from their maximum curvilinear and radial depths and normalised difference: each
// hip is assigned the class of its nearest neighbour among the other hips (features scaled by the
// other hips' ranges), never by a rule fitted with the hip itself.
struct ValidationClassification {
  std::vector<std::string> classes;             // row/column order of the confusion matrix
  std::vector<std::vector<int>> confusion;      // [true class][assigned class]
  std::vector<std::string> truth, assigned;     // per hip, in data order
  int correct = 0;
};
ValidationClassification classify_leave_one_out(const ValidationData& data);

struct CorrelationReportResult {
  std::filesystem::path report, correlation_csv;
  double mean_r_all = 0, mean_r_curvilinear = 0, mean_r_radial = 0;  // primary measure, status ok
  int ok_cells = 0;
};

// Reads the folder's results and writes correlation.csv, report.md and the figures into it.
CorrelationReportResult write_correlation_report(const std::filesystem::path& dir);

}  // namespace hipfai::studies
