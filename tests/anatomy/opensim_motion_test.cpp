// Tests of the OpenSim motion reader (anatomy/opensim_motion.h): small .mot/.sto texts in degrees
// and radians, both sides, the layout of an example file of OpenSim's own tests, the bad files,
// and the header's claim that OpenSim's hip CustomJoint sequence is hipfai's joint coordinate
// system sequence.
#include "anatomy/opensim_motion.h"

#include "core/error.h"
#include "tests/anatomy/anatomy_checks.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

namespace hipfai::anatomy {
namespace {

using test_support::expect_error;

// Expects parse to throw hipfai::Error with a one-line message containing every part.
// OpenSim's Storage header as Storage::writeDefaultHeader writes it (name, version, nRows,
// nColumns, inDegrees), then endheader.
const std::string kDegreesMot =
    "walk_ik\n"
    "version=1\n"
    "nRows=3\n"
    "nColumns=5\n"
    "inDegrees=yes\n"
    "endheader\n"
    "time\thip_flexion_r\thip_adduction_r\thip_rotation_r\tknee_angle_r\n"
    "0.00\t10.5\t-2.25\t4.0\t-20\n"
    "0.01\t12\t-3\t5.5\t-22\n"
    "0.02\t14.75\t-3.5\t-7\t-25\n";

TEST(OpenSimMotion, ReadsDegreesAndKeepsTime) {
  const JointAngleSeries series = parse_opensim_motion(kDegreesMot, "walk.mot");
  EXPECT_EQ(series.name, "walk_ik");
  EXPECT_EQ(series.side, Side::kRight);
  ASSERT_EQ(series.poses.size(), 3u);
  ASSERT_EQ(series.time_s.size(), 3u);
  EXPECT_EQ(series.time_s[2], 0.02);
  // Degrees are copied unchanged (exact: no conversion).
  EXPECT_EQ(series.poses[0].flexion_deg, 10.5);
  EXPECT_EQ(series.poses[0].adduction_deg, -2.25);
  EXPECT_EQ(series.poses[0].internal_rotation_deg, 4.0);
  EXPECT_EQ(series.poses[2].internal_rotation_deg, -7.0);
}

TEST(OpenSimMotion, ConvertsRadiansOfTheLeftHip) {
  const std::string sto =
      "states\n"
      "version=1\n"
      "nRows=2\n"
      "nColumns=4\n"
      "inDegrees=no\n"
      "endheader\n"
      "time hip_rotation_l hip_flexion_l hip_adduction_l\n"  // spaces, and another column order
      "0.5 -0.1 1.0471975511965976 0.2\n"
      "0.75 0 +0.5 -0.25\n";
  const JointAngleSeries series = parse_opensim_motion(sto, "states.sto");
  EXPECT_EQ(series.side, Side::kLeft);
  ASSERT_EQ(series.poses.size(), 2u);
  // One multiplication by 180/pi: within a few ulps of 60 deg.
  EXPECT_NEAR(series.poses[0].flexion_deg, 60.0, 1e-12);
  EXPECT_NEAR(series.poses[0].adduction_deg, 0.2 * 180.0 / std::numbers::pi, 1e-12);
  EXPECT_NEAR(series.poses[0].internal_rotation_deg, -0.1 * 180.0 / std::numbers::pi, 1e-12);
  EXPECT_NEAR(series.poses[1].flexion_deg, 0.5 * 180.0 / std::numbers::pi, 1e-12);
  EXPECT_EQ(series.time_s[1], 0.75);
  // Asking for the right side of a left-only file is an error.
  expect_error([&] { parse_opensim_motion(sto, "states.sto", Side::kRight); },
               {"states.sto:7:", "no column hip_flexion_r"});
}

TEST(OpenSimMotion, ReadsOpenSim4StatePaths) {
  const std::string sto =
      "version=1\ninDegrees=no\nendheader\n"
      "time\t/jointset/hip_r/hip_flexion_r/value\t/jointset/hip_r/hip_flexion_r/speed\t"
      "/jointset/hip_r/hip_adduction_r/value\t/jointset/hip_r/hip_rotation_r/value\n"
      "0\t0.1\t5\t0.2\t0.3\n";
  const JointAngleSeries series = parse_opensim_motion(sto, "states.sto");
  ASSERT_EQ(series.poses.size(), 1u);
  EXPECT_NEAR(series.poses[0].flexion_deg, 0.1 * 180.0 / std::numbers::pi, 1e-12);  // not the speed column
  EXPECT_NEAR(series.poses[0].internal_rotation_deg, 0.3 * 180.0 / std::numbers::pi, 1e-12);
}

// The first lines of Applications/IK/tests/resources/std_subject01_walk1_ik.mot in OpenSim's
// sources (gait2392 inverse kinematics, a SIMM-style header with no version and no inDegrees:
// OpenSim reads such a .mot in degrees), with its row counts changed from 73 to the two rows kept.
std::string simm_walk(const std::string& rows) {
  return "First trial\t\t\t\n"
         "nRows=" + rows + "\t\t\t\n"
         "nColumns=24\t\t\t\n"
         "\t\t\t\n"
         "# SIMM Motion File Header:\t\t\t\n"
         "name first trial\t\t\t\n"
         "datacolumns 24\t\t\t\n"
         "datarows " + rows + "\t\t\t\n"
         "otherdata 1\t\t\t\n"
         "range 0.400000 1.600000\t\t\t\n"
         "endheader\n"
         "time\tpelvis_tilt\tpelvis_list\tpelvis_rotation\tpelvis_tx\tpelvis_ty\tpelvis_tz\thip_flexion_r\t"
         "hip_adduction_r\thip_rotation_r\tknee_angle_r\tankle_angle_r\tsubtalar_angle_r\thip_flexion_l\t"
         "hip_adduction_l\thip_rotation_l\tknee_angle_l\tankle_angle_l\tsubtalar_angle_l\tlumbar_extension\t"
         "lumbar_bending\tlumbar_rotation\tmtp_angle_r\tmtp_angle_l\n"
         "0.4\t5.21211788\t-1.90606861\t-0.87064439\t0.60176933\t1.04547006\t-0.02167826\t19.67986891\t"
         "-2.81547267\t-6.54743948\t-55.15907196\t2.77144862\t0.01353125\t-6.26933486\t1.25769946\t"
         "-0.90428342\t-7.26185614\t5.425119\t-0.00008378\t-16.77970596\t-0.24849451\t-5.24973036\t0\t0\n"
         "0.417\t5.19040076\t-1.79281414\t-0.72719721\t0.59905633\t1.04456937\t-0.02302733\t20.1704694\t"
         "-3.0099434\t-7.02786216\t-50.29830241\t2.78678039\t0.01321517\t-7.73853432\t1.45769557\t"
         "-0.7247911\t-6.27683521\t5.66724026\t-0.0001467\t-17.07117509\t-0.19829415\t-5.54417829\t0\t0\n";
}

TEST(OpenSimMotion, ReadsTheLayoutOfOpenSimsGaitExample) {
  const std::string text = simm_walk("2");
  // Both hips are there: the side must be given.
  expect_error([&] { parse_opensim_motion(text, "walk_ik.mot"); }, {"walk_ik.mot:12:", "both hips"});
  const JointAngleSeries right = parse_opensim_motion(text, "walk_ik.mot", Side::kRight);
  EXPECT_EQ(right.name, "first trial");  // the name line overrides the first line, as in OpenSim
  ASSERT_EQ(right.poses.size(), 2u);
  EXPECT_EQ(right.time_s[1], 0.417);
  EXPECT_EQ(right.poses[0].flexion_deg, 19.67986891);  // degrees: read unchanged
  EXPECT_EQ(right.poses[0].adduction_deg, -2.81547267);
  EXPECT_EQ(right.poses[1].internal_rotation_deg, -7.02786216);
  const JointAngleSeries left = parse_opensim_motion(text, "walk_ik.mot", Side::kLeft);
  EXPECT_EQ(left.side, Side::kLeft);
  EXPECT_EQ(left.poses[1].flexion_deg, -7.73853432);
  EXPECT_EQ(left.poses[0].internal_rotation_deg, -0.90428342);
  // The unedited header's counts disagree with the two rows kept.
  expect_error([&] { parse_opensim_motion(simm_walk("73"), "walk_ik.mot", Side::kRight); },
               {"walk_ik.mot", "2 data rows", "nRows=73"});
  // The degrees rule is the SIMM .mot files'; the same text named .sto has no units.
  expect_error([&] { parse_opensim_motion(text, "walk_ik.sto", Side::kRight); }, {"walk_ik.sto", "inDegrees"});
}

TEST(OpenSimMotion, AcceptsWindowsLineEnds) {
  std::string crlf;
  for (const char c : kDegreesMot) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  const JointAngleSeries series = parse_opensim_motion(crlf, "walk.mot");
  ASSERT_EQ(series.poses.size(), 3u);
  EXPECT_EQ(series.poses[1].flexion_deg, 12.0);
}

TEST(OpenSimMotion, ReadsAFile) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("hipfai_opensim_motion_" + std::to_string(::getpid()) +
                     ".mot");
  std::ofstream(path) << kDegreesMot;
  const JointAngleSeries series = read_opensim_motion(path, Side::kRight);
  std::filesystem::remove(path);
  EXPECT_EQ(series.poses.size(), 3u);
  expect_error([&] { read_opensim_motion(path); }, {path.string(), "cannot open"});
}

// Replaces the first occurrence of `from` in kDegreesMot.
std::string edited(const std::string& from, const std::string& to) {
  std::string text = kDegreesMot;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(OpenSimMotion, BadFilesAreOneLineErrorsNamingFileAndLine) {
  const auto parse = [](const std::string& text) { return [text] { parse_opensim_motion(text, "bad.mot"); }; };
  expect_error(parse(edited("endheader\n", "")), {"bad.mot", "no 'endheader'"});
  expect_error(parse(edited("hip_adduction_r", "hip_abduction_r")), {"bad.mot:7:", "no hip_flexion"});
  expect_error(parse(edited("12\t-3\t5.5\t-22", "12\t-3\t5.5")), {"bad.mot:9:", "expected 5 values, found 4"});
  expect_error(parse(edited("12\t-3", "12\tdeg")), {"bad.mot:9:", "hip_adduction_r", "'deg' is not a number"});
  expect_error(parse(edited("12\t-3", "12\tnan")), {"bad.mot:9:", "hip_adduction_r", "not finite"});
  expect_error(parse(edited("0.02\t", "0.01\t")), {"bad.mot:10:", "does not come after"});
  expect_error(parse(edited("nRows=3", "nRows=4")), {"bad.mot", "3 data rows", "nRows=4"});
  expect_error(parse(edited("nColumns=5", "nColumns=6")), {"bad.mot:7:", "nColumns=6"});
  expect_error(parse(edited("nRows=3", "nRows=three")), {"bad.mot:3:", "nRows"});
  expect_error(parse(edited("inDegrees=yes", "inDegrees=maybe")), {"bad.mot:5:", "inDegrees"});
  expect_error(parse(edited("time\t", "t\t")), {"bad.mot:7:", "expected 'time'"});
  expect_error(parse(edited("hip_rotation_r", "hip_flexion_r")), {"bad.mot:7:", "both hold hip_flexion_r"});
  const std::string header_only = kDegreesMot.substr(0, kDegreesMot.find("0.00\t"));
  expect_error(parse(header_only), {"bad.mot:7:", "no data rows"});
  expect_error(parse(kDegreesMot.substr(0, kDegreesMot.find("time"))), {"bad.mot:6:", "no column labels"});
  // Degrees read as radians: 10.5 rad is 601.6 deg, past any hip angle.
  expect_error(parse(edited("inDegrees=yes", "inDegrees=no")), {"bad.mot:8:", "hip_flexion_r", "radians"});
  // A version-1 file without a units line is not guessed.
  expect_error(parse(edited("inDegrees=yes\n", "")), {"bad.mot", "inDegrees"});
  expect_error(parse(""), {"bad.mot", "endheader"});
}

// The header's mapping: OpenSim's hip CustomJoint (pelvis frame X anterior, Y superior, Z right;
// body-fixed rotation1-2-3 about Z, X, Y for the right hip; Z, -X, -Y for the left) equals
// hipfai's Rx(flexion) Ry(adduction) Rz(internal rotation) after relabelling the axes, for the
// right hip as it is and for the left hip mirrored through the sagittal plane.
TEST(OpenSimMotion, CustomJointSequenceIsTheJointCoordinateSystem) {
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  Eigen::Matrix3d relabel;  // rows: hipfai X, Y, Z in OpenSim's axes (Z right, X anterior, Y superior)
  relabel << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  const Eigen::Matrix3d mirror = Eigen::Vector3d(1, 1, -1).asDiagonal();  // OpenSim's sagittal mirror
  for (const geometry::HipPoseDeg pose : {geometry::HipPoseDeg{59.6, 13.6, 10.9}, geometry::HipPoseDeg{-20, -35, 40},
                                          geometry::HipPoseDeg{90, 15, -25}}) {
    const double f = pose.flexion_deg * geometry::kDegToRad, a = pose.adduction_deg * geometry::kDegToRad,
                 r = pose.internal_rotation_deg * geometry::kDegToRad;
    const Eigen::Matrix3d hipfai = geometry::femur_rotation(pose, geometry::PoseSequence::kJointCoordinateSystem);
    const Eigen::Matrix3d right = (AngleAxisd(f, Vector3d::UnitZ()) * AngleAxisd(a, Vector3d::UnitX()) *
                                   AngleAxisd(r, Vector3d::UnitY()))
                                      .toRotationMatrix();
    const Eigen::Matrix3d left = (AngleAxisd(f, Vector3d::UnitZ()) * AngleAxisd(a, -Vector3d::UnitX()) *
                                  AngleAxisd(r, -Vector3d::UnitY()))
                                     .toRotationMatrix();
    // Products of three rotations: entries agree to a few ulps.
    EXPECT_LT((relabel * right * relabel.transpose() - hipfai).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT((relabel * mirror * left * mirror * relabel.transpose() - hipfai).cwiseAbs().maxCoeff(), 1e-14);
    // And the fixed-axes reading is not the same (the test can tell the two apart).
    const Eigen::Matrix3d fixed = geometry::femur_rotation(pose, geometry::PoseSequence::kFixedAxes);
    EXPECT_GT((relabel * right * relabel.transpose() - fixed).cwiseAbs().maxCoeff(), 1e-3);
  }
}

}  // namespace
}  // namespace hipfai::anatomy
