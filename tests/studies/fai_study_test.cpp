// `hipfai study fai --quick` settings: the output layout and the two anchor cases.
#include "studies/fai_study.h"

#include "studies/results/results_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace hipfai::studies {
namespace {

TEST(FaiStudy, QuickRunWritesCompleteFiniteResults) {
  FaiStudyOptions options;
  options.out_dir = std::filesystem::temp_directory_path() / "hipfai_fai_quick";
  options.cache_dir = std::filesystem::temp_directory_path() / "hipfai_fai_cache";
  std::filesystem::remove_all(options.out_dir);
  options.edge_mm = 3.0;  // the --quick settings
  options.sub_motions = 10;
  options.progress = false;
  const FaiStudyResult result = run_fai_study(options);
  ASSERT_EQ(result.models.size(), 25u);

  for (const char* file : {"results.h5", "summary.csv", "steps.csv", "resolution.csv", "report.md",
                           "fig63_curvilinear.svg", "fig63_radial.svg", "fig63_difference.svg",
                           "fig63_pathology.svg", "fig62_curvilinear.svg", "fig62_radial.svg",
                           "fig60_ce40_alpha60.svg", "hip_ce40_alpha80.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(options.out_dir / file)) << file;
  }
  EXPECT_TRUE(std::filesystem::exists(options.out_dir / "vtp" / "ce40_alpha80_labrum_step010.vtp"));
  const auto h5 = options.out_dir / "results.h5";
  std::size_t rows = 0;
  const auto curvilinear = read_dataset(h5, "/summary/max_curvilinear_mm", &rows);
  EXPECT_EQ(rows, 25u);
  const auto radial = read_dataset(h5, "/summary/max_radial_mm");
  const auto ce = read_dataset(h5, "/summary/ce_deg");
  const auto alpha = read_dataset(h5, "/summary/alpha_deg");
  for (std::size_t i = 0; i < rows; ++i) {
    EXPECT_TRUE(std::isfinite(curvilinear[i]) && std::isfinite(radial[i]));
    EXPECT_GE(curvilinear[i], 0.0);
    EXPECT_GE(radial[i], 0.0);
    if (ce[i] == 20 && alpha[i] == 40) {  // normal hip: no penetration (thesis §4.3.3.2)
      EXPECT_EQ(curvilinear[i], 0.0);
      EXPECT_EQ(radial[i], 0.0);
    }
    if (ce[i] == 40 && alpha[i] == 80) {  // combined cam-pincer: penetration
      EXPECT_GT(curvilinear[i] + radial[i], 0.0);
    }
  }
  std::size_t steps = 0;
  const auto per_step = read_dataset(h5, "/models/ce40_alpha80/radial_max_mm", &steps);
  EXPECT_EQ(steps, 10u);
  for (double d : per_step) EXPECT_TRUE(std::isfinite(d));
  EXPECT_FALSE(read_string_attribute(h5, "/", "code_version").empty());
  std::ifstream summary(options.out_dir / "summary.csv");
  int lines = 0;
  for (std::string line; std::getline(summary, line);) ++lines;
  EXPECT_EQ(lines, 26);
}

TEST(FaiStudy, PathologyAndBandsFollowThesisTable10) {
  EXPECT_EQ(pathology_of(20, 40), "normal");
  EXPECT_EQ(pathology_of(40, 40), "pincer");
  EXPECT_EQ(pathology_of(20, 80), "cam");
  EXPECT_EQ(pathology_of(40, 80), "combined cam-pincer");
  EXPECT_EQ(pathology_of(0, 40), "dysplasia");
  EXPECT_EQ(pathology_of(0, 80), "combined dysplasia-impingement");
  EXPECT_EQ(curvilinear_band(0.0), "none");
  EXPECT_EQ(curvilinear_band(12.0), "intermediate");
  EXPECT_EQ(radial_band(9.0), "very high");
  EXPECT_EQ(difference_band(-0.3), "very low");
  EXPECT_EQ(difference_band(0.25), "high");
}

// --hip-parameters: the base parameters reach the generator (a different hip, cached apart), the
// grid keeps its own CE, alpha and edge, and a base equal to the defaults is the default hip.
TEST(FaiStudy, BaseHipParametersKeyTheGeneratedHip) {
  const std::filesystem::path cache = "cache";
  const ParametricHip plain{20.0, 80.0, 3.0};
  geometry::HipParameters defaults;
  EXPECT_EQ(generated_hip_dir(ParametricHip{20.0, 80.0, 3.0, defaults}, cache), generated_hip_dir(plain, cache));
  geometry::HipParameters grid_fields = defaults;  // CE, alpha and edge of the base are replaced
  grid_fields.ce_deg = 40.0;
  grid_fields.alpha_deg = 45.0;
  grid_fields.edge_mm = 1.0;
  EXPECT_EQ(generated_hip_dir(ParametricHip{20.0, 80.0, 3.0, grid_fields}, cache), generated_hip_dir(plain, cache));
  geometry::HipParameters cranial = defaults;
  cranial.acetabular_anteversion_deg = 14.4;
  EXPECT_NE(generated_hip_dir(ParametricHip{20.0, 80.0, 3.0, cranial}, cache), generated_hip_dir(plain, cache));
  const auto changed = geometry::hip_parameters_changed(cranial);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed.front().first, "acetabular_anteversion_deg");
  EXPECT_DOUBLE_EQ(changed.front().second, 14.4);
}

}  // namespace
}  // namespace hipfai::studies
