#include "studies/fai_reference.h"

#include "core/error.h"
#include "core/text_format.h"
#include "studies/fai_study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace hipfai::studies {
namespace {

bool on_grid(double ce, double alpha) {
  auto grid = [](double v, double lo, double hi) {
    return v >= lo - 1e-9 && v <= hi + 1e-9 && std::abs(v / 10.0 - std::round(v / 10.0)) < 1e-9;
  };
  return grid(ce, 0, 40) && grid(alpha, 40, 80);
}

const char* name(ReferenceCell cell) {
  switch (cell) {
    case ReferenceCell::kPenetrates: return "p.";
    case ReferenceCell::kNoPenetration: return "n.p.";
    case ReferenceCell::kAmbiguous: return "?";
  }
  return "?";
}

}  // namespace

ReferenceCell thesis_curvilinear_cell(double ce, double alpha) {
  if (!on_grid(ce, alpha)) return ReferenceCell::kAmbiguous;
  // Table 8: penetration exactly where CE + alpha >= 80 on the grid.
  return ce + alpha >= 80.0 - 1e-9 ? ReferenceCell::kPenetrates : ReferenceCell::kNoPenetration;
}

ReferenceCell thesis_radial_cell(double ce, double alpha) {
  if (!on_grid(ce, alpha)) return ReferenceCell::kAmbiguous;
  if (ce + alpha >= 80.0 - 1e-9) return ReferenceCell::kPenetrates;
  if (ce < 5.0) return ReferenceCell::kNoPenetration;  // CE 0, alpha 40-70: n.p.
  return ReferenceCell::kAmbiguous;  // Table 9 lists r; the text says none for the normal hip
}

namespace {

// Arbabi 2009 thesis, Tables 8 and 9 (§4.3.3.1), transcribed cell by cell: rows CE 0, 10, 20,
// 30, 40 deg, columns alpha 40, 50, 60, 70, 80 deg. kNp is a printed "n.p.".
constexpr ThesisCorrelation kNp{};
constexpr ThesisCorrelation pen(double r, double p) { return {true, r, p}; }

constexpr ThesisCorrelation kTable8[5][5] = {
    {kNp, kNp, kNp, kNp, pen(0.85, 2.14e-9)},
    {kNp, kNp, kNp, pen(0.83, 5.75e-9), pen(0.89, 2.01e-11)},
    {kNp, kNp, pen(0.89, 2.51e-11), pen(0.91, 1.43e-12), pen(0.89, 3.99e-10)},
    {kNp, pen(0.90, 9.50e-12), pen(0.95, 1.04e-16), pen(0.90, 1.01e-11), pen(0.91, 5.31e-9)},
    {pen(0.97, 3.73e-19), pen(0.96, 3.82e-18), pen(0.93, 4.15e-12), pen(0.88, 4.39e-9), pen(0.95, 3.42e-8)},
};

constexpr ThesisCorrelation kTable9[5][5] = {
    {kNp, kNp, kNp, kNp, pen(0.83, 7.38e-9)},
    {pen(0.31, 0.092), pen(0.34, 0.064), pen(0.39, 0.031), pen(0.83, 6.42e-9), pen(0.90, 3.96e-12)},
    {pen(0.60, 3.88e-4), pen(0.61, 2.70e-4), pen(0.89, 2.75e-11), pen(0.95, 4.93e-16), pen(0.91, 1.58e-11)},
    {pen(0.58, 6.20e-4), pen(0.90, 9.89e-12), pen(0.97, 7.90e-20), pen(0.97, 3.32e-20), pen(0.93, 4.27e-10)},
    {pen(0.97, 7.17e-20), pen(0.97, 4.56e-20), pen(0.96, 4.98e-16), pen(0.97, 3.93e-16), pen(0.96, 1.34e-8)},
};

const ThesisCorrelation& table_cell(const ThesisCorrelation (&table)[5][5], const char* which, double ce,
                                    double alpha) {
  if (!on_grid(ce, alpha)) {
    throw_error("thesis ", which, ": CE ", ce, " / alpha ", alpha,
                " deg is off the table's grid (CE 0..40, alpha 40..80 in steps of 10)");
  }
  return table[static_cast<int>(std::lround(ce / 10.0))][static_cast<int>(std::lround((alpha - 40.0) / 10.0))];
}

}  // namespace

ThesisCorrelation thesis_table8(double ce, double alpha) { return table_cell(kTable8, "Table 8", ce, alpha); }
ThesisCorrelation thesis_table9(double ce, double alpha) { return table_cell(kTable9, "Table 9", ce, alpha); }

// §4.3.3.1: "The mean correlation coefficient was 0.84 (standard deviation 0.18, range 0.31 - 0.97)
// for all penetration depths, 0.91 (standard deviation 0.04, range 0.83 - 0.97) for the curvilinear
// penetration, and 0.80 (standard deviation 0.22, range 0.31 - 0.97) for the radial penetration."
ThesisCorrelationSummary thesis_summary_all() { return {0.84, 0.18, 0.31, 0.97}; }
ThesisCorrelationSummary thesis_summary_curvilinear() { return {0.91, 0.04, 0.83, 0.97}; }
ThesisCorrelationSummary thesis_summary_radial() { return {0.80, 0.22, 0.31, 0.97}; }

const std::vector<ReferenceMorphology>& thesis_table10() {
  static const std::vector<ReferenceMorphology> table{
      {"normal", 20, 40, "very low", "very low", "intermediate"},
      {"pincer", 40, 40, "low", "very low", "high"},
      {"cam", 20, 80, "high", "very high", "very low"},
      {"combined cam-pincer", 40, 80, "very high", "very high", "intermediate"},
      {"dysplasia", 0, 40, "very low", "very low", "intermediate"},
      {"combined dysplasia-impingement", 0, 80, "very low", "low", "low"},
  };
  return table;
}

int band_rank(const std::string& band) {
  if (band == "none" || band == "very low") return 0;
  if (band == "low") return 1;
  if (band == "intermediate") return 2;
  if (band == "high") return 3;
  if (band == "very high") return 4;
  return -1;
}

ReferenceComparison compare_with_thesis(const std::vector<StudyCell>& cells) {
  ReferenceComparison result;
  auto find = [&](double ce, double alpha) -> const StudyCell* {
    for (const auto& c : cells) {
      if (std::abs(c.ce_deg - ce) < 1e-9 && std::abs(c.alpha_deg - alpha) < 1e-9) return &c;
    }
    return nullptr;
  };
  std::vector<double> ces, alphas;
  for (const auto& c : cells) {
    if (std::find(ces.begin(), ces.end(), c.ce_deg) == ces.end()) ces.push_back(c.ce_deg);
    if (std::find(alphas.begin(), alphas.end(), c.alpha_deg) == alphas.end()) alphas.push_back(c.alpha_deg);
  }
  std::sort(ces.begin(), ces.end());
  std::sort(alphas.begin(), alphas.end());

  std::ostringstream md;
  auto table = [&](const char* title, bool curvilinear) {
    md << "### " << title << "\n\nEach cell: ours (max depth, mm) vs thesis -> verdict. p. = penetration, "
       << "n.p. = no penetration, ? = ambiguous in the thesis (not counted).\n\n| CE \\ alpha |";
    for (double a : alphas) md << ' ' << fixed(a, 0) << " |";
    md << "\n|---|";
    for (std::size_t i = 0; i < alphas.size(); ++i) md << "---|";
    md << '\n';
    int& agree = curvilinear ? result.curvilinear_agree : result.radial_agree;
    int& counted = curvilinear ? result.curvilinear_counted : result.radial_counted;
    for (double ce : ces) {
      md << "| " << fixed(ce, 0) << " |";
      for (double a : alphas) {
        const StudyCell* c = find(ce, a);
        if (!c) {
          md << " - |";
          continue;
        }
        const double depth = curvilinear ? c->max_curvilinear_mm : c->max_radial_mm;
        const bool ours = depth > 0.0;
        const ReferenceCell ref = curvilinear ? thesis_curvilinear_cell(ce, a) : thesis_radial_cell(ce, a);
        std::string verdict = "not counted";
        if (ref != ReferenceCell::kAmbiguous) {
          const bool ok = ours == (ref == ReferenceCell::kPenetrates);
          ++counted;
          if (ok) ++agree;
          verdict = ok ? "agree" : "**differ**";
        }
        md << ' ' << (ours ? "p. " + fixed(depth, 2) : std::string("n.p.")) << " vs " << name(ref) << " -> "
           << verdict << " |";
      }
      md << '\n';
    }
    md << "\n" << agree << " of " << counted << " counted cells agree.\n\n";
  };
  md << "## Which cells penetrate: ours vs thesis Tables 8 and 9\n\n";
  table("Table 8 (curvilinear: femur bone vs labrum)", true);
  table("Table 9 (radial: femur vs acetabular cartilage + labrum)", false);
  md << "Table 9's ambiguous cells (CE 10 / alpha 40-60, CE 20 / alpha 40-50, CE 30 / alpha 40) list weak "
        "correlations although the thesis' text and Table 10 say the normal hip does not penetrate; they are "
        "shown, not counted (studies/fai_reference.h).\n\n";

  md << "## Table 10: bands of the six characteristic morphologies, ours vs thesis\n\n"
     << "| morphology | CE | alpha | CP ours | CP thesis | RP ours | RP thesis | CP - RP ours | CP - RP thesis |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& m : thesis_table10()) {
    const StudyCell* c = find(m.ce_deg, m.alpha_deg);
    if (!c) continue;
    auto cell = [&](const std::string& ours_band, double value, const std::string& theirs) {
      const int diff = std::abs(band_rank(ours_band) - band_rank(theirs));
      ++result.table10_counted;
      if (diff <= 1) ++result.table10_within_one_band;
      return fixed(value, 2) + " (" + ours_band + ")" + (diff <= 1 ? "" : " **off by " + std::to_string(diff) + "**");
    };
    md << "| " << m.name << " | " << fixed(m.ce_deg, 0) << " | " << fixed(m.alpha_deg, 0) << " | "
       << cell(curvilinear_band(c->max_curvilinear_mm), c->max_curvilinear_mm, m.curvilinear_band) << " | "
       << m.curvilinear_band << " | " << cell(radial_band(c->max_radial_mm), c->max_radial_mm, m.radial_band) << " | "
       << m.radial_band << " | "
       << cell(difference_band(c->normalised_difference), c->normalised_difference, m.difference_band) << " | "
       << m.difference_band << " |\n";
  }
  const StudyCell* deepest_c = nullptr;
  const StudyCell* deepest_r = nullptr;
  for (const auto& c : cells) {
    if (!deepest_c || c.max_curvilinear_mm > deepest_c->max_curvilinear_mm) deepest_c = &c;
    if (!deepest_r || c.max_radial_mm > deepest_r->max_radial_mm) deepest_r = &c;
  }
  if (deepest_c && deepest_r) {
    result.largest_curvilinear_at_combined = deepest_c->ce_deg == 40 && deepest_c->alpha_deg == 80;
    result.largest_radial_at_pure_cam = deepest_r->ce_deg == 20 && deepest_r->alpha_deg == 80;
    md << "\n" << result.table10_within_one_band << " of " << result.table10_counted
       << " bands within one band of the thesis'. Largest curvilinear depth: CE " << fixed(deepest_c->ce_deg, 0)
       << " / alpha " << fixed(deepest_c->alpha_deg, 0) << " (" << fixed(deepest_c->max_curvilinear_mm, 2)
       << " mm; thesis: combined cam-pincer CE 40 / alpha 80) -> "
       << (result.largest_curvilinear_at_combined ? "agree" : "**differ**") << ". Largest radial depth: CE "
       << fixed(deepest_r->ce_deg, 0) << " / alpha " << fixed(deepest_r->alpha_deg, 0) << " ("
       << fixed(deepest_r->max_radial_mm, 2) << " mm; thesis: pure cam CE 20 / alpha 80) -> "
       << (result.largest_radial_at_pure_cam ? "agree" : "**differ**") << ".\n\n";
  }
  result.markdown = md.str();
  return result;
}

}  // namespace hipfai::studies
