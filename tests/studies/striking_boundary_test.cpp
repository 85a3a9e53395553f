// The curvilinear depth sampled also on the border of the striking region (the sphere R + tol,
// PenetrationOptions::sample_striking_boundary) adds samples and changes nothing else: the same
// per-vertex depths, a step maximum never below the vertices', and a first contact never later.
#include "geometry/hip_generator.h"
#include "studies/hip_sensitivity.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/motion.h"
#include "studies/pipeline/penetration_run.h"

#include <gtest/gtest.h>

namespace hipfai::studies {
namespace {

TEST(StrikingBoundary, BorderSamplesAddToTheVerticesAndMoveFirstContactOnlyEarlier) {
  geometry::HipParameters p;
  p.ce_deg = 40.0;  // combined cam-pincer: the cam's flank runs along under the labrum's face
  p.alpha_deg = 80.0;
  p.edge_mm = 3.0;
  const geometry::HipModel model = geometry::generate_hip(p).model;
  const LoadedHip hip = loaded_hip_from_model(model, "border");
  const Motion motion = standing_to_sitting(10);
  PenetrationOptions vertices;
  vertices.radial = false;
  PenetrationOptions border = vertices;
  border.sample_striking_boundary = true;
  StageLog log;
  const PenetrationRun a = compute_penetration(hip, motion, vertices, log);
  const PenetrationRun b = compute_penetration(hip, motion, border, log);

  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (std::size_t k = 0; k < a.steps.size(); ++k) {
    EXPECT_GE(b.steps[k].curvilinear_mm, a.steps[k].curvilinear_mm) << "step " << k;
    EXPECT_GE(b.steps[k].curvilinear_swap_mm, a.steps[k].curvilinear_swap_mm) << "step " << k;
    // Penetrating vertices are counted over the mesh's own vertices only.
    EXPECT_EQ(b.steps[k].curvilinear_vertices, a.steps[k].curvilinear_vertices) << "step " << k;
  }
  // The per-vertex fields are the mesh's vertices' own answers, unchanged.
  for (const char* key : {"femur_bone/curvilinear_depth_mm", "labrum/curvilinear_depth_mm"}) {
    ASSERT_TRUE(a.max_fields.count(key) && b.max_fields.count(key)) << key;
    EXPECT_EQ(a.max_fields.at(key), b.max_fields.at(key)) << key;
  }
  // The border samples are used: on this hip the border is where the depth is largest.
  EXPECT_GT(b.max_curvilinear_mm(), a.max_curvilinear_mm() + 0.1);

  const Eigen::Vector3d axis = (hip.frame * motion.steps.front().axis).normalized();
  const double striking = p.articular_radius_mm + a.contact_tolerance_mm;
  const double first_vertices = first_striking_contact_deg(model.tissue("femur_bone"), model.tissue("labrum"),
                                                           model.hjc_mm, axis, striking, 2, false);
  const double first_border = first_striking_contact_deg(model.tissue("femur_bone"), model.tissue("labrum"),
                                                         model.hjc_mm, axis, striking, 2, true);
  EXPECT_LE(first_border, first_vertices);
  EXPECT_GT(first_border, 0.5);  // still apart in the neutral pose
}

}  // namespace
}  // namespace hipfai::studies
