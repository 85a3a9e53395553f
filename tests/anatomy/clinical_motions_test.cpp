// Tests of the clinical motions to bony impingement (anatomy/clinical_motions.h) on generated
// hips: the exact ranges against a brute-force stepping oracle (pose the femur, test the bones
// for intersection), invariance under a mirrored-and-moved copy of the hip, the cam hip's lost
// FADIR internal rotation, intersecting bones, an unreachable start pose, and the JSON.
#include "anatomy/clinical_motions.h"
#include "anatomy/side.h"
#include "contact/start_pose.h"
#include "core/error.h"
#include "geometry/hip_frame.h"
#include "geometry/primitive_meshes.h"
#include "tests/geometry/study_hips.h"
#include "tests/anatomy/anatomy_checks.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

namespace hipfai::anatomy {
namespace {

using test_support::rotated;

using geometry::TriMesh;
using geometry::Vec3;

// The thesis' coarser surface level: ranges are exact for any mesh, so the test does not need a
// fine one, and the brute-force oracle stays fast.
constexpr double kClinicalEdgeMm = geometry::test_support::kStudyTestEdgeMm;

ClinicalRomRequest clinical_request_for(const geometry::HipModel& hip) {
  ClinicalRomRequest request;
  request.pelvis = &hip.tissue("acetabular_bone");
  request.femur = &hip.tissue("femur_bone");
  request.hjc_mm = hip.hjc_mm;
  request.hip_axes = Eigen::Matrix3d::Identity();  // generated hips are in their hip frame
  request.acetabulum = make_clock_face(hip.hjc_mm, hip.acetabular_axis, hip.superior);
  request.femoral_head = make_clock_face(hip.hjc_mm, hip.neck_axis, hip.superior);
  return request;
}

bool intersect(const TriMesh& pelvis, const TriMesh& femur, const Vec3& centre) {
  contact::StartPoseOptions options;
  options.centre = centre;
  const auto overlap = contact::check_start_pose(pelvis, femur, options);
  EXPECT_EQ(overlap.status, contact::QueryStatus::kOk) << overlap.message;
  return overlap.overlaps();
}

TEST(ClinicalMotions, RangesMatchBruteForceStepping) {
  const auto& hip = geometry::test_support::study_hip(30.0, 60.0, kClinicalEdgeMm);
  const ClinicalRomRequest request = clinical_request_for(hip);
  const ClinicalRom rom = clinical_range_of_motion(request);
  // The oracle poses the femur by start pose * turn and asks contact::check_start_pose whether the
  // bones intersect (vertices and edges, beyond 1 um). Every limit must be free on a 5 deg grid
  // up to it and 0.25 deg before it, and intersecting 0.25 deg after it: 0.25 deg at the contact's
  // 20-70 mm from the HJC moves it 0.09-0.3 mm, far beyond the oracle's 1 um touching tolerance.
  constexpr double kGridDeg = 5.0;
  constexpr double kBracketDeg = 0.25;
  int limited = 0;
  for (const MotionOutcome* outcome : rom.motions()) {
    ASSERT_TRUE(outcome->limit.has_value()) << outcome->reason;
    const MotionLimit& m = *outcome->limit;
    SCOPED_TRACE(m.name);
    auto femur_at = [&](double angle_deg) {
      const Eigen::Matrix3d turn =
          Eigen::AngleAxisd(m.sign * angle_deg * geometry::kDegToRad, m.axis).toRotationMatrix();
      return rotated(*request.femur, turn * m.start_rotation, request.hjc_mm);
    };
    const double scan_to = m.unlimited ? 359.0 : m.angle_deg - kBracketDeg;
    for (double a = 0.0; a < scan_to; a += kGridDeg) {
      ASSERT_FALSE(intersect(*request.pelvis, femur_at(a), request.hjc_mm)) << "at " << a << " deg";
    }
    ASSERT_FALSE(intersect(*request.pelvis, femur_at(scan_to), request.hjc_mm));
    if (m.unlimited) continue;
    ++limited;
    EXPECT_TRUE(intersect(*request.pelvis, femur_at(m.angle_deg + kBracketDeg), request.hjc_mm))
        << "limit " << m.angle_deg;
    // The reported contact point lies on both bones at the limit: within a few um of the pelvis
    // vertex / the rotated femur vertex (exact), and the clocks are those of that point.
    EXPECT_NEAR(m.acetabular_clock.angle_deg, clock_angle_deg(request.acetabulum, m.contact_point_mm), 1e-9);
    EXPECT_EQ(m.acetabular_clock.label, geometry::clock_label(m.acetabular_clock.angle_deg));
  }
  EXPECT_GE(limited, 6);  // the socket stops most clinical motions of a generated hip
}

// Distance from p to segment [a, b].
double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (a + t * (b - a) - p).norm();
}

// The femoral clock is the contact point's in the femur at neutral: undoing the limit pose brings
// the point back onto the femur's contact feature (its vertex, its triangle's plane, its edge).
TEST(ClinicalMotions, FemoralClockIsTheContactTakenBackToNeutral) {
  const auto& hip = geometry::test_support::study_hip(30.0, 60.0, kClinicalEdgeMm);
  const ClinicalRomRequest request = clinical_request_for(hip);
  const ClinicalRom rom = clinical_range_of_motion(request);
  const auto& femur = request.femur->vertices;
  int checked = 0;
  for (const MotionOutcome* outcome : rom.motions()) {
    if (!outcome->limit || outcome->limit->unlimited) continue;
    const MotionLimit& m = *outcome->limit;
    SCOPED_TRACE(m.name);
    const Eigen::Matrix3d total =
        Eigen::AngleAxisd(m.sign * m.angle_deg * geometry::kDegToRad, m.axis).toRotationMatrix() * m.start_rotation;
    const Vec3 back = request.hjc_mm + total.transpose() * (m.contact_point_mm - request.hjc_mm);
    // 1e-6 mm: rounding of rotations of points ~100 mm from the HJC; the edge-edge meeting point
    // is exact up to the closed-form root's rounding (far below 1e-6 rad x 100 mm).
    switch (m.contact.kind) {
      case contact::ContactKind::kMobileVertexOnFixedTriangle:
        EXPECT_LT((back - femur[static_cast<std::size_t>(m.contact.vertex)]).norm(), 1e-6);
        break;
      case contact::ContactKind::kFixedVertexOnMobileTriangle: {
        const auto& t = request.femur->triangles[static_cast<std::size_t>(m.contact.triangle)];
        const Vec3 n = geometry::triangle_unit_normal(*request.femur, static_cast<std::size_t>(m.contact.triangle));
        EXPECT_LT(std::abs((back - femur[static_cast<std::size_t>(t[0])]).dot(n)), 1e-6);
        break;
      }
      case contact::ContactKind::kEdgeOnEdge:
        EXPECT_LT(segment_distance(back, femur[static_cast<std::size_t>(m.contact.mobile_edge[0])],
                                   femur[static_cast<std::size_t>(m.contact.mobile_edge[1])]), 1e-6);
        break;
      case contact::ContactKind::kNone: break;
    }
    EXPECT_NEAR(m.femoral_clock.angle_deg, clock_angle_deg(request.femoral_head, back), 1e-9);
    EXPECT_EQ(m.femoral_clock.label, geometry::clock_label(m.femoral_clock.angle_deg));
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

// A right hip mirrored into a left one, moved by a random rigid motion and mirrored back through
// another plane (anatomy/side.h) is the same hip in other coordinates: same ranges and clocks.
TEST(ClinicalMotions, MirroredAndMovedHipGivesTheSameRom) {
  const auto& hip = geometry::test_support::study_hip(20.0, 80.0, kClinicalEdgeMm);
  const ClinicalRomRequest original = clinical_request_for(hip);
  const ClinicalRom expected = clinical_range_of_motion(original);

  std::mt19937 random(20260531);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const Vec3 random_axis = Vec3(uniform(random), uniform(random), uniform(random)).normalized();
  Eigen::Affine3d rigid = Eigen::Affine3d::Identity();
  rigid.linear() = Eigen::AngleAxisd(2.0 * uniform(random) + 0.5, random_axis).toRotationMatrix();
  rigid.translation() = Vec3(150.0 * uniform(random), 250.0 * uniform(random), -400.0 + 50.0 * uniform(random));
  const Eigen::Affine3d to_left = reflection(Vec3(-80.0, 0.0, 0.0), Vec3::UnitX());
  const Eigen::Affine3d back_to_right =
      reflection(rigid * Vec3(-80.0, 0.0, 0.0), Vec3(uniform(random), uniform(random), uniform(random)));
  const Eigen::Affine3d map = back_to_right * rigid * to_left;
  ASSERT_NEAR(map.linear().determinant(), 1.0, 1e-12);
  const Eigen::Matrix3d L = map.linear();

  const TriMesh pelvis = reflected(reflected(*original.pelvis, rigid * to_left), back_to_right);
  const TriMesh femur = reflected(reflected(*original.femur, rigid * to_left), back_to_right);
  ClinicalRomRequest moved = original;
  moved.pelvis = &pelvis;
  moved.femur = &femur;
  moved.hjc_mm = map * original.hjc_mm;
  moved.hip_axes = L * original.hip_axes;
  for (ClockFace* face : {&moved.acetabulum, &moved.femoral_head}) {
    face->centre_mm = map * face->centre_mm;
    face->axis = L * face->axis;
    face->anterior = L * face->anterior;
    face->superior = L * face->superior;
  }
  const ClinicalRom got = clinical_range_of_motion(moved);
  const auto want = expected.motions();
  const auto have = got.motions();
  for (std::size_t k = 0; k < want.size(); ++k) {
    ASSERT_EQ(want[k]->limit.has_value(), have[k]->limit.has_value()) << k;
    if (!want[k]->limit) {
      EXPECT_EQ(want[k]->reason, have[k]->reason);
      continue;
    }
    const MotionLimit& a = *want[k]->limit;
    const MotionLimit& b = *have[k]->limit;
    SCOPED_TRACE(a.name);
    // Rounding of the moved coordinates only (1e-13 relative at 500 mm): 0.01 deg is generous.
    EXPECT_NEAR(a.angle_deg, b.angle_deg, 0.01);
    EXPECT_EQ(a.unlimited, b.unlimited);
    if (a.unlimited) continue;
    // The same contact, so the same clocks up to rounding.
    EXPECT_EQ(a.contact.kind, b.contact.kind);
    EXPECT_NEAR(a.acetabular_clock.angle_deg, b.acetabular_clock.angle_deg, 1e-6);
    EXPECT_NEAR(a.femoral_clock.angle_deg, b.femoral_clock.angle_deg, 1e-6);
    EXPECT_EQ(a.acetabular_clock.label, b.acetabular_clock.label);
    EXPECT_LT((map * a.contact_point_mm - b.contact_point_mm).norm(), 1e-6);
  }
}

// Cam impingement: at the same CE, the hip with alpha 80 deg has less internal rotation in the
// FADIR position than the hip with alpha 40 deg.
TEST(ClinicalMotions, CamHipLosesFadirInternalRotation) {
  const ClinicalRom normal = clinical_range_of_motion(clinical_request_for(geometry::test_support::study_hip(20.0, 40.0, kClinicalEdgeMm)));
  const ClinicalRom cam = clinical_range_of_motion(clinical_request_for(geometry::test_support::study_hip(20.0, 80.0, kClinicalEdgeMm)));
  ASSERT_TRUE(normal.fadir_internal_rotation.limit) << normal.fadir_internal_rotation.reason;
  ASSERT_TRUE(cam.fadir_internal_rotation.limit) << cam.fadir_internal_rotation.reason;
  std::printf("FADIR internal rotation: alpha 40 %.2f deg, alpha 80 %.2f deg; IR at 90 flexion %.2f / %.2f deg\n",
              normal.fadir_internal_rotation.limit->angle_deg, cam.fadir_internal_rotation.limit->angle_deg,
              normal.internal_rotation_at_90_flexion.limit->angle_deg,
              cam.internal_rotation_at_90_flexion.limit->angle_deg);
  EXPECT_LT(cam.fadir_internal_rotation.limit->angle_deg, normal.fadir_internal_rotation.limit->angle_deg);
}

TEST(ClinicalMotions, IntersectingBonesAreRefused) {
  const auto& hip = geometry::test_support::study_hip(30.0, 60.0, kClinicalEdgeMm);
  ClinicalRomRequest request = clinical_request_for(hip);
  // 6 mm deeper into the socket: more than the two 2 mm cartilage layers between the bones.
  TriMesh femur = *request.femur;
  for (auto& v : femur.vertices) v -= 6.0 * hip.acetabular_axis;
  request.femur = &femur;
  try {
    clinical_range_of_motion(request);
    FAIL() << "no error";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind("the bones intersect in the neutral pose: ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
}

// A block in front of the femoral shaft stops flexion before 90 deg: the motions from 90 deg of
// flexion have no start pose, and say why; FABER's 45 deg may still be reachable.
TEST(ClinicalMotions, UnreachableStartPoseGivesReason) {
  const auto& hip = geometry::test_support::study_hip(30.0, 60.0, kClinicalEdgeMm);
  ClinicalRomRequest request = clinical_request_for(hip);
  const auto box = geometry::bounding_box(*request.femur);
  // Anterior of the shaft's distal end, clear of it by 5 mm at neutral.
  const TriMesh block = geometry::make_box(Vec3(box.min.x(), box.max.y() + 5.0, box.min.z()),
                                           Vec3(box.max.x(), box.max.y() + 25.0, box.min.z() + 15.0), 2);
  const TriMesh pelvis = geometry::merge_meshes({request.pelvis, &block});
  request.pelvis = &pelvis;
  const ClinicalRom rom = clinical_range_of_motion(request);
  ASSERT_TRUE(rom.flexion.limit);
  const double flexion = rom.flexion.limit->angle_deg;
  ASSERT_LT(flexion, 90.0);
  // The limit is the block's (its triangles come after the socket's in the merged mesh).
  const auto& c = rom.flexion.limit->contact;
  const bool block_contact =
      (c.kind == contact::ContactKind::kMobileVertexOnFixedTriangle &&
       c.triangle >= static_cast<std::int32_t>(hip.tissue("acetabular_bone").num_triangles())) ||
      (c.kind == contact::ContactKind::kFixedVertexOnMobileTriangle &&
       c.vertex >= static_cast<std::int32_t>(hip.tissue("acetabular_bone").num_vertices())) ||
      (c.kind == contact::ContactKind::kEdgeOnEdge &&
       c.fixed_edge[0] >= static_cast<std::int32_t>(hip.tissue("acetabular_bone").num_vertices()));
  EXPECT_TRUE(block_contact);
  char expected[96];
  std::snprintf(expected, sizeof(expected), "flexion stops at %.1f deg, before 90", flexion);
  for (const MotionOutcome* outcome : {&rom.internal_rotation_at_90_flexion, &rom.external_rotation_at_90_flexion,
                                       &rom.fadir_internal_rotation}) {
    EXPECT_FALSE(outcome->limit);
    EXPECT_EQ(outcome->reason, expected);
  }
  const auto json = nlohmann::json::parse(clinical_rom_json(rom));
  EXPECT_TRUE(json["fadir_internal_rotation"].is_null());
  EXPECT_EQ(json["reasons"]["fadir_internal_rotation"], expected);
  EXPECT_NEAR(json["flexion"]["deg"].get<double>(), flexion, 1e-12);
}

TEST(ClinicalMotions, JsonHasTheTenKeys) {
  const auto& hip = geometry::test_support::study_hip(30.0, 60.0, kClinicalEdgeMm);
  const ClinicalRom rom = clinical_range_of_motion(clinical_request_for(hip));
  const auto json = nlohmann::json::parse(clinical_rom_json(rom));
  for (const char* key : {"flexion", "extension", "abduction", "adduction", "internal_rotation", "external_rotation",
                          "internal_rotation_at_90_flexion", "external_rotation_at_90_flexion",
                          "fadir_internal_rotation", "faber"}) {
    ASSERT_TRUE(json.contains(key)) << key;
  }
  const auto& ir90 = json["internal_rotation_at_90_flexion"];
  ASSERT_FALSE(ir90.is_null());
  EXPECT_NEAR(ir90["deg"].get<double>(), rom.internal_rotation_at_90_flexion.limit->angle_deg, 1e-12);
  if (!rom.internal_rotation_at_90_flexion.limit->unlimited) {
    EXPECT_EQ(ir90["contact"]["acetabular_clock"], rom.internal_rotation_at_90_flexion.limit->acetabular_clock.label);
  }
}

TEST(ClinicalMotions, BadInputThrows) {
  const auto& hip = geometry::test_support::study_hip(30.0, 60.0, kClinicalEdgeMm);
  ClinicalRomRequest request = clinical_request_for(hip);
  request.hip_axes.col(0) *= -1.0;  // left-handed
  EXPECT_THROW(clinical_range_of_motion(request), Error);
  request = clinical_request_for(hip);
  request.acetabulum.anterior = request.acetabulum.axis;
  EXPECT_THROW(clinical_range_of_motion(request), Error);
  request = clinical_request_for(hip);
  request.femur = nullptr;
  EXPECT_THROW(clinical_range_of_motion(request), Error);
}

}  // namespace
}  // namespace hipfai::anatomy
