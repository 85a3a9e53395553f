// The thesis' Tables 8-10 as data and the cell-by-cell comparison, on synthetic study cells whose
// agreement is known by construction.
#include "studies/fai_reference.h"

#include <gtest/gtest.h>

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
