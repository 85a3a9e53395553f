// Property test on the generated hips: the fast cylindrical and radial queries equal their exhaustive
// oracles on the FAI study's tissue pairs, at several poses of standing to sitting.
#include "contact/cylindrical_segmenting.h"
#include "contact/oracle_cylindrical.h"
#include "contact/oracle_radial.h"
#include "contact/radial_segmenting.h"
#include "geometry/hip_generator.h"
#include "studies/pipeline/motion.h"

#include <gtest/gtest.h>

namespace hipfai::studies {
namespace {

void expect_same(const contact::PenetrationResult& fast, const contact::PenetrationResult& oracle) {
  ASSERT_EQ(fast.pairs.size(), oracle.pairs.size());
  for (std::size_t i = 0; i < fast.pairs.size(); ++i) {
    EXPECT_EQ(fast.pairs[i].mobile_vertex, oracle.pairs[i].mobile_vertex);
    // Both evaluate the same closed-form depth; only rounding may differ.
    EXPECT_NEAR(fast.pairs[i].depth_mm, oracle.pairs[i].depth_mm, 1e-9);
  }
}

TEST(GeneratedHipOracle, FastQueriesEqualOraclesOnCombinedHip) {
  geometry::HipParameters parameters;
  parameters.ce_deg = 40;
  parameters.alpha_deg = 80;
  parameters.edge_mm = 3.0;
  const auto hip = geometry::generate_hip(parameters).model;
  const auto& femur = hip.tissue("femur_bone");
  const auto& labrum = hip.tissue("labrum");
  const auto& cartilage = hip.tissue("femoral_cartilage");
  const auto& acetabular = hip.tissue("acetabular_cartilage");
  const auto socket = geometry::merge_meshes({&acetabular, &labrum});
  const auto whole_femur = geometry::merge_meshes({&femur, &cartilage});
  const Motion motion = standing_to_sitting(6);
  const auto centre = hip.hjc_mm;
  int penetrating = 0;
  for (const std::size_t k : {1u, 3u, 5u}) {
    const auto& step = motion.steps[k];
    geometry::TriMesh posed_femur = femur, posed_whole = whole_femur;
    geometry::rotate_about_axis(posed_femur, centre, step.axis, step.angle_deg * geometry::kDegToRad);
    geometry::rotate_about_axis(posed_whole, centre, step.axis, step.angle_deg * geometry::kDegToRad);
    // Curvilinear: femur bone (posed) against the labrum about the step's axis.
    const auto fast_c = contact::cylindrical_segmenting(labrum, posed_femur, centre, step.axis);
    const auto oracle_c = contact::oracle_cylindrical(labrum, posed_femur, centre, step.axis);
    expect_same(fast_c, oracle_c);
    // Radial: whole femur (posed) inside the acetabular soft tissue, every mapping, both rules.
    for (const auto mapping : {contact::RadialMapping::kSpherical, contact::RadialMapping::kCartesian,
                               contact::RadialMapping::kCube}) {
      contact::RadialTableOptions table_options;
      table_options.mapping = mapping;
      table_options.table_size = 4000;
      const auto table = contact::build_radial_table(socket, centre, table_options);
      for (const auto rule : {contact::RadialCrossingRule::kAdjacent, contact::RadialCrossingRule::kUnion}) {
        contact::RadialQueryOptions options;
        options.rule = rule;
        expect_same(contact::radial_segmenting(table, socket, posed_whole, options),
                    contact::oracle_radial(socket, posed_whole, centre,
                                           contact::RadialConfiguration::kMobileInsideFixed, rule));
      }
    }
    penetrating += static_cast<int>(oracle_c.pairs.size());
  }
  EXPECT_GT(penetrating, 0);  // the combined hip must exercise the penetrating branch
}

}  // namespace
}  // namespace hipfai::studies
