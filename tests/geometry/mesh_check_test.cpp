#include "geometry/mesh_check.h"

#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <utility>

namespace hipfai::geometry {
namespace {

// Unit box, 2 x 2 quads per face: 26 vertices, 48 triangles, 72 edges.
TriMesh unit_box() { return make_box(Vec3::Zero(), Vec3::Ones(), 2); }

// Brute-force edge statistics, independent of check_mesh: for each distinct undirected edge,
// count by direct search the triangles using it.
std::pair<std::size_t, std::size_t> brute_boundary_and_non_manifold(const TriMesh& mesh) {
  std::set<std::pair<int, int>> edges;
  for (const Triangle& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      const int a = t[e], b = t[(e + 1) % 3];
      if (a != b) edges.insert({std::min(a, b), std::max(a, b)});
    }
  }
  std::size_t boundary = 0, non_manifold = 0;
  for (const auto& [a, b] : edges) {
    std::size_t users = 0;
    for (const Triangle& t : mesh.triangles) {
      const bool has_a = t[0] == a || t[1] == a || t[2] == a;
      const bool has_b = t[0] == b || t[1] == b || t[2] == b;
      users += has_a && has_b ? 1 : 0;
    }
    boundary += users == 1 ? 1 : 0;
    non_manifold += users > 2 ? 1 : 0;
  }
  return {boundary, non_manifold};
}

TEST(CheckMesh, ClosedBoxIsCleanAndMatchesClosedForms) {
  const TriMesh box = make_box(Vec3(1, 2, 3), Vec3(2, 4, 6), 2);
  const MeshReport r = check_mesh(box);
  EXPECT_EQ(r.num_vertices, 26u);
  EXPECT_EQ(r.num_triangles, 48u);
  EXPECT_EQ(r.num_edges, 72u);  // closed: every edge in two triangles, E = 3 T / 2
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.non_manifold_vertices, 0u);
  EXPECT_EQ(r.degenerate_triangles, 0u);
  EXPECT_EQ(r.sliver_triangles, 0u);
  EXPECT_EQ(r.duplicate_triangles, 0u);
  EXPECT_EQ(r.connected_components, 1u);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.orientation_consistent);
  EXPECT_TRUE(r.outward);
  EXPECT_TRUE(r.watertight_manifold);
  // 1 x 2 x 3 box; all inputs are small dyadic numbers, so only summation rounding remains.
  EXPECT_NEAR(r.signed_volume_mm3, 6.0, 1e-12);
  EXPECT_NEAR(r.surface_area_mm2, 22.0, 1e-12);
  EXPECT_EQ(r.bounds.min, Vec3(1, 2, 3));
  EXPECT_EQ(r.bounds.max, Vec3(2, 4, 6));
  // Same definition (each distinct edge once) as tri_mesh's mean_edge_length, computed apart.
  EXPECT_NEAR(r.mean_edge_length_mm, mean_edge_length(box), 1e-12);
}

TEST(CheckMesh, HoleLeavesBoundaryEdges) {
  TriMesh box = unit_box();
  box.triangles.erase(box.triangles.begin() + 5);
  const MeshReport r = check_mesh(box);
  EXPECT_EQ(r.boundary_edges, 3u);
  EXPECT_EQ(brute_boundary_and_non_manifold(box).first, 3u);
  EXPECT_FALSE(r.closed);
  EXPECT_TRUE(r.orientation_consistent);
  EXPECT_FALSE(r.outward);
  EXPECT_FALSE(r.watertight_manifold);
  EXPECT_EQ(r.non_manifold_vertices, 0u);  // the hole's corners are half-disks, still manifold
}

TEST(CheckMesh, FlippedTriangleBreaksConsistency) {
  TriMesh box = unit_box();
  std::swap(box.triangles[7][1], box.triangles[7][2]);
  const MeshReport r = check_mesh(box);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.inconsistent_edges, 3u);  // all three of its edges now run with their neighbours
  EXPECT_FALSE(r.orientation_consistent);
  EXPECT_FALSE(r.outward);
}

TEST(CheckMesh, InsideOutBoxIsConsistentButNotOutward) {
  TriMesh box = unit_box();
  for (Triangle& t : box.triangles) std::swap(t[1], t[2]);
  const MeshReport r = check_mesh(box);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.orientation_consistent);
  EXPECT_NEAR(r.signed_volume_mm3, -1.0, 1e-12);
  EXPECT_FALSE(r.outward);
}

// A fin: one extra triangle hung on an edge of the box makes that edge non-manifold (3 users),
// leaves the fin's two free edges as boundary, and its two end vertices non-manifold.
TEST(CheckMesh, FinMakesNonManifoldEdge) {
  TriMesh box = unit_box();
  const Triangle host = box.triangles[0];
  box.vertices.push_back(Vec3(0.5, 0.5, 5.0));
  box.triangles.push_back({host[0], host[1], static_cast<std::int32_t>(box.vertices.size() - 1)});
  const MeshReport r = check_mesh(box);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_EQ(r.boundary_edges, 2u);
  EXPECT_EQ(brute_boundary_and_non_manifold(box), std::make_pair(std::size_t{2}, std::size_t{1}));
  EXPECT_EQ(r.non_manifold_vertices, 2u);
  EXPECT_EQ(r.connected_components, 1u);
  EXPECT_FALSE(r.watertight_manifold);
}

// Two tetrahedra touching at one vertex: closed, every edge manifold, but the shared vertex's
// triangles form two separate fans.
TEST(CheckMesh, BowtieVertexIsNonManifold) {
  TriMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
                   Vec3(-1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1)};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2},   // octant + + +
                    {0, 4, 5}, {0, 6, 4}, {4, 6, 5}, {0, 5, 6}};  // octant - - - (mirrored, rewound)
  const MeshReport r = check_mesh(mesh);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_EQ(r.connected_components, 1u);  // joined through the shared vertex
  EXPECT_TRUE(r.orientation_consistent);
  EXPECT_NEAR(r.signed_volume_mm3, 2.0 / 6.0, 1e-15);
  EXPECT_TRUE(r.outward);
  EXPECT_FALSE(r.watertight_manifold);
}

TEST(CheckMesh, TwoSpheresAreTwoComponents) {
  const TriMesh a = make_octasphere(Vec3::Zero(), 1.0, 2);
  const TriMesh b = make_octasphere(Vec3(5, 0, 0), 2.0, 3);
  const TriMesh both = merge_meshes({&a, &b});
  const MeshReport r = check_mesh(both);
  EXPECT_EQ(r.connected_components, 2u);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.outward);
  EXPECT_TRUE(r.watertight_manifold);
  // Volume is additive over the two closed parts.
  EXPECT_NEAR(r.signed_volume_mm3, signed_volume(a) + signed_volume(b), 1e-9);
}

TEST(CheckMesh, ZeroAreaAndRepeatedIndexTrianglesAreDegenerate) {
  TriMesh box = unit_box();
  const auto n = static_cast<std::int32_t>(box.vertices.size());
  // Three points on one oblique line: 0.1, 0.2, 0.3 are inexact in binary, so the cross product
  // is only zero up to rounding — the case the relative tolerance is for.
  const Vec3 step(0.1, 0.2, 0.3);
  box.vertices.push_back(Vec3(3.0, 0.0, 0.0) + step);
  box.vertices.push_back(Vec3(3.0, 0.0, 0.0) + 2.0 * step);
  box.vertices.push_back(Vec3(3.0, 0.0, 0.0) + 3.0 * step);
  box.triangles.push_back({n, n + 1, n + 2});
  box.triangles.push_back({0, 0, 1});
  const MeshReport r = check_mesh(box);
  EXPECT_EQ(r.degenerate_triangles, 2u);
  EXPECT_EQ(r.sliver_triangles, 0u);
  EXPECT_FALSE(r.watertight_manifold);
}

TEST(CheckMesh, SliverIsCountedApartFromDegenerate) {
  TriMesh mesh = unit_box();
  const auto n = static_cast<std::int32_t>(mesh.vertices.size());
  // Apex 1e-4 above the middle of a unit base: smallest angle atan(2e-4) = 2e-4 rad < 1e-3.
  mesh.vertices.push_back(Vec3(5, 0, 0));
  mesh.vertices.push_back(Vec3(6, 0, 0));
  mesh.vertices.push_back(Vec3(5.5, 1e-4, 0));
  // And a fat-enough one: angle atan(4e-3) = 4e-3 rad > 1e-3, not a sliver.
  mesh.vertices.push_back(Vec3(5, 2, 0));
  mesh.vertices.push_back(Vec3(6, 2, 0));
  mesh.vertices.push_back(Vec3(5.5, 2.002, 0));
  mesh.triangles.push_back({n, n + 1, n + 2});
  mesh.triangles.push_back({n + 3, n + 4, n + 5});
  const MeshReport r = check_mesh(mesh);
  EXPECT_EQ(r.sliver_triangles, 1u);
  EXPECT_EQ(r.degenerate_triangles, 0u);
  EXPECT_EQ(r.connected_components, 3u);
}

TEST(CheckMesh, DuplicateTrianglesInAnyOrder) {
  TriMesh box = unit_box();
  const Triangle t = box.triangles[3];
  box.triangles.push_back(t);                  // same winding
  box.triangles.push_back({t[1], t[0], t[2]});  // reversed
  const MeshReport r = check_mesh(box);
  EXPECT_EQ(r.duplicate_triangles, 2u);
  EXPECT_EQ(r.non_manifold_edges, 3u);  // each of its edges now has 4 users
  EXPECT_FALSE(r.watertight_manifold);
}

TEST(CheckMesh, UnreferencedVerticesAreNotComponents) {
  TriMesh box = unit_box();
  box.vertices.push_back(Vec3(9, 9, 9));
  const MeshReport r = check_mesh(box);
  EXPECT_EQ(r.unreferenced_vertices, 1u);
  EXPECT_EQ(r.connected_components, 1u);
  EXPECT_EQ(r.bounds.max, Vec3(9, 9, 9));  // the box covers every stored vertex
}

// A single open triangle: every edge is boundary, nothing is closed.
TEST(CheckMesh, SingleTriangle) {
  TriMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(0, 4, 0)};
  mesh.triangles = {{0, 1, 2}};
  const MeshReport r = check_mesh(mesh);
  EXPECT_EQ(r.boundary_edges, 3u);
  EXPECT_EQ(r.non_manifold_vertices, 0u);
  EXPECT_DOUBLE_EQ(r.surface_area_mm2, 6.0);  // 3-4-5 right triangle, exact
  EXPECT_DOUBLE_EQ(r.mean_edge_length_mm, 4.0);  // (3 + 4 + 5) / 3
  EXPECT_FALSE(r.closed);
}

TEST(CheckMesh, EmptyMeshGivesZeros) {
  const MeshReport r = check_mesh(TriMesh{});
  EXPECT_EQ(r.num_vertices, 0u);
  EXPECT_EQ(r.connected_components, 0u);
  EXPECT_FALSE(r.closed);
  EXPECT_FALSE(r.outward);
}

// The torus is closed and manifold but has genus 1: Euler characteristic V - E + F = 0.
TEST(CheckMesh, TorusEulerCharacteristic) {
  const TriMesh torus = make_torus(Vec3::Zero(), 10.0, 3.0, 24, 12);
  const MeshReport r = check_mesh(torus);
  EXPECT_TRUE(r.watertight_manifold);
  EXPECT_TRUE(r.outward);
  EXPECT_EQ(static_cast<long>(r.num_vertices) - static_cast<long>(r.num_edges) +
                static_cast<long>(r.num_triangles),
            0);
}

// closed_shell_labels: one label per closed, consistently oriented group of triangles joined
// through edges; nothing for a surface that is not made of such shells.
TEST(ClosedShellLabels, OneShellPerClosedPart) {
  const TriMesh box = unit_box();
  const auto one = closed_shell_labels(box.triangles);
  ASSERT_TRUE(one.has_value());
  EXPECT_EQ(std::set<std::int32_t>(one->begin(), one->end()), std::set<std::int32_t>{0});

  const TriMesh a = make_octasphere(Vec3::Zero(), 1.0, 2);
  const TriMesh b = make_octasphere(Vec3(0.5, 0, 0), 2.0, 3);  // overlapping: still two shells
  const TriMesh both = merge_meshes({&a, &b});
  const auto two = closed_shell_labels(both.triangles);
  ASSERT_TRUE(two.has_value());
  for (std::size_t t = 0; t < both.triangles.size(); ++t) {
    EXPECT_EQ((*two)[t], t < a.triangles.size() ? 0 : 1) << t;
  }

  TriMesh inside_out = unit_box();  // consistently inward is still a closed shell
  for (Triangle& t : inside_out.triangles) std::swap(t[1], t[2]);
  EXPECT_TRUE(closed_shell_labels(inside_out.triangles).has_value());
}

TEST(ClosedShellLabels, NoneForOpenNonManifoldOrInconsistentSurfaces) {
  TriMesh hole = unit_box();
  hole.triangles.erase(hole.triangles.begin() + 5);
  EXPECT_FALSE(closed_shell_labels(hole.triangles).has_value());

  TriMesh flipped = unit_box();
  std::swap(flipped.triangles[7][1], flipped.triangles[7][2]);
  EXPECT_FALSE(closed_shell_labels(flipped.triangles).has_value());

  TriMesh fin = unit_box();
  const Triangle host = fin.triangles[0];
  fin.vertices.push_back(Vec3(0.5, 0.5, 5.0));
  fin.triangles.push_back({host[0], host[1], static_cast<std::int32_t>(fin.vertices.size() - 1)});
  EXPECT_FALSE(closed_shell_labels(fin.triangles).has_value());

  // A closed box with a second copy of one triangle, wound the other way: its edges are used
  // four times.
  TriMesh doubled = unit_box();
  Triangle copy = doubled.triangles[3];
  std::swap(copy[1], copy[2]);
  doubled.triangles.push_back(copy);
  doubled.triangles.push_back(doubled.triangles[3]);
  EXPECT_FALSE(closed_shell_labels(doubled.triangles).has_value());

  TriMesh repeated = unit_box();
  repeated.triangles[2][1] = repeated.triangles[2][0];
  EXPECT_FALSE(closed_shell_labels(repeated.triangles).has_value());
  EXPECT_TRUE(closed_shell_labels(std::vector<Triangle>{}).has_value());  // nothing: no shells
}

}  // namespace
}  // namespace hipfai::geometry
