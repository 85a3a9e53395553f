// Vertex clusters (contact/vertex_clusters.h) and the ring table's ball test that passes over a
// whole cluster (CylindricalTable::ball_may_touch). Every vertex is in exactly one cluster and
// inside its sphere; a ball that holds a point which passes the per-vertex filters is never
// culled, with the point deep inside, on the ball's surface, exactly on a cell border, exactly at
// the distance filter's bounds and in a cell at the grid's edge. The query over clusters reports
// the same pairs as the plain one on every scene of cylindrical_angular_walk_test.cpp.
#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "contact/detail/ablation.h"
#include "contact/vertex_clusters.h"
#include "core/error.h"
#include "geometry/primitive_meshes.h"
#include "random_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;
using test_shapes::random_pose;
using test_shapes::random_shape;
using test_shapes::random_unit;

TEST(VertexClusters, EveryVertexOnceAndInsideItsSphere) {
  std::mt19937 rng(5);
  const TriMesh mesh = random_shape(rng, 0);
  for (const std::size_t size : {1, 3, 32, 1000000}) {
    const VertexClusters clusters = VertexClusters::build(mesh, size);
    ASSERT_EQ(clusters.num_vertices(), mesh.vertices.size());
    std::vector<int> seen(mesh.vertices.size(), 0);
    std::uint32_t next = 0;
    for (const VertexCluster& cluster : clusters.clusters()) {
      EXPECT_EQ(cluster.first, next);
      EXPECT_GT(cluster.last, cluster.first);
      EXPECT_LE(cluster.last - cluster.first, size);
      next = cluster.last;
      for (std::uint32_t i = cluster.first; i < cluster.last; ++i) {
        const auto v = static_cast<std::size_t>(clusters.mesh_index(i));
        ASSERT_LT(v, mesh.vertices.size());
        ++seen[v];
        EXPECT_EQ(clusters.vertex(i), mesh.vertices[v]);
        EXPECT_LE((clusters.vertex(i) - cluster.centre).norm(), cluster.radius_mm);
      }
    }
    EXPECT_EQ(next, mesh.vertices.size());
    for (const int count : seen) EXPECT_EQ(count, 1);
  }
  EXPECT_TRUE(VertexClusters::build(TriMesh{}).clusters().empty());
  EXPECT_THROW(VertexClusters::build(mesh, 0), Error);
  TriMesh bad = mesh;
  bad.vertices[3].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(VertexClusters::build(bad), Error);
}

TEST(VertexClusters, SpheresAreSmallOnASmoothSurface) {
  // The median split keeps a cluster's vertices together: on a sphere, a cluster of 32 covers
  // about 32 vertices' share of the area, a patch of side s = sqrt(32 A / n), whose bounding
  // sphere is about the half diagonal s / sqrt(2). The clusters' mean radius stays within 20 % of
  // it (runs of 32 along a Morton curve, which jump across the surface, give 50 % more).
  const TriMesh sphere = geometry::make_octasphere(geometry::Vec3::Zero(), 10.0, 4);
  const VertexClusters clusters = VertexClusters::build(sphere, 32);
  double total = 0.0;
  for (const VertexCluster& cluster : clusters.clusters()) total += cluster.radius_mm;
  const double side = std::sqrt(32.0 * geometry::surface_area(sphere) / static_cast<double>(sphere.vertices.size()));
  EXPECT_LT(total / static_cast<double>(clusters.clusters().size()), 1.2 * side / std::sqrt(2.0));
}

// Whether the point (axis frame) passes the query's per-vertex filters.
bool passes_filters(const CylindricalTable& table, const Vec3& local) {
  return table.distance_may_touch(local.norm()) && table.has_candidates(std::hypot(local.x(), local.y()), local.z());
}

// A ball of radius rho holding `local` (on its surface in direction u, or at its centre) must not
// be culled when the point passes the filters.
void expect_not_culled(const CylindricalTable& table, const Vec3& local, const Vec3& u, double rho, const char* what) {
  if (!passes_filters(table, local)) return;
  EXPECT_TRUE(table.ball_may_touch(local, 0.0)) << what;
  EXPECT_TRUE(table.ball_may_touch(local + rho * u, rho * (1.0 + 1e-12))) << what << " rho " << rho;
}

TEST(CylindricalBallMayTouch, NeverCullsABallHoldingAPointThatPassesTheFilters) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0, culled = 0;
  for (int trial = 0; trial < 9; ++trial) {
    const TriMesh fixed = random_shape(rng, trial % 3);
    const TriMesh mobile = random_shape(rng, (trial + 1) % 3);
    const Vec3 centre(10 * unit(rng) - 5, 10 * unit(rng) - 5, 10 * unit(rng) - 5);
    const CylindricalTable table = CylindricalTable::build(fixed, centre, random_unit(rng), {}, &mobile);
    if (table.status() != QueryStatus::kOk) continue;
    const double rr = table.resolution_r_mm(), rz = table.resolution_z_mm();
    const double r_extent = rr * static_cast<double>(table.num_r_cells());
    const double z_extent = rz * static_cast<double>(table.num_z_cells());
    for (int k = 0; k < 3000; ++k) {
      // Anywhere in and around the grid; every third point exactly on a cell border in r and z.
      double r = table.r_lo_mm() - rr + (r_extent + 2 * rr) * unit(rng);
      double z = table.z_lo_mm() - rz + (z_extent + 2 * rz) * unit(rng);
      if (k % 3 == 0) {
        r = table.r_lo_mm() + rr * std::floor((r - table.r_lo_mm()) / rr);
        z = table.z_lo_mm() + rz * std::floor((z - table.z_lo_mm()) / rz);
      }
      if (r < 0.0) continue;
      const double theta = std::numbers::pi * (2 * unit(rng) - 1);
      const Vec3 local(r * std::cos(theta), r * std::sin(theta), z);
      const Vec3 u = random_unit(rng);
      for (const double rho : {1e-9, 0.3 * rr, 2.0 * rr, 10.0 * rr}) expect_not_culled(table, local, u, rho, "random");
      ++checked;
      // The culling itself: a small ball away from every non-empty cell and off the distance
      // range is passed over (the test would prove nothing if nothing were ever culled).
      culled += table.ball_may_touch(local, 1e-9) ? 0 : 1;
    }
    // Points exactly at the distance filter's bounds, found by bisection on distance_may_touch.
    for (const bool upper : {false, true}) {
      double in = 0.0, out = 0.0;
      for (double d = 0.01; d < 1e4; d *= 1.5) {
        if (table.distance_may_touch(d)) in = d;
      }
      if (in == 0.0) continue;
      out = upper ? 1e5 : 0.0;
      for (int i = 0; i < 200; ++i) {
        const double middle = 0.5 * (in + out);
        (table.distance_may_touch(middle) ? in : out) = middle;
      }
      for (int k = 0; k < 200; ++k) {
        const Vec3 direction = random_unit(rng);
        expect_not_culled(table, in * direction, direction, 0.5, upper ? "at L_max" : "at L_min");
        expect_not_culled(table, in * direction, -direction, 0.5, upper ? "at L_max" : "at L_min");
      }
    }
  }
  EXPECT_GT(checked, 10000);
  EXPECT_GT(culled, 1000);
}

TEST(CylindricalBallMayTouch, QueryOverClustersRejectsANonFinitePose) {
  // (The query over clusters equals the plain one on every scene of
  // cylindrical_angular_walk_test.cpp, at cluster sizes 1, 5 and 32.)
  const TriMesh box = geometry::make_box(Vec3(3, -1, -1), Vec3(5, 1, 1), 2);
  const CylindricalTable table = CylindricalTable::build(box, Vec3::Zero(), Vec3::UnitZ());
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(cylindrical_segmenting(table, VertexClusters::build(box), bad).status, QueryStatus::kInvalidInput);
  EXPECT_EQ(cylindrical_segmenting(table, VertexClusters::build(box), Eigen::Isometry3d::Identity()).status,
            QueryStatus::kOk);
}

TEST(CylindricalTableClusters, AnyMeshWithAsManyVerticesIsAnsweredExactly) {
  // The table keeps the clusters of the mesh it was restricted to and uses only the grouping of
  // indices: a mesh with as many vertices that is not a rigid copy of it (here its vertices
  // scattered among each other and moved) gets the same pairs as without the clusters.
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t reported = 0;
  for (int trial = 0; trial < 10; ++trial) {
    const TriMesh fixed = random_shape(rng, trial % 3);
    const TriMesh rest = random_shape(rng, (trial + 2) % 3);
    const CylindricalTable table = CylindricalTable::build(fixed, Vec3::Zero(), random_unit(rng), {}, &rest);
    ASSERT_EQ(table.mobile_clusters().num_vertices(), rest.vertices.size());
    TriMesh other = rest;
    std::shuffle(other.vertices.begin(), other.vertices.end(), rng);
    for (Vec3& p : other.vertices) p += Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
    for (const TriMesh* mesh : {&rest, static_cast<const TriMesh*>(&other)}) {
      detail::CylindricalAblation plain;
      plain.mobile_clusters = false;
      const PenetrationResult want = detail::cylindrical_segmenting(table, *mesh, {}, plain);
      const PenetrationResult got = cylindrical_segmenting(table, *mesh);
      ASSERT_EQ(got.pairs.size(), want.pairs.size()) << "trial " << trial;
      for (std::size_t i = 0; i < got.pairs.size(); ++i) {
        EXPECT_EQ(got.pairs[i].mobile_vertex, want.pairs[i].mobile_vertex);
        EXPECT_EQ(got.pairs[i].fixed_triangle, want.pairs[i].fixed_triangle);
        EXPECT_EQ(got.pairs[i].depth_mm, want.pairs[i].depth_mm);
      }
      reported += want.pairs.size();
    }
  }
  EXPECT_GT(reported, 100u);
  // Without a mobile mesh, or without the angular index, the table keeps no clusters.
  const TriMesh box = geometry::make_box(Vec3(3, -1, -1), Vec3(5, 1, 1), 2);
  EXPECT_EQ(CylindricalTable::build(box, Vec3::Zero(), Vec3::UnitZ()).mobile_clusters().num_vertices(), 0u);
  CylindricalTableOptions no_index;
  no_index.angular_index = false;
  EXPECT_EQ(CylindricalTable::build(box, Vec3::Zero(), Vec3::UnitZ(), no_index, &box).mobile_clusters().num_vertices(),
            0u);
}

}  // namespace
}  // namespace hipfai::contact
