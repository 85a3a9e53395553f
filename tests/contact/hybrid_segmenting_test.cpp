#include "contact/hybrid_segmenting.h"

#include "contact/oracle_cylindrical.h"
#include "contact/oracle_radial.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;
using geometry::Vec3;

// A sphere (mobile, radius 10) rotating inside a box-shaped socket whose top is pushed down into
// it: the sphere's vertices near the top penetrate. A threshold between the sphere's inner and
// outer vertices makes both methods answer for some of them.
struct HybridScene {
  TriMesh fixed;
  TriMesh mobile;
  Vec3 centre{0.3, -0.2, 0.1};
  Vec3 axis = Vec3(0.2, 1.0, 0.1).normalized();
};

HybridScene make_scene() {
  HybridScene scene;
  // A closed torus-like fixed shell is awkward; a thick box slab cutting the sphere's top cap
  // is a closed fixed solid both methods handle: mobile vertices inside the slab penetrate.
  scene.fixed = geometry::make_box(Vec3(-15, -15, 7), Vec3(15, 15, 20), 12);
  scene.mobile = geometry::make_octasphere(scene.centre, 10.0, 4);
  // Perturb radii so vertices spread over distances 9..11 from the centre.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> radius(9.0, 11.0);
  for (Vec3& p : scene.mobile.vertices) p = scene.centre + (p - scene.centre).normalized() * radius(random);
  return scene;
}

// Independent reference: each band's vertices answered by that method's exhaustive oracle.
TEST(HybridSegmenting, EachBandMatchesItsMethodsOracle) {
  const HybridScene scene = make_scene();
  const auto cylindrical_table = CylindricalTable::build(scene.fixed, scene.centre, scene.axis);
  RadialTableOptions radial_options;
  radial_options.table_size = 2000;
  const auto radial_table = build_radial_table(scene.fixed, scene.centre, radial_options);
  HybridOptions options;
  options.thresholds_mm = {10.0};
  options.radial.configuration = RadialConfiguration::kMobileInsideFixed;
  const auto hybrid = hybrid_segmenting(cylindrical_table, radial_table, scene.fixed, scene.mobile, options);
  ASSERT_EQ(hybrid.result.status, QueryStatus::kOk) << hybrid.result.message;

  const auto radial = oracle_radial(scene.fixed, scene.mobile, scene.centre,
                                    RadialConfiguration::kMobileInsideFixed);
  const auto cylindrical = oracle_cylindrical(scene.fixed, scene.mobile, scene.centre, scene.axis);
  std::vector<PenetrationPair> expected;
  for (const auto& pair : radial.pairs) {
    if ((scene.mobile.vertices[pair.mobile_vertex] - scene.centre).norm() < 10.0) expected.push_back(pair);
  }
  for (const auto& pair : cylindrical.pairs) {
    if ((scene.mobile.vertices[pair.mobile_vertex] - scene.centre).norm() >= 10.0) expected.push_back(pair);
  }
  sort_by_mobile_vertex(expected);
  ASSERT_EQ(hybrid.result.pairs.size(), expected.size());
  ASSERT_GT(expected.size(), 10u);  // the scene must exercise both bands
  int radial_pairs = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(hybrid.result.pairs[i].mobile_vertex, expected[i].mobile_vertex);
    EXPECT_EQ(hybrid.result.pairs[i].fixed_triangle, expected[i].fixed_triangle);
    // Both paths evaluate the same closed-form depth; 1e-9 mm allows only rounding differences.
    EXPECT_NEAR(hybrid.result.pairs[i].depth_mm, expected[i].depth_mm, 1e-9);
    radial_pairs += std::isnan(hybrid.result.pairs[i].angle_deg) ? 1 : 0;
  }
  EXPECT_GT(radial_pairs, 0);
  EXPECT_LT(radial_pairs, static_cast<int>(expected.size()));
}

// Both methods must agree on WHICH vertices penetrate a closed solid (only the depths differ,
// thesis Fig. 41): with every band radial, or every band cylindrical, the vertex sets are equal.
TEST(HybridSegmenting, BothMethodsFindTheSameVertices) {
  const HybridScene scene = make_scene();
  const auto cylindrical_table = CylindricalTable::build(scene.fixed, scene.centre, scene.axis);
  RadialTableOptions radial_options;
  radial_options.table_size = 2000;
  const auto radial_table = build_radial_table(scene.fixed, scene.centre, radial_options);
  HybridOptions all_radial, all_cylindrical;
  all_radial.band_methods = {HybridMethod::kRadial};
  all_cylindrical.band_methods = {HybridMethod::kCylindrical};
  const auto a = hybrid_segmenting(cylindrical_table, radial_table, scene.fixed, scene.mobile, all_radial);
  const auto b = hybrid_segmenting(cylindrical_table, radial_table, scene.fixed, scene.mobile, all_cylindrical);
  ASSERT_EQ(a.result.pairs.size(), b.result.pairs.size());
  for (std::size_t i = 0; i < a.result.pairs.size(); ++i) {
    EXPECT_EQ(a.result.pairs[i].mobile_vertex, b.result.pairs[i].mobile_vertex);
  }
}

TEST(HybridSegmenting, RejectsBadThresholds) {
  const HybridScene scene = make_scene();
  const auto cylindrical_table = CylindricalTable::build(scene.fixed, scene.centre, scene.axis);
  const auto radial_table = build_radial_table(scene.fixed, scene.centre, {});
  HybridOptions options;
  options.thresholds_mm = {5.0, 3.0};
  EXPECT_EQ(hybrid_segmenting(cylindrical_table, radial_table, scene.fixed, scene.mobile, options).result.status,
            QueryStatus::kInvalidInput);
  options.thresholds_mm = {5.0};
  options.band_methods = {HybridMethod::kRadial};
  EXPECT_EQ(hybrid_segmenting(cylindrical_table, radial_table, scene.fixed, scene.mobile, options).result.status,
            QueryStatus::kInvalidInput);
}

}  // namespace
}  // namespace hipfai::contact
