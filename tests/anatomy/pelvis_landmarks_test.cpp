// The anterior pelvic plane found on the real LHDL pelvis: where it lies against the CT frame, and
// that it moves with the bone (rigid transforms, mirroring, a rough superior hint), refuses a
// hemipelvis.
#include "anatomy/pelvis_landmarks.h"

#include "core/error.h"
#include "geometry/hip_frame.h"
#include "geometry/hjc_regions.h"
#include "geometry/mesh_io.h"
#include "tests/anatomy/anatomy_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace hipfai::anatomy {
namespace {

using test_support::angle_deg;

using geometry::Vec3;

const std::string kRealHip = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
// hip.json's femoral head sphere fit.
const Vec3 kHeadCentre(143.33, 243.35, -432.43);

const geometry::TriMesh& pelvis() {
  static const geometry::TriMesh mesh = geometry::read_mesh(kRealHip + "pelvis_no_sacrum.ply");
  return mesh;
}

PelvisLandmarks find(const geometry::TriMesh& mesh, const Vec3& hjc, const Vec3& hint) {
  PelvisLandmarksRequest request;
  request.pelvis = &mesh;
  request.hjc_mm = hjc;
  request.superior_hint = hint;
  return find_pelvis_landmarks(request);
}

Eigen::Isometry3d random_pelvis_motion(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
  t.translation() = Vec3(u(rng), u(rng), u(rng)) * 300.0;
  return t;
}

TEST(PelvisLandmarks, TheRealPelvisFrameAgreesWithTheScanAxes) {
  // The LHDL CT frame is the scanner's (DICOM-like: +x to the subject's left, +y posterior, +z
  // superior) with the subject supine: the APP frame must lie near it (pelvic tilt in a supine
  // scan is within ~ 10 deg of the APP being horizontal), not equal to it.
  const PelvisLandmarks found = find(pelvis(), kHeadCentre, Vec3::UnitZ());
  EXPECT_EQ(found.side, Side::kRight);
  EXPECT_LT(angle_deg(found.frame.right, -Vec3::UnitX()), 5.0);
  EXPECT_LT(angle_deg(found.frame.anterior, -Vec3::UnitY()), 15.0);
  EXPECT_LT(angle_deg(found.frame.superior, Vec3::UnitZ()), 15.0);
  // Right-handed, orthonormal.
  EXPECT_NEAR(found.frame.right.cross(found.frame.anterior).dot(found.frame.superior), 1.0, 1e-12);
  // Landmarks where they belong: the ASIS on their own sides, above and lateral of the tubercles;
  // the inter-ASIS distance of an adult pelvis (~ 200-280 mm).
  const double asis_width = (found.asis_right_mm - found.asis_left_mm).norm();
  EXPECT_GT(asis_width, 200.0);
  EXPECT_LT(asis_width, 280.0);
  EXPECT_GT(found.frame.superior.dot(found.asis_right_mm - found.pubic_tubercle_right_mm), 50.0);
  EXPECT_GT(found.frame.right.dot(kHeadCentre - 0.5 * (found.asis_right_mm + found.asis_left_mm)), 50.0);
  // The APP touches the pelvis at its landmarks and nothing lies in front of it (a supporting
  // plane, up to the tubercles' own spread).
  const Vec3 n = found.frame.anterior;
  const double plane = n.dot(found.asis_right_mm);
  EXPECT_NEAR(n.dot(found.asis_left_mm), plane, 1e-9);
  double ahead = -1e9;
  for (const Vec3& v : pelvis().vertices) ahead = std::max(ahead, n.dot(v) - plane);
  EXPECT_LT(ahead, 2.0);
  EXPECT_LT(found.symmetry_residual_mm, 0.05 * found.width_mm);
}

TEST(PelvisLandmarks, MoveWithTheBoneAndMirrorIntoALeftHip) {
  const PelvisLandmarks reference = find(pelvis(), kHeadCentre, Vec3::UnitZ());
  std::mt19937 rng(7);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::Isometry3d t = random_pelvis_motion(rng);
    geometry::TriMesh moved = pelvis();
    geometry::apply_transform(moved, t);
    const PelvisLandmarks found = find(moved, t * kHeadCentre, t.linear() * Vec3::UnitZ());
    EXPECT_LT((found.asis_right_mm - t * reference.asis_right_mm).norm(), 1e-6);
    EXPECT_LT((found.pubic_tubercle_left_mm - t * reference.pubic_tubercle_left_mm).norm(), 1e-6);
    EXPECT_LT(angle_deg(found.frame.anterior, t.linear() * reference.frame.anterior), 1e-6);
    EXPECT_LT(angle_deg(found.frame.right, t.linear() * reference.frame.right), 1e-6);
    EXPECT_EQ(found.side, Side::kRight);
  }
  // Mirrored through an arbitrary plane: a left pelvis whose right ASIS is the mirror of the
  // original's left one, and the hip on the left.
  const Eigen::Affine3d mirror = reflection(Vec3(10.0, -40.0, 5.0), Vec3(0.3, 0.9, -0.2).normalized());
  const geometry::TriMesh mirrored = reflected(pelvis(), mirror);
  const PelvisLandmarks found = find(mirrored, mirror * kHeadCentre, mirror.linear() * Vec3::UnitZ());
  EXPECT_EQ(found.side, Side::kLeft);
  EXPECT_LT((found.asis_right_mm - mirror * reference.asis_left_mm).norm(), 1e-6);
  EXPECT_LT((found.asis_left_mm - mirror * reference.asis_right_mm).norm(), 1e-6);
  EXPECT_LT(angle_deg(found.frame.anterior, mirror.linear() * reference.frame.anterior), 1e-6);
  EXPECT_LT(angle_deg(found.frame.superior, mirror.linear() * reference.frame.superior), 1e-6);
  EXPECT_LT(angle_deg(found.frame.right, -(mirror.linear() * reference.frame.right)), 1e-6);
}

TEST(PelvisLandmarks, ARoughSuperiorHintGivesTheSameLandmarks) {
  // The hint only picks the anterior face; tilted by 30 deg in any direction it must not change
  // the plane found (a supine CT's femur lies within ~ 20 deg of the pelvis' superior).
  const PelvisLandmarks reference = find(pelvis(), kHeadCentre, Vec3::UnitZ());
  for (const Vec3& tilt_axis : std::vector<Vec3>{Vec3::UnitX(), Vec3::UnitY(), Vec3(1, 1, 0).normalized()}) {
    for (const double degrees : {-30.0, 30.0}) {
      const Vec3 hint = Eigen::AngleAxisd(degrees * geometry::kDegToRad, tilt_axis) * Vec3::UnitZ();
      const PelvisLandmarks found = find(pelvis(), kHeadCentre, hint);
      EXPECT_LT((found.asis_right_mm - reference.asis_right_mm).norm(), 1e-9) << degrees;
      EXPECT_LT((found.pubic_tubercle_right_mm - reference.pubic_tubercle_right_mm).norm(), 1e-9) << degrees;
    }
  }
}

TEST(PelvisLandmarks, AHemipelvisIsRefusedWithOneLine) {
  const geometry::TriMesh half = geometry::submesh_where(pelvis(), [](const Vec3& v) { return v.x() < 240.0; });
  try {
    find(half, kHeadCentre, Vec3::UnitZ());
    FAIL() << "a hemipelvis was accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("not a whole pelvis"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
  geometry::TriMesh empty;
  PelvisLandmarksRequest request;
  request.pelvis = &empty;
  EXPECT_THROW(find_pelvis_landmarks(request), Error);
}

}  // namespace
}  // namespace hipfai::anatomy
