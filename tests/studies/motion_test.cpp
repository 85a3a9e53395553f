#include "studies/motion.h"

#include "core/error.h"
#include "core/literature.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace hipfai::studies {
namespace {

// The last sub-motion must reproduce the thesis end pose exactly (Cardan angles recovered from the
// interpolated rotation), and every sub-motion turns by the same angle about the same axis.
TEST(Motion, StandingToSittingEndsAtThesisPose) {
  const Motion motion = standing_to_sitting(30);
  ASSERT_EQ(motion.steps.size(), 30u);
  const auto& last = motion.steps.back().pose;
  EXPECT_NEAR(last.flexion_deg, literature::kStandToSitFlexionDeg, 1e-9);
  EXPECT_NEAR(last.adduction_deg, literature::kStandToSitAdductionDeg, 1e-9);
  EXPECT_NEAR(last.internal_rotation_deg, literature::kStandToSitInternalRotationDeg, 1e-9);
  const double step_angle = motion.steps.front().angle_deg;
  for (std::size_t k = 0; k < motion.steps.size(); ++k) {
    EXPECT_NEAR(motion.steps[k].angle_deg, step_angle * (k + 1), 1e-9);
    EXPECT_NEAR((motion.steps[k].axis - motion.steps.front().axis).norm(), 0.0, 1e-12);
  }
}

TEST(Motion, MedicalRotationsTurnAboutFrameAxes) {
  const Motion flexion = medical_rotation("flexion", 90.0, 9);
  EXPECT_NEAR(flexion.steps.back().angle_deg, 90.0, 1e-9);
  EXPECT_NEAR(flexion.steps.back().axis.x(), 1.0, 1e-12);
  const Motion external = medical_rotation("external_rotation", 30.0, 3);
  EXPECT_NEAR(external.steps.back().axis.z(), -1.0, 1e-12);
  EXPECT_THROW(medical_rotation("twist", 30.0, 3), hipfai::Error);
}

std::filesystem::path write_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path;
}

TEST(Motion, ReadsCsvWithForces) {
  const auto path = write_file("hipfai_motion_ok.csv",
                               "step,flexion_deg,adduction_deg,internal_rotation_deg,Fx_N,Fy_N,Fz_N\n"
                               "1,10,0,0,0,0,-700\n2,20,5,1,10,20,-1000\n");
  const Motion motion = read_motion_csv(path);
  ASSERT_EQ(motion.steps.size(), 2u);
  EXPECT_DOUBLE_EQ(motion.steps[1].pose.adduction_deg, 5.0);
  ASSERT_TRUE(motion.steps[1].force_N.has_value());
  EXPECT_DOUBLE_EQ(motion.steps[1].force_N->z(), -1000.0);
}

TEST(Motion, BadCsvNamesTheLine) {
  const auto path = write_file("hipfai_motion_bad.csv",
                               "step,flexion_deg,adduction_deg,internal_rotation_deg\n1,10,0,0\n2,x,0,0\n");
  try {
    read_motion_csv(path);
    FAIL() << "expected an error";
  } catch (const hipfai::Error& e) {
    EXPECT_NE(std::string(e.what()).find(":3:"), std::string::npos) << e.what();
  }
  // Radians by mistake are not caught, but values beyond a full turn are: 200 "deg".
  const auto units = write_file("hipfai_motion_units.csv",
                                "step,flexion_deg,adduction_deg,internal_rotation_deg\n1,200,0,0\n");
  EXPECT_THROW(read_motion_csv(units), hipfai::Error);
}

}  // namespace
}  // namespace hipfai::studies
