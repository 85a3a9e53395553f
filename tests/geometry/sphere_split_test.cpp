#include "geometry/sphere_split.h"

#include "geometry/mesh_check.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

namespace hipfai::geometry {
namespace {

// Distinct undirected edges whose endpoints lie on different sides of the sphere, counted by brute
// force over the triangles (independent of the splitter's edge map).
std::size_t crossing_edges(const TriMesh& mesh, const Vec3& centre, double radius) {
  std::set<std::pair<int, int>> edges;
  for (const Triangle& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      const int a = t[e], b = t[(e + 1) % 3];
      const bool in_a = (mesh.vertices[static_cast<std::size_t>(a)] - centre).norm() <= radius;
      const bool in_b = (mesh.vertices[static_cast<std::size_t>(b)] - centre).norm() <= radius;
      if (in_a != in_b) edges.insert({std::min(a, b), std::max(a, b)});
    }
  }
  return edges.size();
}

void expect_same_surface(const TriMesh& before, const SphereSplit& split, const Vec3& centre, double radius) {
  const TriMesh& after = split.mesh;
  ASSERT_EQ(split.num_original, before.num_vertices());
  for (std::size_t v = 0; v < before.num_vertices(); ++v) EXPECT_EQ(after.vertices[v], before.vertices[v]);
  EXPECT_EQ(after.num_vertices() - before.num_vertices(), crossing_edges(before, centre, radius));
  for (std::size_t v = before.num_vertices(); v < after.num_vertices(); ++v) {
    EXPECT_NEAR((after.vertices[v] - centre).norm(), radius, 1e-12 * radius) << "new vertex " << v;
  }
  EXPECT_NEAR(surface_area(after), surface_area(before), 1e-10 * surface_area(before));
  EXPECT_NEAR(signed_volume(after), signed_volume(before), 1e-10 * std::abs(signed_volume(before)));
  const MeshReport report = check_mesh(after);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.orientation_consistent);
  EXPECT_TRUE(report.outward);
  EXPECT_EQ(report.non_manifold_edges, 0u);
}

TEST(SphereSplit, EveryCrossingEdgeGetsOneVertexOnTheSphereAndTheSurfaceStaysTheSame) {
  const TriMesh box = make_box(Vec3(-10, -8, -6), Vec3(12, 9, 7), 7);
  for (const double radius : {5.0, 8.3, 11.0, 14.9}) {
    const Vec3 centre(0.7, -0.4, 0.3);
    expect_same_surface(box, split_at_sphere(box, centre, radius), centre, radius);
  }
}

TEST(SphereSplit, ASphereThatMissesTheSurfaceChangesNothing) {
  const TriMesh box = make_box(Vec3(-1, -1, -1), Vec3(1, 1, 1), 3);
  for (const double radius : {0.5, 2.0}) {  // inside every face, beyond every corner
    const SphereSplit split = split_at_sphere(box, Vec3::Zero(), radius);
    EXPECT_EQ(split.mesh.vertices, box.vertices);
    EXPECT_EQ(split.mesh.triangles, box.triangles);
  }
}

// Hard case: vertices exactly on the sphere count as inside; their edges to outside vertices meet
// the sphere at the vertex itself (t = 0), which gives zero-area triangles but the same surface.
TEST(SphereSplit, VerticesExactlyOnTheSphereGiveFiniteVerticesOnIt) {
  const TriMesh box = make_box(Vec3(-2, -2, -2), Vec3(2, 2, 2), 4);  // vertices on the unit grid
  const SphereSplit split = split_at_sphere(box, Vec3::Zero(), 2.0);  // face centres lie on it
  for (const Vec3& v : split.mesh.vertices) EXPECT_TRUE(v.allFinite());
  expect_same_surface(box, split, Vec3::Zero(), 2.0);
}

// A shared edge gets one vertex, whichever triangle meets it first: a sphere through a fine
// octasphere's band keeps the surface closed (checked above) and adds no duplicate position.
TEST(SphereSplit, SharedEdgesShareTheirNewVertex) {
  const TriMesh ball = make_octasphere(Vec3::Zero(), 25.0, 4);
  const Vec3 centre(0.0, 0.0, 20.0);
  const SphereSplit split = split_at_sphere(ball, centre, 30.0);
  expect_same_surface(ball, split, centre, 30.0);
  std::set<std::tuple<double, double, double>> positions;
  for (std::size_t v = split.num_original; v < split.mesh.num_vertices(); ++v) {
    const Vec3& p = split.mesh.vertices[v];
    EXPECT_TRUE(positions.insert({p.x(), p.y(), p.z()}).second) << "duplicate new vertex " << v;
  }
  EXPECT_GT(positions.size(), 20u);
}

}  // namespace
}  // namespace hipfai::geometry
