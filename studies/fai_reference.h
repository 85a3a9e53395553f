// hipfai — the reference study's outcome (Arbabi 2009 thesis §4.3.3, Tables 8-10) as data, and the
// cell-by-cell comparison of a computed 25-hip study with it (printed by the FAI study's report).
//
// Table 8 (curvilinear, femur bone vs labrum) lists a correlation, i.e. penetration, at CE 0 /
// alpha 80, CE 10 / alpha 70-80, CE 20 / alpha 60-80, CE 30 / alpha 50-80 and CE 40 / alpha
// 40-80, "n.p." elsewhere. Table 9 (radial) lists the same plus CE 10 / alpha 40-60, CE 20 /
// alpha 40-50 and CE 30 / alpha 40 — but the thesis' text (§4.3.3.1, §4.3.4) and Table 10 say
// that the normal hip (CE 20 / alpha 40) does not penetrate. Those six cells, whose correlations
// are also the weakest of the table (r 0.31-0.61, two not significant), are read as AMBIGUOUS:
// reported, not counted. Every other radial cell is counted.
#pragma once

#include <string>
#include <vector>

namespace hipfai::studies {

enum class ReferenceCell { kPenetrates, kNoPenetration, kAmbiguous };

// Thesis Tables 8 and 9 for one hip (CE and alpha on the 10 deg grid; other angles: ambiguous).
ReferenceCell thesis_curvilinear_cell(double ce_deg, double alpha_deg);
ReferenceCell thesis_radial_cell(double ce_deg, double alpha_deg);

// Thesis Tables 8 and 9, one cell: penetration with Pearson r and p between the per-step maximum
// depth and the per-step maximum von Mises stress over the 30 steps of standing-to-sitting, or n.p.
// (The printed p follow from r with 31 pairs, the start pose included; five extreme hips, CE 20 /
// alpha 80, CE 30 / 80 and CE 40 / 60-80, fit shorter series: tests/studies/fai_reference_test.cpp.)
struct ThesisCorrelation {
  bool penetrates = false;  // false: "n.p."
  double r = 0.0, p = 1.0;  // as printed (r to 2 decimals, p to 3 significant digits)
};
// Cells on the 10-degree grid (CE 0..40, alpha 40..80); throws hipfai::Error for angles off it.
ThesisCorrelation thesis_table8(double ce_deg, double alpha_deg);  // curvilinear
ThesisCorrelation thesis_table9(double ce_deg, double alpha_deg);  // radial
// The thesis' summary of those r (§4.3.3.1): mean, SD, range, for all / curvilinear / radial.
struct ThesisCorrelationSummary { double mean, sd, min, max; };
ThesisCorrelationSummary thesis_summary_all();
ThesisCorrelationSummary thesis_summary_curvilinear();
ThesisCorrelationSummary thesis_summary_radial();

// Thesis Table 10: the six characteristic morphologies and their bands.
struct ReferenceMorphology {
  std::string name;
  double ce_deg, alpha_deg;
  std::string curvilinear_band, radial_band, difference_band;
};
const std::vector<ReferenceMorphology>& thesis_table10();

// Rank of a band name on its scale: "none" and "very low" 0, "low" 1, "intermediate" 2,
// "high" 3, "very high" 4 (difference bands: "very low" 0 ... "high" 3). -1 for an unknown name.
int band_rank(const std::string& band);

struct StudyCell {
  double ce_deg = 0, alpha_deg = 0;
  double max_curvilinear_mm = 0, max_radial_mm = 0;
  double normalised_difference = 0;
};

struct ReferenceComparison {
  int curvilinear_agree = 0, curvilinear_counted = 0;
  int radial_agree = 0, radial_counted = 0;
  int table10_within_one_band = 0, table10_counted = 0;  // bands (CP, RP, difference) x morphologies
  bool largest_radial_at_pure_cam = false;
  bool largest_curvilinear_at_combined = false;
  std::string markdown;  // the which-cells tables and the Table 10 comparison
};

// Compares a study's cells (any subset of the grid) with the thesis. Depths > 0 count as
// penetration. The band functions are those of the study (fai_study.h).
ReferenceComparison compare_with_thesis(const std::vector<StudyCell>& cells);

}  // namespace hipfai::studies
