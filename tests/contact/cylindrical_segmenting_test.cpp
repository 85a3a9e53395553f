// Property tests of cylindrical segmenting against the exhaustive oracle on random scenes, plus
// the pre-processing split, deformation updates, threads and invalid input.
#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "contact/oracle_cylindrical.h"
#include "core/error.h"
#include "geometry/primitive_meshes.h"
#include "random_shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <string>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;
using test_shapes::random_shape;
using test_shapes::random_unit;

// Same vertex set (exact), depths equal to 1e-9 mm: both sides evaluate the same closed form on
// coordinates that differ only by the rounding of the pose (~1e-13 mm), so 1e-9 is generous while
// any wrong triangle or missed crossing changes the depth by far more.
void expect_same_segmenting(const PenetrationResult& got, const PenetrationResult& want, const std::string& what) {
  ASSERT_NE(got.status, QueryStatus::kInvalidInput) << what << ": " << got.message;
  ASSERT_EQ(want.status, QueryStatus::kOk) << what;
  ASSERT_EQ(got.pairs.size(), want.pairs.size()) << what;
  for (std::size_t i = 0; i < got.pairs.size(); ++i) {
    ASSERT_EQ(got.pairs[i].mobile_vertex, want.pairs[i].mobile_vertex) << what;
    EXPECT_NEAR(got.pairs[i].depth_mm, want.pairs[i].depth_mm, 1e-9) << what;
    EXPECT_TRUE(std::isfinite(got.pairs[i].angle_deg)) << what;
  }
}

TEST(CylindricalSegmenting, EqualsOracleOnRandomScenes) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t total_penetrating = 0;
  for (int trial = 0; trial < 36; ++trial) {
    const TriMesh fixed = random_shape(rng, trial % 3);
    const TriMesh mobile = random_shape(rng, (trial / 3) % 3);
    const Vec3 centre(20 * u(rng) - 10, 20 * u(rng) - 10, 20 * u(rng) - 10);
    const Vec3 axis = random_unit(rng) * (0.1 + 5 * u(rng));  // any length
    const double angle_deg = 360 * u(rng) - 180;
    TriMesh posed = mobile;
    geometry::rotate_about_axis(posed, centre, axis.normalized(), angle_deg * std::numbers::pi / 180);

    const PenetrationResult oracle = oracle_cylindrical(fixed, posed, centre, axis);
    total_penetrating += oracle.pairs.size();
    const std::string what = "trial " + std::to_string(trial);

    CylindricalTableOptions table_options;
    table_options.resolution_r_mm = geometry::mean_edge_length(fixed) * (0.3 + 3 * u(rng));
    table_options.resolution_z_mm = geometry::mean_edge_length(fixed) * (0.3 + 3 * u(rng));
    expect_same_segmenting(cylindrical_segmenting(fixed, posed, centre, axis, {}, table_options), oracle,
                what + " one-shot");
    const CylindricalTable full = CylindricalTable::build(fixed, centre, axis, table_options);
    expect_same_segmenting(cylindrical_segmenting(full, posed), oracle, what + " full table");
    // Pre-processing split: table restricted to the mobile mesh at pose 0, queried at the angle.
    const CylindricalTable restricted =
        CylindricalTable::build(fixed, centre, axis, table_options, &mobile);
    const CylindricalPoseCache cache(restricted, mobile);
    expect_same_segmenting(cache.query(angle_deg), oracle, what + " pose cache");
    expect_same_segmenting(cache.query(angle_deg + 720.0), oracle, what + " pose cache +2 turns");
  }
  EXPECT_GT(total_penetrating, 500u);  // the scenes really collide
}

TEST(CylindricalSegmenting, PoseCacheSweepEqualsOracle) {
  std::mt19937 rng(5);
  const TriMesh fixed = random_shape(rng, 1);
  const TriMesh mobile = random_shape(rng, 0);
  const Vec3 centre(1, 2, 3), axis = random_unit(rng);
  const CylindricalTable table = CylindricalTable::build(fixed, centre, axis, {}, &mobile);
  const CylindricalPoseCache cache(table, mobile);
  for (double angle = -180.0; angle < 180.0; angle += 22.5) {
    TriMesh posed = mobile;
    geometry::rotate_about_axis(posed, centre, axis, angle * std::numbers::pi / 180);
    expect_same_segmenting(cache.query(angle), oracle_cylindrical(fixed, posed, centre, axis),
                "angle " + std::to_string(angle));
  }
}

TEST(CylindricalSegmenting, ThreadCountDoesNotChangeResults) {
  std::mt19937 rng(11);
  const TriMesh fixed = random_shape(rng, 0);
  const TriMesh mobile = random_shape(rng, 2);
  const Vec3 centre(0, 0, 0), axis = random_unit(rng);
  const CylindricalTable table = CylindricalTable::build(fixed, centre, axis);
  CylindricalQueryOptions one, three;
  one.num_threads = 1;
  three.num_threads = 3;
  const PenetrationResult a = cylindrical_segmenting(table, mobile, one);
  const PenetrationResult b = cylindrical_segmenting(table, mobile, three);
  ASSERT_FALSE(a.pairs.empty());
  ASSERT_EQ(a.pairs.size(), b.pairs.size());
  for (std::size_t i = 0; i < a.pairs.size(); ++i) {
    EXPECT_EQ(a.pairs[i].mobile_vertex, b.pairs[i].mobile_vertex);
    EXPECT_EQ(a.pairs[i].fixed_triangle, b.pairs[i].fixed_triangle);
    EXPECT_EQ(a.pairs[i].depth_mm, b.pairs[i].depth_mm);
  }
  const CylindricalPoseCache cache1(table, mobile, one), cache3(table, mobile, three);
  EXPECT_EQ(cache1.num_crossings(), cache3.num_crossings());
  EXPECT_EQ(cache1.query(10.0).pairs.size(), cache3.query(10.0).pairs.size());
}

// Moves a few vertices; returns the ids of every triangle touching a moved vertex.
std::vector<std::int32_t> deform(TriMesh& mesh, std::mt19937& rng, double displacement_mm) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::set<std::int32_t> moved;
  for (std::size_t v = 0; v < mesh.vertices.size(); v += 7) {
    mesh.vertices[v] += displacement_mm * Vec3(u(rng), u(rng), u(rng)) / std::sqrt(3.0);
    moved.insert(static_cast<std::int32_t>(v));
  }
  std::vector<std::int32_t> changed;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (std::int32_t v : mesh.triangles[t]) {
      if (moved.count(v)) {
        changed.push_back(static_cast<std::int32_t>(t));
        break;
      }
    }
  }
  return changed;
}

TEST(CylindricalSegmenting, UpdatedTableEqualsRebuild) {
  for (double displacement : {0.3, 4.0, 40.0}) {  // small, several cells, beyond the grid
    std::mt19937 rng(17);
    TriMesh fixed = random_shape(rng, 0);
    const TriMesh mobile = random_shape(rng, 1);
    const Vec3 centre(2, -1, 0), axis = random_unit(rng);
    CylindricalTable table = CylindricalTable::build(fixed, centre, axis);
    const std::vector<std::int32_t> changed = deform(fixed, rng, displacement);
    update_triangles(table, fixed, changed);
    const CylindricalTable rebuilt = CylindricalTable::build(fixed, centre, axis);
    const PenetrationResult oracle = oracle_cylindrical(fixed, mobile, centre, axis);
    const std::string what = "displacement " + std::to_string(displacement);
    expect_same_segmenting(cylindrical_segmenting(table, mobile), oracle, what + " updated");
    expect_same_segmenting(cylindrical_segmenting(rebuilt, mobile), oracle, what + " rebuilt");
    EXPECT_FALSE(oracle.pairs.empty()) << what;
    if (displacement > 10.0) {
      EXPECT_GT(table.num_overflow_triangles(), 0u);
    }
  }
}

TEST(CylindricalSegmenting, NeighbourCellsCoverSmallDeformations) {
  std::mt19937 rng(23);
  TriMesh fixed = random_shape(rng, 0);
  const TriMesh mobile = random_shape(rng, 0);
  const Vec3 centre(0, 0, 1), axis = random_unit(rng);
  CylindricalTableOptions options;
  options.resolution_r_mm = options.resolution_z_mm = 0.5;
  CylindricalTable table = CylindricalTable::build(fixed, centre, axis, options);
  const double displacement = 1.4;  // <= 3 cells of 0.5 mm
  const std::vector<std::int32_t> changed = deform(fixed, rng, displacement);
  update_triangles(table, fixed, changed, TableUpdate::kGeometryOnly);
  const PenetrationResult oracle = oracle_cylindrical(fixed, mobile, centre, axis);
  ASSERT_FALSE(oracle.pairs.empty());
  table.set_neighbour_cells(3);
  expect_same_segmenting(cylindrical_segmenting(table, mobile), oracle, "k = 3");
  const CylindricalPoseCache cache(table, mobile);
  expect_same_segmenting(cache.query(0.0), oracle, "k = 3 pose cache");
  // Without the neighbours the stale bins miss crossings somewhere (this is why k is needed).
  table.set_neighbour_cells(0);
  const PenetrationResult stale = cylindrical_segmenting(table, mobile);
  bool differs = stale.pairs.size() != oracle.pairs.size();
  for (std::size_t i = 0; !differs && i < stale.pairs.size(); ++i) {
    differs = stale.pairs[i].mobile_vertex != oracle.pairs[i].mobile_vertex ||
              std::abs(stale.pairs[i].depth_mm - oracle.pairs[i].depth_mm) > 1e-9;
  }
  EXPECT_TRUE(differs);
}

TEST(CylindricalSegmenting, UpdateRejectsChangedTopology) {
  const TriMesh fixed = geometry::make_box(Vec3(-1, -1, -1), Vec3(1, 1, 1), 2);
  CylindricalTable table = CylindricalTable::build(fixed, Vec3::Zero(), Vec3::UnitZ());
  TriMesh smaller = fixed;
  smaller.triangles.pop_back();
  const std::vector<std::int32_t> ids = {0};
  EXPECT_THROW(update_triangles(table, smaller, ids), Error);
  const std::vector<std::int32_t> bad = {100000};
  EXPECT_THROW(update_triangles(table, fixed, bad), Error);
}

TEST(CylindricalSegmenting, InvalidAndDisjointInput) {
  const TriMesh fixed = geometry::make_box(Vec3(-1, -1, -1), Vec3(1, 1, 1), 2);
  TriMesh mobile = geometry::make_box(Vec3(0, 0, 0), Vec3(2, 2, 2), 2);
  EXPECT_EQ(cylindrical_segmenting(fixed, mobile, Vec3::Zero(), Vec3::Zero()).status,
            QueryStatus::kInvalidInput);
  EXPECT_EQ(cylindrical_segmenting(fixed, mobile, Vec3::Zero(), Vec3(0, 0, NAN)).status,
            QueryStatus::kInvalidInput);
  EXPECT_EQ(cylindrical_segmenting(TriMesh{}, mobile, Vec3::Zero(), Vec3::UnitZ()).status,
            QueryStatus::kInvalidInput);
  TriMesh broken = mobile;
  broken.vertices[0].x() = NAN;
  EXPECT_EQ(cylindrical_segmenting(fixed, broken, Vec3::Zero(), Vec3::UnitZ()).status,
            QueryStatus::kInvalidInput);
  // Far along the axis: the z ranges do not overlap.
  TriMesh far = geometry::make_box(Vec3(0, 0, 50), Vec3(2, 2, 52), 2);
  EXPECT_EQ(cylindrical_segmenting(fixed, far, Vec3::Zero(), Vec3::UnitZ()).status,
            QueryStatus::kNoOverlap);
  const CylindricalTable table = CylindricalTable::build(fixed, Vec3::Zero(), Vec3::UnitZ(), {}, &far);
  EXPECT_EQ(CylindricalPoseCache(table, far).query(30.0).status, QueryStatus::kNoOverlap);
  EXPECT_EQ(CylindricalPoseCache(table, far).query(NAN).status, QueryStatus::kInvalidInput);
  // Deforming the fixed mesh into reach of the mobile one revives the empty table (overflow).
  CylindricalTable revived = table;
  TriMesh moved = fixed;
  for (Vec3& p : moved.vertices) p += Vec3(0.3, 0.2, 50.0);
  std::vector<std::int32_t> all(moved.triangles.size());
  for (std::size_t t = 0; t < all.size(); ++t) all[t] = static_cast<std::int32_t>(t);
  update_triangles(revived, moved, all);
  const PenetrationResult oracle = oracle_cylindrical(moved, far, Vec3::Zero(), Vec3::UnitZ());
  ASSERT_FALSE(oracle.pairs.empty());
  expect_same_segmenting(cylindrical_segmenting(revived, far), oracle, "revived");
}

}  // namespace
}  // namespace hipfai::contact
