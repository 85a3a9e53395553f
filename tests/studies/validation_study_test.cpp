// The validation study end to end at its --quick size (2 hips, FE coarse, 6 steps), with the FE
// in worker processes (the hipfai program), then again from the cache: same numbers, nothing solved.
#include "studies/validation_study.h"

#include "studies/validation_report.h"
#include "tests/core/scratch_folder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace hipfai::studies {
namespace {

#ifdef HIPFAI_WITH_FEM
TEST(ValidationStudy, QuickRunEndToEndAndFromTheCache) {
  const std::filesystem::path program = std::filesystem::path(HIPFAI_BINARY_DIR) / "bin" / "hipfai";
  ASSERT_TRUE(std::filesystem::exists(program)) << program << ": build the hipfai program first";
  const auto root = std::filesystem::temp_directory_path() / "hipfai_validation_quick";
  std::filesystem::remove_all(root);
  ValidationOptions options;
  options.out_dir = root / "out1";
  options.cache_dir = root / "cache";
  options.hips = {{20, 40}, {40, 60}};
  options.edge_mm = 3.0;
  options.sub_motions = 6;
  options.fe_level = FeLevel::kCoarse;
  options.program = program;
  options.progress = false;
  const ValidationResult first = run_validation_study(options);
  ASSERT_EQ(first.hips.size(), 2u);
  for (const auto& hip : first.hips) {
    EXPECT_FALSE(hip.fe_reused);
    EXPECT_EQ(hip.fe_steps_failed, 0) << "CE " << hip.ce_deg << " alpha " << hip.alpha_deg;
    EXPECT_GT(hip.fe_dofs, 1000.0);
  }
  const std::string steps = test::file_contents(options.out_dir / "steps.csv");
  // Header + 2 hips x 6 steps, every FE value finite and positive for the primary measure.
  std::istringstream lines(steps);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line.rfind("ce_deg,alpha_deg,step,angle_deg,max_curvilinear_mm,max_radial_mm,von_mises_ball_model_mpa", 0),
            0u);
  int rows = 0;
  while (std::getline(lines, line)) {
    ++rows;
    std::istringstream cells(line);
    std::string cell;
    for (int c = 0; c < 7; ++c) std::getline(cells, cell, ',');
    EXPECT_GT(std::stod(cell), 0.0) << line;
  }
  EXPECT_EQ(rows, 12);
  const CorrelationReportResult report = write_correlation_report(options.out_dir);
  EXPECT_TRUE(std::filesystem::exists(report.report));
  EXPECT_TRUE(std::filesystem::exists(options.out_dir / "fig61" / "fe.vtu"));
  EXPECT_TRUE(std::filesystem::exists(options.out_dir / "fig61" / "ce40_alpha60_end_pose.vtm"));

  // Again into another folder: the FE comes from the cache and the numbers are the same.
  options.out_dir = root / "out2";
  const ValidationResult second = run_validation_study(options);
  for (const auto& hip : second.hips) EXPECT_TRUE(hip.fe_reused);
  EXPECT_EQ(test::file_contents(options.out_dir / "steps.csv"), steps);
}
#endif

TEST(ValidationStudy, RejectsUnusableOptionsBeforeAnyWork) {
  ValidationOptions options;
  options.out_dir = std::filesystem::temp_directory_path() / "hipfai_validation_rejected";
  std::filesystem::remove_all(options.out_dir);
  options.sub_motions = 2;
  EXPECT_ANY_THROW(run_validation_study(options));
  options.sub_motions = 6;
  options.fe_level = FeLevel::kCoarse;
  options.program = "/nonexistent/hipfai";
  EXPECT_ANY_THROW(run_validation_study(options));
  EXPECT_FALSE(std::filesystem::exists(options.out_dir));
}

}  // namespace
}  // namespace hipfai::studies
