// The clinical measures on shapes whose answer is known: the head-neck offset of a sphere on a
// cylinder (the offset is the difference of their radii), and the morphology of generated hips whose
// CE and alpha are set by construction.
#include "anatomy/clinical_measures.h"

#include "anatomy/acetabulum.h"
#include "anatomy/femur_landmarks.h"
#include "geometry/hip_frame.h"
#include "geometry/primitive_meshes.h"
#include "tests/geometry/study_hips.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hipfai::anatomy {
namespace {

using geometry::TriMesh;
using geometry::Vec3;

// A closed cylinder of `radius` along +X from x0 to x1, `segments` around, outward.
TriMesh cylinder_along_x(double radius, double x0, double x1, int segments, int rings) {
  TriMesh mesh;
  for (int i = 0; i <= rings; ++i) {
    const double x = x0 + (x1 - x0) * i / rings;
    for (int k = 0; k < segments; ++k) {
      const double a = 2.0 * std::numbers::pi * k / segments;
      mesh.vertices.emplace_back(x, radius * std::cos(a), radius * std::sin(a));
    }
  }
  const auto id = [&](int i, int k) { return static_cast<std::int32_t>(i * segments + (k % segments)); };
  for (int i = 0; i < rings; ++i) {
    for (int k = 0; k < segments; ++k) {
      mesh.triangles.push_back({id(i, k), id(i + 1, k), id(i + 1, k + 1)});
      mesh.triangles.push_back({id(i, k), id(i + 1, k + 1), id(i, k + 1)});
    }
  }
  const auto start = static_cast<std::int32_t>(mesh.vertices.size());
  mesh.vertices.emplace_back(x0, 0.0, 0.0);
  mesh.vertices.emplace_back(x1, 0.0, 0.0);
  for (int k = 0; k < segments; ++k) {
    mesh.triangles.push_back({start, id(0, k + 1), id(0, k)});
    mesh.triangles.push_back({start + 1, id(rings, k), id(rings, k + 1)});
  }
  return mesh;
}

TEST(HeadNeckOffset, ASphereOnACylinderHasTheDifferenceOfTheirRadii) {
  // Head: radius 24 about the origin; neck: radius 15 along +X (the neck axis) from the centre to
  // two head radii out. In the anterior half-plane the head reaches 24 at the equator, the neck
  // stays at 15: offset 9, ratio 9 / 48. Tolerance: the faceting of the two meshes, under 0.05 mm
  // (sphere edges ~ 0.6 mm at radius 24: sagitta < 0.01 mm; 256 cylinder segments: 0.001 mm).
  const double head = 24.0, neck = 15.0;
  TriMesh femur = geometry::make_octasphere(Vec3::Zero(), head, 6);
  const TriMesh cylinder = cylinder_along_x(neck, 0.0, 2.0 * head, 256, 8);
  femur = geometry::merge_meshes({&femur, &cylinder});
  const HeadNeckOffset offset = measure_head_neck_offset(femur, Vec3::Zero(), head, Vec3::UnitX(), Vec3::UnitY());
  ASSERT_TRUE(offset.measured) << offset.reason;
  EXPECT_NEAR(offset.head_radius_mm, head, 0.05);
  EXPECT_NEAR(offset.neck_radius_mm, neck, 0.05);
  EXPECT_NEAR(offset.offset_mm, head - neck, 0.1);
  EXPECT_NEAR(offset.ratio, (head - neck) / (2.0 * head), 0.002);
  // The waist lies where the sphere has come down to the neck: beyond sqrt(R^2 - r^2) along the axis.
  EXPECT_GE(offset.neck_waist_mm, std::sqrt(head * head - neck * neck) - 0.5);
  // An anterior direction along the neck axis is refused, not guessed.
  EXPECT_FALSE(measure_head_neck_offset(femur, Vec3::Zero(), head, Vec3::UnitX(), Vec3::UnitX()).measured);
}

Morphology morphology_of(double ce, double alpha, ClinicalMeasures* out = nullptr) {
  const auto& hip = geometry::test_support::study_hip(ce, alpha, geometry::test_support::kStudyTestEdgeMm);
  const TriMesh& femur = hip.tissue("femur_bone");
  const TriMesh& pelvis = hip.tissue("acetabular_bone");
  FemurLandmarksRequest femur_request;
  femur_request.femur = &femur;
  femur_request.head_centre_hint_mm = hip.hjc_mm;
  FemurLandmarks landmarks = find_femur_landmarks(femur_request);
  landmarks.neck_axis = hip.neck_axis;  // the generator's (known) neck axis
  AnatomicalFrame frame;                // the hip frame: lateral, anterior, superior at the HJC
  frame.origin_mm = hip.hjc_mm;
  AcetabulumRequest acetabulum_request;
  acetabulum_request.pelvis = &pelvis;
  acetabulum_request.head_centre_mm = landmarks.head_centre_mm;
  acetabulum_request.head_radius_mm = landmarks.head_radius_mm;
  acetabulum_request.pelvis_frame = frame;
  const Acetabulum acetabulum = find_acetabulum(acetabulum_request);
  ClinicalMeasuresRequest request;
  request.pelvis = &pelvis;
  request.femur = &femur;
  request.pelvis_frame = frame;
  request.femur_frame = frame;
  request.femur_landmarks = &landmarks;
  request.acetabulum = &acetabulum;
  request.hjc_mm = hip.hjc_mm;
  const ClinicalMeasures measures = measure_clinical(request);
  if (out != nullptr) *out = measures;
  return measures.morphology;
}

TEST(ClinicalMeasures, GeneratedMorphologiesAreClassifiedAsBuilt) {
  // CE and alpha are set by the generator (bone alpha: 42 deg at 40, 85 at 80); the thresholds are
  // Tannast et al. 2007 (LCE 20, 39) and Nötzli et al. 2002 (alpha 50.5).
  ClinicalMeasures normal;
  EXPECT_EQ(morphology_of(30.0, 40.0, &normal), Morphology::kNormal);
  EXPECT_TRUE(normal.findings.empty());
  EXPECT_NEAR(normal.lateral_ce.ce_deg, 30.0, 0.5);
  EXPECT_EQ(morphology_of(10.0, 40.0), Morphology::kDysplasia);
  EXPECT_EQ(morphology_of(40.0, 40.0), Morphology::kPincer);
  EXPECT_EQ(morphology_of(20.0, 80.0), Morphology::kCam);
  EXPECT_EQ(morphology_of(40.0, 80.0), Morphology::kCombined);
  EXPECT_EQ(morphology_of(10.0, 80.0), Morphology::kCamWithDysplasia);
  EXPECT_STREQ(morphology_name(Morphology::kCamWithDysplasia), "cam_with_dysplasia");
}

}  // namespace
}  // namespace hipfai::anatomy
