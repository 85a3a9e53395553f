// The thesis' Tables 8-10 as data and the cell-by-cell comparison, on synthetic study cells whose
// agreement is known by construction.
#include "studies/fai_reference.h"

#include "core/error.h"
#include "stats/pearson.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace hipfai::studies {
namespace {

std::vector<StudyCell> thesis_pattern() {
  std::vector<StudyCell> cells;
  for (double ce = 0; ce <= 40; ce += 10) {
    for (double alpha = 40; alpha <= 80; alpha += 10) {
      const bool c = thesis_curvilinear_cell(ce, alpha) == ReferenceCell::kPenetrates;
      const bool r = thesis_radial_cell(ce, alpha) == ReferenceCell::kPenetrates;
      cells.push_back({ce, alpha, c ? 1.0 : 0.0, r ? 1.0 : 0.0, 0.0});
    }
  }
  return cells;
}

TEST(FaiReference, TablesEightAndNineCells) {
  // Table 8: 15 penetrating cells, on the diagonal CE + alpha >= 80.
  int curvilinear = 0, radial = 0, ambiguous = 0;
  for (double ce = 0; ce <= 40; ce += 10) {
    for (double alpha = 40; alpha <= 80; alpha += 10) {
      curvilinear += thesis_curvilinear_cell(ce, alpha) == ReferenceCell::kPenetrates;
      radial += thesis_radial_cell(ce, alpha) == ReferenceCell::kPenetrates;
      ambiguous += thesis_radial_cell(ce, alpha) == ReferenceCell::kAmbiguous;
    }
  }
  EXPECT_EQ(curvilinear, 15);
  EXPECT_EQ(radial, 15);
  EXPECT_EQ(ambiguous, 6);  // CE 10 / 40-60, CE 20 / 40-50, CE 30 / 40
  EXPECT_EQ(thesis_curvilinear_cell(0, 80), ReferenceCell::kPenetrates);
  EXPECT_EQ(thesis_curvilinear_cell(10, 60), ReferenceCell::kNoPenetration);
  EXPECT_EQ(thesis_radial_cell(20, 40), ReferenceCell::kAmbiguous);
  EXPECT_EQ(thesis_radial_cell(0, 70), ReferenceCell::kNoPenetration);
  EXPECT_EQ(thesis_curvilinear_cell(15, 60), ReferenceCell::kAmbiguous);  // off the grid
}

constexpr double kGridCe[] = {0, 10, 20, 30, 40};
constexpr double kGridAlpha[] = {40, 50, 60, 70, 80};

// Value rounded to the 2 decimals the thesis prints.
double round2(double v) { return std::round(v * 100.0) / 100.0; }

struct Moments {
  double mean = 0, population_sd = 0, sample_sd = 0, min = 1, max = -1;
  int n = 0;
};
Moments moments(const std::vector<double>& values) {
  Moments m;
  m.n = static_cast<int>(values.size());
  for (double v : values) {
    m.mean += v;
    m.min = std::min(m.min, v);
    m.max = std::max(m.max, v);
  }
  m.mean /= m.n;
  double ss = 0;
  for (double v : values) ss += (v - m.mean) * (v - m.mean);
  m.population_sd = std::sqrt(ss / m.n);
  m.sample_sd = std::sqrt(ss / (m.n - 1));
  return m;
}

std::vector<double> printed_r(bool curvilinear, bool radial) {
  std::vector<double> r;
  for (double ce : kGridCe) {
    for (double alpha : kGridAlpha) {
      if (curvilinear && thesis_table8(ce, alpha).penetrates) r.push_back(thesis_table8(ce, alpha).r);
      if (radial && thesis_table9(ce, alpha).penetrates) r.push_back(thesis_table9(ce, alpha).r);
    }
  }
  return r;
}

// The n.p. cells of Tables 8 and 9 are those of thesis_curvilinear_cell / thesis_radial_cell; the
// radial cells those functions call ambiguous are exactly the weak ones Table 9 lists (r <= 0.61).
TEST(FaiReference, TablesEightAndNineValuesAgreeWithTheCellFunctions) {
  int np8 = 0, np9 = 0;
  for (double ce : kGridCe) {
    for (double alpha : kGridAlpha) {
      const ThesisCorrelation c = thesis_table8(ce, alpha), r = thesis_table9(ce, alpha);
      np8 += !c.penetrates;
      np9 += !r.penetrates;
      EXPECT_EQ(thesis_curvilinear_cell(ce, alpha),
                c.penetrates ? ReferenceCell::kPenetrates : ReferenceCell::kNoPenetration)
          << "CE " << ce << " alpha " << alpha;
      const ReferenceCell radial = thesis_radial_cell(ce, alpha);
      if (radial == ReferenceCell::kAmbiguous) {
        EXPECT_TRUE(r.penetrates);
        EXPECT_LE(r.r, 0.61);
      } else {
        EXPECT_EQ(radial, r.penetrates ? ReferenceCell::kPenetrates : ReferenceCell::kNoPenetration)
            << "CE " << ce << " alpha " << alpha;
      }
      for (const ThesisCorrelation& cell : {c, r}) {
        if (cell.penetrates) {
          EXPECT_GT(cell.r, 0.0);
          EXPECT_LE(cell.r, 1.0);
          EXPECT_GT(cell.p, 0.0);
          EXPECT_LT(cell.p, 0.1);
        } else {
          EXPECT_EQ(cell.r, 0.0);
          EXPECT_EQ(cell.p, 1.0);
        }
      }
    }
  }
  EXPECT_EQ(np8, 10);  // CE + alpha < 80
  EXPECT_EQ(np9, 4);   // CE 0 / alpha 40-70
}

// The check of the transcription: the thesis' summary (§4.3.3.1) recomputed from the transcribed
// r. The printed SDs are reproduced by the POPULATION standard deviation (divisor n): curvilinear
// 0.0382 -> 0.04, radial 0.2205 -> 0.22, all 0.1787 -> 0.18. The sample SD (divisor n - 1) gives
// 0.0395, 0.2260 and 0.1812: the radial value rounds to 0.23, not the printed 0.22 (only 0.001
// past the rounding boundary, so the thesis may have used the sample SD of its unrounded r).
TEST(FaiReference, TranscribedCorrelationsReproduceTheThesisSummary) {
  struct Case {
    const char* name;
    std::vector<double> r;
    ThesisCorrelationSummary printed;
    int n;
  };
  const Case cases[] = {
      {"curvilinear", printed_r(true, false), thesis_summary_curvilinear(), 15},
      {"radial", printed_r(false, true), thesis_summary_radial(), 21},
      {"all", printed_r(true, true), thesis_summary_all(), 36},
  };
  for (const Case& c : cases) {
    const Moments m = moments(c.r);
    EXPECT_EQ(m.n, c.n) << c.name;
    EXPECT_NEAR(round2(m.mean), c.printed.mean, 1e-12) << c.name << " mean " << m.mean;
    EXPECT_NEAR(round2(m.population_sd), c.printed.sd, 1e-12) << c.name << " SD " << m.population_sd;
    EXPECT_EQ(m.min, c.printed.min) << c.name;
    EXPECT_EQ(m.max, c.printed.max) << c.name;
  }
  EXPECT_NEAR(round2(moments(printed_r(true, false)).sample_sd), 0.04, 1e-12);
  EXPECT_NEAR(round2(moments(printed_r(false, true)).sample_sd), 0.23, 1e-12);  // printed: 0.22
  EXPECT_NEAR(round2(moments(printed_r(true, true)).sample_sd), 0.18, 1e-12);
  // The summary as printed.
  EXPECT_EQ(thesis_summary_all().mean, 0.84);
  EXPECT_EQ(thesis_summary_curvilinear().sd, 0.04);
  EXPECT_EQ(thesis_summary_radial().min, 0.31);
}

TEST(FaiReference, TablesEightAndNineSpotCells) {
  const ThesisCorrelation dysplasia_impingement = thesis_table8(0, 80);
  EXPECT_TRUE(dysplasia_impingement.penetrates);
  EXPECT_EQ(dysplasia_impingement.r, 0.85);
  EXPECT_EQ(dysplasia_impingement.p, 2.14e-9);
  EXPECT_EQ(thesis_table8(40, 40).r, 0.97);  // pincer
  EXPECT_EQ(thesis_table8(40, 40).p, 3.73e-19);
  EXPECT_EQ(thesis_table8(20, 80).p, 3.99e-10);  // cam
  EXPECT_FALSE(thesis_table8(30, 40).penetrates);
  EXPECT_EQ(thesis_table9(10, 40).r, 0.31);  // the weakest, not significant
  EXPECT_EQ(thesis_table9(10, 40).p, 0.092);
  EXPECT_EQ(thesis_table9(20, 40).r, 0.60);  // the normal hip
  EXPECT_EQ(thesis_table9(20, 40).p, 3.88e-4);
  EXPECT_EQ(thesis_table9(30, 70).p, 3.32e-20);
  EXPECT_EQ(thesis_table9(40, 80).r, 0.96);
  EXPECT_FALSE(thesis_table9(0, 70).penetrates);
  EXPECT_TRUE(thesis_table9(0, 80).penetrates);
}

TEST(FaiReference, TablesEightAndNineThrowOffTheGrid) {
  EXPECT_THROW(thesis_table8(15, 60), hipfai::Error);
  EXPECT_THROW(thesis_table8(50, 60), hipfai::Error);
  EXPECT_THROW(thesis_table8(-10, 60), hipfai::Error);
  EXPECT_THROW(thesis_table9(20, 30), hipfai::Error);
  EXPECT_THROW(thesis_table9(20, 90), hipfai::Error);
  EXPECT_THROW(thesis_table9(20, 65), hipfai::Error);
  EXPECT_THROW(thesis_table9(std::numeric_limits<double>::quiet_NaN(), 40), hipfai::Error);
  EXPECT_NO_THROW(thesis_table9(40, 80));
}

// Two-sided p of Pearson r with n pairs, by the library (Student's t, n - 2 degrees of freedom):
// pearson() of a constructed sample whose r is exactly the given one.
double library_p(double r, int n) {
  std::vector<double> u(n), v(n);
  double uu = 0, vv = 0, v_mean = 0;
  for (int i = 0; i < n; ++i) {
    u[i] = i - (n - 1) / 2.0;  // odd about the centre ...
    v[i] = u[i] * u[i];        // ... and even: orthogonal once v is centred
    v_mean += v[i] / n;
  }
  for (int i = 0; i < n; ++i) {
    v[i] -= v_mean;
    uu += u[i] * u[i];
    vv += v[i] * v[i];
  }
  std::vector<double> y(n);
  for (int i = 0; i < n; ++i) y[i] = r * u[i] / std::sqrt(uu) + std::sqrt(1 - r * r) * v[i] / std::sqrt(vv);
  return stats::pearson(u, y).p_value;
}

// Does a printed (r, p) pair fit n pairs: p within the p-values of r -+ 0.005 (r's rounding),
// widened by p's own 3-digit rounding?
bool fits(const ThesisCorrelation& cell, int n) {
  return library_p(cell.r + 0.005, n) <= cell.p * 1.005 && cell.p * 0.995 <= library_p(cell.r - 0.005, n);
}

// The printed p follow from the printed r by Student's t with 31 pairs (the 30 sub-motions of
// standing-to-sitting and the start pose) — a check of the transcribed p, exponents included —
// except at five extreme hips, the same five in both tables, where "the full movement could not
// be applied ... due to large deformation" (§4.3.2.3): there a shorter series fits both tables
// (CE 20 / alpha 80: 28 pairs, CE 30 / 80: 22, CE 40 / 60: 27, CE 40 / 70: 25 or 26, CE 40 / 80: 15).
TEST(FaiReference, PrintedPValuesFollowFromRAndTheNumberOfPoses) {
  struct Short {
    double ce, alpha;
    int n;
  };
  const Short shortened[] = {{20, 80, 28}, {30, 80, 22}, {40, 60, 27}, {40, 70, 26}, {40, 80, 15}};
  int full = 0;
  for (double ce : kGridCe) {
    for (double alpha : kGridAlpha) {
      int n = 31;
      for (const Short& s : shortened) {
        if (s.ce == ce && s.alpha == alpha) n = s.n;
      }
      full += n == 31 && thesis_table9(ce, alpha).penetrates;
      for (const ThesisCorrelation& cell : {thesis_table8(ce, alpha), thesis_table9(ce, alpha)}) {
        if (!cell.penetrates) continue;
        EXPECT_TRUE(fits(cell, n)) << "CE " << ce << " alpha " << alpha << " r " << cell.r << " p " << cell.p;
        if (n != 31) {
          EXPECT_FALSE(fits(cell, 31)) << "CE " << ce << " alpha " << alpha;
        }
      }
    }
  }
  EXPECT_EQ(full, 16);
  // Discriminating: a wrong exponent or a wrong second decimal of r does not fit.
  EXPECT_FALSE(fits({true, 0.85, 2.14e-8}, 31));
  EXPECT_FALSE(fits({true, 0.85, 2.14e-10}, 31));
  EXPECT_FALSE(fits({true, 0.86, 2.14e-9}, 31));
}

TEST(FaiReference, ComparisonCountsAgreementsCellByCell) {
  std::vector<StudyCell> cells = thesis_pattern();
  const auto same = compare_with_thesis(cells);
  EXPECT_EQ(same.curvilinear_agree, 25);
  EXPECT_EQ(same.curvilinear_counted, 25);
  EXPECT_EQ(same.radial_agree, 19);
  EXPECT_EQ(same.radial_counted, 19);
  // Flip two curvilinear cells and one counted radial cell; an ambiguous radial cell changes nothing.
  for (auto& c : cells) {
    if (c.ce_deg == 0 && c.alpha_deg == 80) c.max_curvilinear_mm = 0.0;
    if (c.ce_deg == 20 && c.alpha_deg == 50) c.max_curvilinear_mm = 2.0;
    if (c.ce_deg == 40 && c.alpha_deg == 40) c.max_radial_mm = 0.0;
    if (c.ce_deg == 20 && c.alpha_deg == 40) c.max_radial_mm = 3.0;
  }
  const auto flipped = compare_with_thesis(cells);
  EXPECT_EQ(flipped.curvilinear_agree, 23);
  EXPECT_EQ(flipped.radial_agree, 18);
  EXPECT_EQ(flipped.radial_counted, 19);
  EXPECT_NE(flipped.markdown.find("Table 8"), std::string::npos);
  EXPECT_NE(flipped.markdown.find("Table 9"), std::string::npos);
}

TEST(FaiReference, TableTenBandsWithinOneBand) {
  // Depths at the middle of the thesis' bands agree in every band; the difference column uses
  // the normalised difference bands.
  std::vector<StudyCell> cells;
  const double curvilinear_mid[] = {2.5, 7.5, 12.5, 17.5, 22.5};
  const double radial_mid[] = {1.0, 3.0, 5.0, 7.0, 9.0};
  const double difference_mid[] = {-0.3, -0.1, 0.1, 0.3};
  for (const auto& m : thesis_table10()) {
    cells.push_back({m.ce_deg, m.alpha_deg, curvilinear_mid[band_rank(m.curvilinear_band)],
                     radial_mid[band_rank(m.radial_band)], difference_mid[band_rank(m.difference_band)]});
  }
  const auto result = compare_with_thesis(cells);
  EXPECT_EQ(result.table10_counted, 18);
  EXPECT_EQ(result.table10_within_one_band, 18);
  EXPECT_TRUE(result.largest_curvilinear_at_combined);
  // Pure cam and combined share the "very high" radial band; with equal values the first wins.
  cells[2].max_radial_mm = 9.5;
  EXPECT_TRUE(compare_with_thesis(cells).largest_radial_at_pure_cam);
  // Two bands off: the cam's curvilinear depth in "very low" instead of "high".
  cells[2].max_curvilinear_mm = 1.0;
  EXPECT_EQ(compare_with_thesis(cells).table10_within_one_band, 17);
}

}  // namespace
}  // namespace hipfai::studies
