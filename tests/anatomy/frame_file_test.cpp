// Tests of the user frame reader (anatomy/frame_file.h): the three shapes (axes, landmarks, a hip
// model.json written by the project's own writer), frames built from landmarks placed in a known
// pose, and the errors.
#include "anatomy/frame_file.h"

#include "core/error.h"
#include "geometry/hip_model.h"
#include "tests/anatomy/anatomy_checks.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace hipfai::anatomy {
namespace {

using test_support::expect_error;

using geometry::Vec3;
using Json = nlohmann::json;

Json to_json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

// A rigid placement of the canonical (right, anterior, superior) = (X, Y, Z) coordinates: an
// oblique rotation and a CT-like offset, as a segmented bone would sit in its scan.
const Eigen::Matrix3d kRotation =
    (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(-0.4, Vec3::UnitX())).toRotationMatrix();
const Vec3 kOffset(143.8, 243.46, -432.58);
Vec3 placed(const Vec3& canonical) { return kRotation * canonical + kOffset; }

// Frames built from double-precision arithmetic on ~500 mm coordinates: axes agree to ~1e-15, so
// 1e-12 leaves room for the few operations and still catches any wrong sign or axis.
constexpr double kTol = 1e-12;

void expect_axes(const AnatomicalFrame& frame, const Eigen::Matrix3d& expected_axes, const Vec3& origin) {
  EXPECT_LT((frame.axes() - expected_axes).cwiseAbs().maxCoeff(), kTol) << frame.axes();
  EXPECT_LT((frame.origin_mm - origin).norm(), 1e-9);  // mm: coordinates of ~500 mm
}

Json axes_file() {
  Json file;
  file["side"] = "left";
  file["hjc_mm"] = to_json(kOffset);
  // Pelvis: the placed canonical axes, given at other lengths (they are normalised).
  file["frames"]["pelvis"] = {{"origin_mm", to_json(kOffset)},
                              {"right", to_json(2.0 * kRotation.col(0))},
                              {"anterior", to_json(0.5 * kRotation.col(1))},
                              {"superior", to_json(kRotation.col(2))}};
  file["extra"] = "ignored";
  return file;
}

TEST(FrameFile, ReadsAxes) {
  const UserFrame user = parse_frame_file(axes_file().dump(), "frames.json");
  EXPECT_EQ(user.source_kind, "axes");
  ASSERT_TRUE(user.side.has_value());
  EXPECT_EQ(*user.side, Side::kLeft);
  ASSERT_TRUE(user.hjc_mm.has_value());
  EXPECT_EQ(*user.hjc_mm, kOffset);
  ASSERT_TRUE(user.pelvis.has_value());
  EXPECT_FALSE(user.femur.has_value());
  EXPECT_FALSE(user.neck_axis.has_value());
  expect_axes(*user.pelvis, kRotation, kOffset);
}

TEST(FrameFile, AxesErrors) {
  const auto parse = [](const Json& file) { return [text = file.dump()] { parse_frame_file(text, "f.json"); }; };
  Json bent = axes_file();
  // 0.01 rad off orthogonal: cosine 0.01, ten times the tolerance.
  bent["frames"]["femur"] = bent["frames"]["pelvis"];
  bent["frames"]["femur"]["anterior"] = to_json(kRotation * Vec3(0.01, 1, 0));
  expect_error(parse(bent), {"f.json: frames.femur", "right and anterior are not orthogonal"});
  Json left_handed = axes_file();
  left_handed["frames"]["pelvis"]["superior"] = to_json(-kRotation.col(2));
  expect_error(parse(left_handed), {"f.json: frames.pelvis", "left-handed"});
  Json zero = axes_file();
  zero["frames"]["pelvis"]["right"] = Json::array({0, 0, 0});
  expect_error(parse(zero), {"frames.pelvis.right", "zero"});
  Json text_component = axes_file();
  text_component["frames"]["pelvis"]["superior"] = Json::array({0, "up", 1});
  expect_error(parse(text_component), {"frames.pelvis.superior", "numbers"});
  Json two = axes_file();
  two["frames"]["pelvis"]["origin_mm"] = Json::array({1, 2});
  expect_error(parse(two), {"frames.pelvis.origin_mm", "[x, y, z]"});
  Json no_origin = axes_file();
  no_origin["frames"]["pelvis"].erase("origin_mm");
  expect_error(parse(no_origin), {"frames.pelvis.origin_mm", "missing"});
  Json empty = axes_file();
  empty["frames"] = Json::object();
  expect_error(parse(empty), {"f.json: frames", "neither"});
  Json bad_side = axes_file();
  bad_side["side"] = 1;
  expect_error(parse(bad_side), {"f.json: side"});
  expect_error([] { parse_frame_file("{\"frames\": ", "f.json"); }, {"f.json: invalid JSON"});
  expect_error([] { parse_frame_file("[1, 2]", "f.json"); }, {"f.json: expected a JSON object"});
  expect_error([] { parse_frame_file("{\"hjc_mm\": [0, 0, 0]}", "f.json"); }, {"f.json: no \"frames\""});
}

// A pelvis in canonical coordinates: the anterior pelvic plane is y = 0, the ASIS 230 mm apart and
// 90 mm above the pubic tubercles (adult proportions; the frame does not depend on them).
Json canonical_pelvis_landmarks() {
  return {{"asis_right_mm", to_json(placed(Vec3(115, 0, 0)))},
          {"asis_left_mm", to_json(placed(Vec3(-115, 0, 0)))},
          {"pubic_tubercle_right_mm", to_json(placed(Vec3(25, 0, -90)))},
          {"pubic_tubercle_left_mm", to_json(placed(Vec3(-25, 0, -90)))}};
}

// A right femur: head centre beside the pelvis, epicondyles 430 mm below it, 80 mm apart, the
// lateral one (right) 10 mm higher (a tilted epicondyle line: the frame keeps only its part
// perpendicular to the head-to-knee axis).
Json canonical_right_femur_landmarks() {
  return {{"head_centre_mm", to_json(placed(Vec3(90, 0, -60)))},
          {"lateral_epicondyle_mm", to_json(placed(Vec3(130, 0, -485)))},
          {"medial_epicondyle_mm", to_json(placed(Vec3(50, 0, -495)))}};
}

TEST(FrameFile, BuildsFramesFromLandmarks) {
  Json file;
  file["side"] = "right";
  file["pelvis_landmarks"] = canonical_pelvis_landmarks();
  file["femur_landmarks"] = canonical_right_femur_landmarks();
  const UserFrame user = parse_frame_file(file.dump(), "landmarks.json");
  EXPECT_EQ(user.source_kind, "landmarks");
  ASSERT_TRUE(user.pelvis && user.femur && user.hjc_mm);
  // The HJC defaults to the head centre, and is the pelvic frame's origin.
  EXPECT_LT((*user.hjc_mm - placed(Vec3(90, 0, -60))).norm(), 1e-9);
  expect_axes(*user.pelvis, kRotation, placed(Vec3(90, 0, -60)));
  // Femur: superior from the epicondyles' midpoint (90, 0, -490) to the head: exactly +Z.
  expect_axes(*user.femur, kRotation, placed(Vec3(90, 0, -60)));
  // Without the femur, the pelvic origin is the ASIS midpoint, or hjc_mm when given.
  file.erase("femur_landmarks");
  expect_axes(*parse_frame_file(file.dump(), "l.json").pelvis, kRotation, placed(Vec3(0, 0, 0)));
  file["hjc_mm"] = to_json(placed(Vec3(-90, 1, -61)));
  expect_axes(*parse_frame_file(file.dump(), "l.json").pelvis, kRotation, placed(Vec3(-90, 1, -61)));
}

TEST(FrameFile, LeftFemurPointsRightToTheMedialEpicondyle) {
  // The right femur mirrored through the mid-sagittal plane x = 0.
  Json file;
  file["side"] = "left";
  file["pelvis_landmarks"] = canonical_pelvis_landmarks();
  file["femur_landmarks"] = {{"head_centre_mm", to_json(placed(Vec3(-90, 0, -60)))},
                             {"lateral_epicondyle_mm", to_json(placed(Vec3(-130, 0, -485)))},
                             {"medial_epicondyle_mm", to_json(placed(Vec3(-50, 0, -495)))}};
  const UserFrame user = parse_frame_file(file.dump(), "landmarks.json");
  ASSERT_TRUE(user.femur);
  expect_axes(*user.femur, kRotation, placed(Vec3(-90, 0, -60)));
}

TEST(FrameFile, LandmarkErrors) {
  const auto parse = [](const Json& file) { return [text = file.dump()] { parse_frame_file(text, "l.json"); }; };
  Json file;
  file["side"] = "right";
  file["pelvis_landmarks"] = canonical_pelvis_landmarks();
  file["femur_landmarks"] = canonical_right_femur_landmarks();
  // The right femur's landmarks called left: its head is on the pelvis's right.
  Json wrong_side = file;
  wrong_side["side"] = "left";
  expect_error(parse(wrong_side), {"l.json: side: left", "right of the ASIS midpoint"});
  Json no_side = file;
  no_side.erase("side");
  expect_error(parse(no_side), {"l.json: side: missing"});
  Json same_asis = file;
  same_asis["pelvis_landmarks"]["asis_left_mm"] = same_asis["pelvis_landmarks"]["asis_right_mm"];
  expect_error(parse(same_asis), {"l.json: pelvis_landmarks", "ASIS are 0 mm apart"});
  Json flat_pubis = file;  // the pubic midpoint on the line through the ASIS
  flat_pubis["pelvis_landmarks"]["pubic_tubercle_right_mm"] = to_json(placed(Vec3(25, 0, 0)));
  flat_pubis["pelvis_landmarks"]["pubic_tubercle_left_mm"] = to_json(placed(Vec3(-25, 0, 0)));
  expect_error(parse(flat_pubis), {"l.json: pelvis_landmarks", "from the line through the ASIS"});
  Json same_epicondyles = file;
  same_epicondyles["femur_landmarks"]["medial_epicondyle_mm"] = same_epicondyles["femur_landmarks"]["lateral_epicondyle_mm"];
  expect_error(parse(same_epicondyles), {"l.json: femur_landmarks", "epicondyles are 0 mm apart"});
  Json axial_epicondyles = file;  // the epicondyle line along the head-to-knee axis
  axial_epicondyles["femur_landmarks"]["lateral_epicondyle_mm"] = to_json(placed(Vec3(90, 0, -470)));
  axial_epicondyles["femur_landmarks"]["medial_epicondyle_mm"] = to_json(placed(Vec3(90, 0, -510)));
  expect_error(parse(axial_epicondyles), {"l.json: femur_landmarks", "parallel"});
  Json missing = file;
  missing["femur_landmarks"].erase("head_centre_mm");
  expect_error(parse(missing), {"l.json: femur_landmarks.head_centre_mm: missing"});
  Json both = file;
  both["frames"] = axes_file()["frames"];
  expect_error(parse(both), {"l.json: both frames and landmarks"});
}

// A hip model as write_hip_model writes it, with its hip frame placed by kRotation/kOffset (a
// right hip: X lateral = right, Y anterior, Z superior).
geometry::HipModel placed_model() {
  geometry::HipModel model;
  model.hjc_mm = kOffset;
  model.lateral = kRotation.col(0);
  model.superior = kRotation.col(2);
  model.axes.flexion_axis = kRotation.col(0);
  model.axes.adduction_axis = kRotation.col(1);
  model.axes.internal_rotation_axis = kRotation.col(2);
  model.neck_axis = kRotation * Vec3(0.75, -0.16, -0.64).normalized();
  return model;
}

std::string written_model_json(const geometry::HipModel& model) {
  // One folder per test and process: CTest runs the tests of this file in parallel processes.
  const auto dir = std::filesystem::temp_directory_path() /
                   ("hipfai_frame_file_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                    "_" + std::to_string(::getpid()));
  geometry::write_hip_model(model, dir);
  std::ifstream in(dir / "model.json");
  std::stringstream text;
  text << in.rdbuf();
  std::filesystem::remove_all(dir);
  return text.str();
}

TEST(FrameFile, ReadsAHipModel) {
  const geometry::HipModel model = placed_model();
  const UserFrame user = parse_frame_file(written_model_json(model), "model.json");
  EXPECT_EQ(user.source_kind, "hip-model");
  ASSERT_TRUE(user.side && user.hjc_mm && user.pelvis && user.femur && user.neck_axis);
  EXPECT_EQ(*user.side, Side::kRight);
  EXPECT_LT((*user.hjc_mm - kOffset).norm(), 1e-9);
  expect_axes(*user.pelvis, kRotation, kOffset);
  expect_axes(*user.femur, kRotation, kOffset);
  EXPECT_LT((*user.neck_axis - model.neck_axis).norm(), kTol);
}

TEST(FrameFile, HipModelErrors) {
  Json json = Json::parse(written_model_json(placed_model()));
  const auto parse = [](const Json& file) { return [text = file.dump()] { parse_frame_file(text, "m.json"); }; };
  Json left = json;
  left["handedness"] = "left";
  expect_error(parse(left), {"m.json: handedness: 'left'", "right hips"});
  Json swapped = json;  // flexion about the superior axis: not this hip frame
  swapped["flexion_axis"] = json["superior"];
  expect_error(parse(swapped), {"m.json: flexion_axis: differs from lateral"});
  Json oblique = json;
  oblique["superior"] = to_json(kRotation * Vec3(0.01, 0, 1));
  expect_error(parse(oblique), {"m.json: lateral and superior are not orthogonal"});
  Json no_neck = json;
  no_neck.erase("neck_axis");
  expect_error(parse(no_neck), {"m.json: neck_axis: missing"});
  Json other = json;
  other["format"] = "something-else";
  expect_error(parse(other), {"m.json: format"});
}

TEST(FrameFile, ReadsAFile) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("hipfai_frame_file_read_" + std::to_string(::getpid()) + ".json");
  std::ofstream(path) << axes_file().dump(2);
  const UserFrame user = read_frame_file(path);
  std::filesystem::remove(path);
  EXPECT_TRUE(user.pelvis.has_value());
  expect_error([&] { read_frame_file(path); }, {path.string(), "cannot open"});
}

}  // namespace
}  // namespace hipfai::anatomy
