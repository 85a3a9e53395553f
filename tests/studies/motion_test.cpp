#include "studies/pipeline/motion.h"

#include "core/error.h"
#include "core/literature.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

// The two readings of a pose's angles, on a pose where they give different answers by hand:
// flexion 90 then internal rotation 90. In the joint coordinate system the internal rotation turns
// the femur about its own long axis, so the knee (distal femur, -Z at neutral) stays anterior; about
// the fixed pelvic Z it swings the flexed femur medially (-X for a right hip).
TEST(Motion, PoseSequencesTurnTheKneeAsTheirDefinitionsSay) {
  const geometry::HipPoseDeg pose{90.0, 0.0, 90.0};
  const Eigen::Vector3d knee(0.0, 0.0, -1.0);
  const Eigen::Vector3d jcs = geometry::femur_rotation(pose, geometry::PoseSequence::kJointCoordinateSystem) * knee;
  const Eigen::Vector3d fixed = geometry::femur_rotation(pose, geometry::PoseSequence::kFixedAxes) * knee;
  EXPECT_NEAR((jcs - Eigen::Vector3d(0.0, 1.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((fixed - Eigen::Vector3d(-1.0, 0.0, 0.0)).norm(), 0.0, 1e-12);
  // One angle alone: both readings are the same rotation.
  for (const geometry::HipPoseDeg single : {geometry::HipPoseDeg{30, 0, 0}, geometry::HipPoseDeg{0, -20, 0},
                                            geometry::HipPoseDeg{0, 0, 45}}) {
    EXPECT_NEAR((geometry::femur_rotation(single, geometry::PoseSequence::kFixedAxes) -
                 geometry::femur_rotation(single))
                    .norm(),
                0.0, 1e-15);
  }
}

// Standing to sitting read about the fixed axes: one axis, equal angles, the last step the fixed-axes
// end pose; the steps' Cardan angles are the joint-coordinate-system angles of their rotation (the
// convention of motion CSV files), so a CSV round trip keeps the motion.
TEST(Motion, StandingToSittingAboutFixedAxesEndsAtTheFixedAxesPose) {
  const Motion motion = standing_to_sitting(30, geometry::PoseSequence::kFixedAxes);
  ASSERT_EQ(motion.steps.size(), 30u);
  const Eigen::Matrix3d end = geometry::femur_rotation(
      {literature::kStandToSitFlexionDeg, literature::kStandToSitAdductionDeg, literature::kStandToSitInternalRotationDeg},
      geometry::PoseSequence::kFixedAxes);
  EXPECT_NEAR((motion.steps.back().rotation - end).norm(), 0.0, 1e-12);
  for (std::size_t k = 0; k < motion.steps.size(); ++k) {
    EXPECT_NEAR((motion.steps[k].axis - motion.steps.front().axis).norm(), 0.0, 1e-12);
    EXPECT_NEAR(motion.steps[k].angle_deg, motion.steps.front().angle_deg * (k + 1), 1e-9);
    EXPECT_NEAR((geometry::femur_rotation(motion.steps[k].pose) - motion.steps[k].rotation).norm(), 0.0, 1e-12);
  }
  // The two readings of the thesis' end pose are different poses (17.4 deg apart).
  const Motion jcs = standing_to_sitting(30);
  const double apart_deg =
      Eigen::AngleAxisd(jcs.steps.back().rotation.transpose() * motion.steps.back().rotation).angle() *
      geometry::kRadToDeg;
  EXPECT_GT(apart_deg, 17.0);
  EXPECT_LT(apart_deg, 18.0);
  EXPECT_EQ(pose_sequence_from_name(pose_sequence_name(geometry::PoseSequence::kFixedAxes)),
            geometry::PoseSequence::kFixedAxes);
  EXPECT_EQ(pose_sequence_from_name("jcs"), geometry::PoseSequence::kJointCoordinateSystem);
  EXPECT_THROW(pose_sequence_from_name("zyx"), hipfai::Error);
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

// The one published number: the resultant of the last sub-motion (phase 1, the default peak)
// is 156 %BW x W exactly (closed form); the direction is the stated one (superior, medial).
TEST(SittingDownLoad, PeakIsTheBergmannValueAtTheEndPose) {
  Motion motion = standing_to_sitting(30);
  SittingDownLoadOptions options;
  options.body_weight_n = 700.0;
  attach_sitting_down_load(motion, options);
  const Eigen::Vector3d peak = *motion.steps.back().force_N;
  // Pure arithmetic on doubles: relative 1e-12.
  EXPECT_NEAR(peak.norm(), 1.56 * 700.0, 1e-12 * 1092.0);
  EXPECT_EQ(literature::kStandToSitPeakForcePercentBW, 156.0);
  EXPECT_GT(peak.z(), 0.0);  // femur pushes the pelvis superiorly
  EXPECT_LT(peak.x(), 0.0);  // and medially (-X for a right hip)
  EXPECT_NEAR(std::atan2(-peak.x(), peak.z()) * geometry::kRadToDeg,
              literature::kSitDownAssumedFrontalAngleDeg, 1e-9);
  double largest = 0.0;
  for (std::size_t k = 0; k < motion.steps.size(); ++k) {
    const double magnitude = motion.steps[k].force_N->norm();
    if (k > 0) {
      EXPECT_GT(magnitude, motion.steps[k - 1].force_N->norm()) << "step " << k;
    }
    largest = std::max(largest, magnitude);
  }
  EXPECT_EQ(largest, peak.norm());
  // Start of the activity (phase 0): the assumed upright value.
  EXPECT_NEAR(sitting_down_force_n(0.0, options).norm(),
              literature::kSitDownAssumedStartForcePercentBW / 100.0 * 700.0, 1e-9);
}

// Peak inside the motion: strictly rising before it, strictly falling after it, the maximum at
// the step whose phase is the peak phase, the end value at phase 1.
TEST(SittingDownLoad, RisesToThePeakThenFalls) {
  Motion motion = standing_to_sitting(20);
  SittingDownLoadOptions options;
  options.body_weight_n = 800.0;
  options.peak_phase = 0.6;  // step 11 (0-based) of 20 sits at phase 12/20
  options.sagittal_angle_deg = 10.0;
  attach_sitting_down_load(motion, options);
  const std::size_t peak_step = 11;
  for (std::size_t k = 1; k < motion.steps.size(); ++k) {
    const double change = motion.steps[k].force_N->norm() - motion.steps[k - 1].force_N->norm();
    if (k <= peak_step) {
      EXPECT_GT(change, 0.0) << "step " << k;
    } else {
      EXPECT_LT(change, 0.0) << "step " << k;
    }
  }
  EXPECT_NEAR(motion.steps[peak_step].force_N->norm(), 1.56 * 800.0, 1e-9);
  EXPECT_NEAR(motion.steps.back().force_N->norm(),
              literature::kSitDownAssumedEndForcePercentBW / 100.0 * 800.0, 1e-9);
  EXPECT_GT(motion.steps.back().force_N->y(), 0.0);  // anterior tilt asked for
  options.body_weight_n = 0.0;
  EXPECT_THROW(attach_sitting_down_load(motion, options), hipfai::Error);
  options.body_weight_n = 800.0;
  options.peak_phase = 0.0;
  EXPECT_THROW(attach_sitting_down_load(motion, options), hipfai::Error);
}

// write_motion_csv -> read_motion_csv gives back the poses (rotation rebuilt from the written
// Cardan angles) and the forces.
TEST(SittingDownLoad, CsvRoundTripKeepsPosesAndForces) {
  Motion motion = standing_to_sitting(30);
  SittingDownLoadOptions options;
  options.body_weight_n = 650.0;
  attach_sitting_down_load(motion, options);
  const auto path = std::filesystem::temp_directory_path() / "hipfai_motion_sitting_down.csv";
  write_motion_csv(motion, path);
  const Motion back = read_motion_csv(path);
  ASSERT_EQ(back.steps.size(), motion.steps.size());
  for (std::size_t k = 0; k < back.steps.size(); ++k) {
    ASSERT_TRUE(back.steps[k].force_N.has_value());
    // Written with max_digits10: the forces come back bit for bit.
    EXPECT_EQ(*back.steps[k].force_N, *motion.steps[k].force_N) << "step " << k;
    // Rotation rebuilt from Cardan angles that were themselves recovered from the rotation:
    // round-off of eulerAngles, ~1e-15; bound 1e-12.
    EXPECT_LT((back.steps[k].rotation - motion.steps[k].rotation).norm(), 1e-12) << "step " << k;
  }
  EXPECT_THROW(write_motion_csv(motion, "/nonexistent-dir/motion.csv"), hipfai::Error);
}

}  // namespace
}  // namespace hipfai::studies
