// The kUnion crossing rule: touching and overlapping fixed solids read as one solid.
#include "contact/oracle_radial.h"
#include "contact/radial_segmenting.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <random>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;
using geometry::Vec3;

// Two boxes stacked along +z, sharing the face z = 12 (like cartilage on bone). A vertex at
// z = 13 seen from O below has passed through the lower box into the upper one.
TEST(RadialUnion, VertexThroughTouchingLayersIsMeasuredFromTheFirstEntry) {
  const TriMesh lower = geometry::make_box(Vec3(-5, -5, 10), Vec3(5, 5, 12), 3);
  const TriMesh upper = geometry::make_box(Vec3(-5, -5, 12), Vec3(5, 5, 20), 3);
  const TriMesh fixed = geometry::merge_meshes({&lower, &upper});
  TriMesh mobile;
  mobile.vertices = {Vec3(0.1, 0.2, 13.0), Vec3(0.3, -0.1, 11.0), Vec3(0.2, 0.1, 9.0), Vec3(0.1, 0.1, 21.0)};
  RadialTableOptions table_options;
  table_options.table_size = 600;
  const auto table = build_radial_table(fixed, Vec3::Zero(), table_options);
  RadialQueryOptions options;
  options.rule = RadialCrossingRule::kUnion;
  const auto result = radial_segmenting(table, fixed, mobile, options);
  ASSERT_EQ(result.pairs.size(), 2u);
  // Depth along the ray to z = 10, the entry into the union: |v| (1 - 10 / z_v).
  EXPECT_EQ(result.pairs[0].mobile_vertex, 0);
  EXPECT_NEAR(result.pairs[0].depth_mm, mobile.vertices[0].norm() * (1.0 - 10.0 / 13.0), 1e-9);
  EXPECT_EQ(result.pairs[1].mobile_vertex, 1);
  EXPECT_NEAR(result.pairs[1].depth_mm, mobile.vertices[1].norm() * (1.0 - 10.0 / 11.0), 1e-9);
  // The adjacent rule stops at the shared face z = 12, where the lower box's exit (lowest index
  // wins the tie) says "outside": vertex 0 is not reported at all.
  const auto adjacent = radial_segmenting(table, fixed, mobile, RadialQueryOptions{});
  ASSERT_FALSE(adjacent.pairs.empty());
  EXPECT_NE(adjacent.pairs[0].mobile_vertex, 0);
}

// Random overlapping solids (two shells and a box), random centres: fast path equals the oracle,
// in both configurations.
TEST(RadialUnion, MatchesOracleOnOverlappingSolids) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  for (int trial = 0; trial < 6; ++trial) {
    auto inner = geometry::make_octasphere(Vec3(jitter(random), jitter(random), 0), 10.0, 3);
    for (auto& t : inner.triangles) std::swap(t[1], t[2]);  // the socket's articular surface
    const auto outer = geometry::make_octasphere(Vec3(0, jitter(random), 0), 12.0, 3);
    const auto block = geometry::make_box(Vec3(-4, -4, 9 + jitter(random)), Vec3(4, 4, 16), 4);
    const TriMesh fixed = geometry::merge_meshes({&inner, &outer, &block});
    auto mobile = geometry::make_octasphere(Vec3(jitter(random), 0, jitter(random)), 11.5, 4);
    for (auto& p : mobile.vertices) p *= 1.0 + 0.15 * jitter(random);
    const Vec3 centre(jitter(random), jitter(random), jitter(random));
    RadialTableOptions table_options;
    table_options.table_size = 3000;
    const auto table = build_radial_table(fixed, centre, table_options);
    for (const auto configuration : {RadialConfiguration::kMobileInsideFixed, RadialConfiguration::kFixedInsideMobile}) {
      RadialQueryOptions options;
      options.rule = RadialCrossingRule::kUnion;
      options.configuration = configuration;
      const auto fast = radial_segmenting(table, fixed, mobile, options);
      const auto oracle = oracle_radial(fixed, mobile, centre, configuration, RadialCrossingRule::kUnion);
      ASSERT_EQ(fast.pairs.size(), oracle.pairs.size()) << "trial " << trial;
      for (std::size_t i = 0; i < fast.pairs.size(); ++i) {
        EXPECT_EQ(fast.pairs[i].mobile_vertex, oracle.pairs[i].mobile_vertex);
        EXPECT_EQ(fast.pairs[i].fixed_triangle, oracle.pairs[i].fixed_triangle);
        EXPECT_NEAR(fast.pairs[i].depth_mm, oracle.pairs[i].depth_mm, 1e-9);
      }
      if (configuration == RadialConfiguration::kMobileInsideFixed) {
        EXPECT_GT(fast.pairs.size(), 0u);
      }
    }
  }
}

// For well-separated solids the union is each solid on its own: both rules agree.
TEST(RadialUnion, EqualsAdjacentRuleForSeparatedSolids) {
  auto inner = geometry::make_octasphere(Vec3::Zero(), 10.0, 4);
  for (auto& t : inner.triangles) std::swap(t[1], t[2]);
  const auto outer = geometry::make_octasphere(Vec3::Zero(), 12.0, 4);
  const TriMesh shell = geometry::merge_meshes({&inner, &outer});
  auto mobile = geometry::make_octasphere(Vec3(0.7, 0.2, -0.3), 10.5, 4);
  const auto table = build_radial_table(shell, Vec3::Zero(), {});
  RadialQueryOptions adjacent, union_rule;
  union_rule.rule = RadialCrossingRule::kUnion;
  const auto a = radial_segmenting(table, shell, mobile, adjacent);
  const auto b = radial_segmenting(table, shell, mobile, union_rule);
  ASSERT_GT(a.pairs.size(), 0u);
  ASSERT_EQ(a.pairs.size(), b.pairs.size());
  for (std::size_t i = 0; i < a.pairs.size(); ++i) EXPECT_NEAR(a.pairs[i].depth_mm, b.pairs[i].depth_mm, 1e-12);
}

}  // namespace
}  // namespace hipfai::contact
