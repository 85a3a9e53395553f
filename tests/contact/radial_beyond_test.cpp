// The kBeyond crossing rule (the thesis' radial rule read literally): a mobile vertex beyond any
// fixed surface along its ray from O penetrates, measured from the crossing nearest O.
#include "contact/detail/ablation.h"
#include "contact/oracle_radial.h"
#include "contact/radial_segmenting.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <random>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;
using geometry::Vec3;

// A box between z = 10 and z = 20 seen from O below it: a vertex inside it, one that has passed
// through it, one short of it.
TEST(RadialBeyond, VertexPastTheSolidCountsFromTheFirstCrossing) {
  const TriMesh fixed = geometry::make_box(Vec3(-5, -5, 10), Vec3(5, 5, 20), 3);
  TriMesh mobile;
  mobile.vertices = {Vec3(0.1, 0.2, 15.0), Vec3(0.3, -0.1, 30.0), Vec3(0.2, 0.1, 9.0)};
  RadialTableOptions table_options;
  table_options.table_size = 600;
  const auto table = build_radial_table(fixed, Vec3::Zero(), table_options);
  RadialQueryOptions beyond;
  beyond.rule = RadialCrossingRule::kBeyond;
  const auto result = radial_segmenting(table, fixed, mobile, beyond);
  ASSERT_EQ(result.pairs.size(), 2u);
  EXPECT_EQ(result.pairs[0].mobile_vertex, 0);
  EXPECT_NEAR(result.pairs[0].depth_mm, mobile.vertices[0].norm() * (1.0 - 10.0 / 15.0), 1e-9);
  EXPECT_EQ(result.pairs[1].mobile_vertex, 1);
  EXPECT_NEAR(result.pairs[1].depth_mm, mobile.vertices[1].norm() * (1.0 - 10.0 / 30.0), 1e-9);
  // Inside the solid the union rule gives the same depth; past it, nothing.
  RadialQueryOptions union_rule;
  union_rule.rule = RadialCrossingRule::kUnion;
  const auto inside = radial_segmenting(table, fixed, mobile, union_rule);
  ASSERT_EQ(inside.pairs.size(), 1u);
  EXPECT_EQ(inside.pairs[0].mobile_vertex, 0);
  EXPECT_NEAR(inside.pairs[0].depth_mm, result.pairs[0].depth_mm, 1e-12);
}

// The other configuration: the fixed solid beyond v (O at the origin, v below the box) is
// reported with the crossing farthest from v.
TEST(RadialBeyond, FixedInsideMobileCountsToTheFarthestCrossing) {
  const TriMesh fixed = geometry::make_box(Vec3(-5, -5, 10), Vec3(5, 5, 20), 3);
  TriMesh mobile;
  mobile.vertices = {Vec3(0.1, 0.2, 5.0), Vec3(0.1, 0.1, 25.0)};
  const auto table = build_radial_table(fixed, Vec3::Zero(), {});
  RadialQueryOptions beyond;
  beyond.rule = RadialCrossingRule::kBeyond;
  beyond.configuration = RadialConfiguration::kFixedInsideMobile;
  const auto result = radial_segmenting(table, fixed, mobile, beyond);
  ASSERT_EQ(result.pairs.size(), 1u);
  EXPECT_EQ(result.pairs[0].mobile_vertex, 0);
  EXPECT_NEAR(result.pairs[0].depth_mm, mobile.vertices[0].norm() * (20.0 / 5.0 - 1.0), 1e-9);
}

// Random overlapping solids (two shells and a box), random centres: the table query equals the
// brute-force oracle in both configurations, culled and unculled.
TEST(RadialBeyond, MatchesOracleOnOverlappingSolids) {
  std::mt19937 random(23);
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  for (int trial = 0; trial < 6; ++trial) {
    auto inner = geometry::make_octasphere(Vec3(jitter(random), jitter(random), 0), 10.0, 3);
    for (auto& t : inner.triangles) std::swap(t[1], t[2]);
    const auto outer = geometry::make_octasphere(Vec3(0, jitter(random), 0), 12.0, 3);
    const auto block = geometry::make_box(Vec3(-4, -4, 9 + jitter(random)), Vec3(4, 4, 16), 4);
    const TriMesh fixed = geometry::merge_meshes({&inner, &outer, &block});
    auto mobile = geometry::make_octasphere(Vec3(jitter(random), 0, jitter(random)), 11.5, 4);
    for (auto& p : mobile.vertices) p *= 1.0 + 0.4 * jitter(random);
    const Vec3 centre(jitter(random), jitter(random), jitter(random));
    RadialTableOptions table_options;
    table_options.table_size = 3000;
    const auto table = build_radial_table(fixed, centre, table_options);
    for (const auto configuration : {RadialConfiguration::kMobileInsideFixed, RadialConfiguration::kFixedInsideMobile}) {
      const auto oracle = oracle_radial(fixed, mobile, centre, configuration, RadialCrossingRule::kBeyond);
      EXPECT_GT(oracle.pairs.size(), 0u) << "trial " << trial;
      for (const bool cull : {true, false}) {
        RadialQueryOptions options;
        options.rule = RadialCrossingRule::kBeyond;
        options.configuration = configuration;
        detail::RadialAblation ablation;
        ablation.cull = cull;
        const auto fast = detail::radial_segmenting(table, fixed, mobile, options, ablation);
        ASSERT_EQ(fast.pairs.size(), oracle.pairs.size()) << "trial " << trial << " cull " << cull;
        for (std::size_t i = 0; i < fast.pairs.size(); ++i) {
          EXPECT_EQ(fast.pairs[i].mobile_vertex, oracle.pairs[i].mobile_vertex);
          EXPECT_EQ(fast.pairs[i].fixed_triangle, oracle.pairs[i].fixed_triangle);
          EXPECT_NEAR(fast.pairs[i].depth_mm, oracle.pairs[i].depth_mm, 1e-9);
        }
      }
    }
  }
}

}  // namespace
}  // namespace hipfai::contact
