// The femur's neutral (studies/pipeline/hip_source.h, put_femur_at_neutral): at the ISB neutral the femur
// turns by the anatomic-mechanical angle about the adduction axis through the HJC, knee medially;
// the pelvis side and the default neutral stay as they are.
#include "core/literature.h"
#include "studies/pipeline/hip_source.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

namespace hipfai::studies {
namespace {

// A right hip whose frame is turned and moved, with a femur of three points: the HJC's
// neighbourhood, a lateral shaft point and a knee centre below and lateral of the HJC.
LoadedHip sample_hip() {
  LoadedHip hip;
  hip.hjc_mm = geometry::Vec3(10.0, -5.0, 30.0);
  hip.frame = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  auto in_model = [&](double x, double y, double z) { return geometry::Vec3(hip.hjc_mm + hip.frame * geometry::Vec3(x, y, z)); };
  geometry::TriMesh femur;
  femur.vertices = {in_model(0, 0, 25), in_model(40, 0, -60), in_model(40, 0, -400)};
  femur.triangles = {{0, 1, 2}};
  geometry::TriMesh labrum;
  labrum.vertices = {in_model(25, 0, 10), in_model(0, 25, 10), in_model(-25, 0, 10)};
  labrum.triangles = {{0, 1, 2}};
  hip.tissues = {{"femur_bone", femur}, {"femoral_cartilage", femur}, {"labrum", labrum}};
  hip.mesh_hash = {{"femur_bone", "f"}, {"femoral_cartilage", "c"}, {"labrum", "l"}};
  return hip;
}

// A point of the model in the hip frame.
geometry::Vec3 in_frame(const LoadedHip& hip, const geometry::Vec3& p) { return hip.frame.transpose() * (p - hip.hjc_mm); }

TEST(FemoralNeutral, TheShaftNeutralChangesNothing) {
  const LoadedHip before = sample_hip();
  LoadedHip hip = sample_hip();
  put_femur_at_neutral(hip, geometry::FemoralNeutral::kShaftAxis);
  for (const auto& [name, mesh] : before.tissues) EXPECT_EQ(hip.tissues.at(name).vertices, mesh.vertices) << name;
  EXPECT_EQ(hip.mesh_hash, before.mesh_hash);
}

TEST(FemoralNeutral, TheMechanicalNeutralAdductsTheFemurAboutTheHjc) {
  const LoadedHip before = sample_hip();
  LoadedHip hip = sample_hip();
  put_femur_at_neutral(hip, geometry::FemoralNeutral::kMechanicalAxis);
  const double angle = literature::kAnatomicMechanicalAngleDeg * geometry::kDegToRad;
  for (const char* tissue : {"femur_bone", "femoral_cartilage"}) {
    const auto& moved = hip.tissues.at(tissue).vertices;
    const auto& original = before.tissues.at(tissue).vertices;
    for (std::size_t v = 0; v < moved.size(); ++v) {
      const geometry::Vec3 a = in_frame(hip, original[v]), b = in_frame(hip, moved[v]);
      EXPECT_NEAR(b.norm(), a.norm(), 1e-9);  // about the HJC
      EXPECT_NEAR(b.y(), a.y(), 1e-9);        // about the adduction (Y) axis
      const double turned = std::remainder(std::atan2(a.x(), -a.z()) - std::atan2(b.x(), -b.z()), 2.0 * M_PI);
      EXPECT_NEAR(turned, angle, 1e-12) << tissue << " vertex " << v;
    }
    // The knee centre, lateral of the HJC with the shaft vertical, moves medially (towards -X).
    EXPECT_LT(in_frame(hip, moved[2]).x(), in_frame(hip, original[2]).x() - 30.0);
    EXPECT_NE(hip.mesh_hash.at(tissue), before.mesh_hash.at(tissue));
  }
  EXPECT_EQ(hip.tissues.at("labrum").vertices, before.tissues.at("labrum").vertices);
  EXPECT_EQ(hip.mesh_hash.at("labrum"), "l");
}

}  // namespace
}  // namespace hipfai::studies
