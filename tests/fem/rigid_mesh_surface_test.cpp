// Closest points on a rigid triangle-mesh surface (fem/rigid_mesh_surface.h): the per-triangle
// projection against the optimality condition of a convex set, the BVH search against brute
// force, and the surface against the exact sphere it approximates (RigidSphere).
#include "fem/rigid_mesh_surface.h"

#include "core/error.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace hipfai::fem {
namespace {

using geometry::Vec3;

Vec3 random_vector(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

TEST(ClosestPointOnTriangle, SatisfiesTheProjectionConditionOnRandomTriangles) {
  // x is the projection of p on the convex triangle T iff x is in T and (p - x) . (y - x) <= 0
  // for every y in T, i.e. for its three vertices. Checked on random, partly thin triangles.
  std::mt19937 rng(7);
  int by_feature[3] = {0, 0, 0};
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec3 a = random_vector(rng, 1.0), b = random_vector(rng, 1.0);
    const Vec3 c = trial % 4 == 0 ? Vec3(a + 0.5 * (b - a) + random_vector(rng, 1e-3))
                                  : random_vector(rng, 1.0);
    const Vec3 p = random_vector(rng, 2.0);
    const MeshClosestPoint hit = closest_point_on_triangle(p, a, b, c);
    ++by_feature[static_cast<int>(hit.feature)];
    // Round-off of products of unit-size coordinates: a few 1e-16; 1e-12 leaves margin for the
    // thin triangles (condition number up to ~1e3).
    constexpr double kTol = 1e-12;
    for (const Vec3& y : {a, b, c}) EXPECT_LE((p - hit.point_mm).dot(y - hit.point_mm), kTol);
    // x in the plane of T and inside it: barycentric coordinates from sub-areas.
    const Vec3 n = (b - a).cross(c - a);
    const double area2 = n.squaredNorm();
    const double u = (c - b).cross(hit.point_mm - b).dot(n) / area2;
    const double v = (a - c).cross(hit.point_mm - c).dot(n) / area2;
    const double w = (b - a).cross(hit.point_mm - a).dot(n) / area2;
    EXPECT_NEAR(u + v + w, 1.0, 1e-9);
    EXPECT_NEAR((hit.point_mm - a).dot(n) / std::sqrt(area2), 0.0, 1e-12);
    for (const double coordinate : {u, v, w}) EXPECT_GE(coordinate, -1e-9);
    EXPECT_NEAR(hit.distance_mm, (p - hit.point_mm).norm(), 1e-15);
  }
  // Every feature class is exercised.
  for (const int count : by_feature) EXPECT_GT(count, 100);
}

TEST(RigidMeshSurface, BvhEqualsBruteForceOnRandomQueries) {
  // A torus has concave and convex regions, so the search and the pseudo-normals are tested on
  // both; queries inside, outside and far away.
  const geometry::TriMesh torus = geometry::make_torus(Vec3(1, 2, 3), 20.0, 6.0, 48, 24);
  const RigidMeshSurface surface(torus, "torus");
  std::mt19937 rng(11);
  for (int trial = 0; trial < 3000; ++trial) {
    const Vec3 q = Vec3(1, 2, 3) + random_vector(rng, trial % 10 == 0 ? 80.0 : 28.0);
    const MeshClosestPoint fast = surface.closest(q);
    const MeshClosestPoint slow = surface.closest_brute_force(q);
    // Same minimum distance to round-off (several triangles can tie at an edge or vertex, so
    // the point is compared, not the triangle index).
    ASSERT_NEAR(fast.distance_mm, slow.distance_mm, 1e-12) << "query " << q.transpose();
    EXPECT_LT((fast.point_mm - slow.point_mm).norm(), 1e-9);
    EXPECT_EQ(fast.inside, slow.inside);
    // Inside/outside against the exact torus, away from its surface (the facets deviate from it
    // by at most the sagitta, < 0.3 mm at this resolution).
    const Vec3 local = q - Vec3(1, 2, 3);
    const double ring = std::hypot(local.x(), local.y()) - 20.0;
    const double torus_distance = std::hypot(ring, local.z()) - 6.0;
    if (std::abs(torus_distance) > 0.3) {
      EXPECT_EQ(fast.inside, torus_distance < 0) << q.transpose();
    }
    // The normal is a unit vector along the offset, pointing out of the body.
    EXPECT_NEAR(fast.normal.norm(), 1.0, 1e-12);
    const Vec3 offset = q - fast.point_mm;
    EXPECT_NEAR(offset.dot(fast.normal), fast.inside ? -fast.distance_mm : fast.distance_mm,
                1e-9 * std::max(1.0, fast.distance_mm));
  }
}

TEST(RigidMeshSurface, OnTheSurfaceTheNormalIsThePseudoNormal) {
  // Queries exactly at the vertices of an octasphere: the angle-weighted pseudo-normal of a
  // vertex of a sphere mesh is close to the radial direction (the facets around it are nearly
  // symmetric): within the facet angle.
  const geometry::TriMesh sphere = geometry::make_octasphere(Vec3::Zero(), 10.0, 3);
  const RigidMeshSurface surface(sphere, "sphere");
  const double facet_angle = 2.0 * std::asin(0.5 * geometry::mean_edge_length(sphere) / 10.0);
  for (const Vec3& v : sphere.vertices) {
    const MeshClosestPoint hit = surface.closest(v);
    EXPECT_LT(hit.distance_mm, 1e-12);
    EXPECT_LT(std::acos(std::min(1.0, hit.normal.dot(v.normalized()))), 2.0 * facet_angle);
  }
}

TEST(RigidMeshSurface, ApproximatesTheRigidSphere) {
  // The octasphere's vertices lie on the sphere and its facets inside it, by at most the largest
  // facet sagitta s = R - (smallest distance of a facet plane from the centre). So for any query
  // the mesh distance differs from the sphere's by at most s, and the normals by the angle the
  // facet under the closest point spans, bounded by asin(longest edge / plane distance).
  constexpr double kRadius = 23.0;  // the femoral bone head of the hip model
  const Vec3 centre(0.5, -1.0, 2.0);
  const geometry::TriMesh mesh = geometry::make_octasphere(centre, kRadius, 5);
  double min_plane = kRadius, max_edge = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 n = geometry::triangle_unit_normal(mesh, t);
    min_plane = std::min(min_plane, (mesh.vertices[tri[0]] - centre).dot(n));
    for (int k = 0; k < 3; ++k) {
      max_edge = std::max(max_edge, (mesh.vertices[tri[k]] - mesh.vertices[tri[(k + 1) % 3]]).norm());
    }
  }
  const double sagitta = kRadius - min_plane;
  const double angle_bound = std::asin(max_edge / min_plane);
  ASSERT_LT(sagitta, 0.03);  // level 5 on R = 23 mm: 0.022 mm, small against the 2 mm layers

  const RigidMeshSurface surface(mesh, "octasphere");
  const RigidSphere sphere(dealii::Point<3>(centre[0], centre[1], centre[2]), kRadius);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> radius(5.0, 40.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 q = centre + radius(rng) * random_vector(rng, 1.0).normalized();
    const SurfacePoint exact = sphere.closest_point(dealii::Point<3>(q[0], q[1], q[2]));
    const SurfacePoint faceted = surface.closest_point(dealii::Point<3>(q[0], q[1], q[2]));
    const dealii::Point<3> query(q[0], q[1], q[2]);
    // Signed gaps along each surface's normal, as the contact solver measures them.
    const double gap_exact = (query - exact.point_mm) * exact.normal;
    const double gap_faceted = (query - faceted.point_mm) * faceted.normal;
    EXPECT_NEAR(gap_faceted, gap_exact, sagitta + 1e-12) << q.transpose();
    EXPECT_LT(std::acos(std::min(1.0, faceted.normal * exact.normal)), angle_bound + 1e-9);
  }
}

TEST(RigidMeshSurface, RejectsEmptyAndDegenerateMeshes) {
  geometry::TriMesh empty;
  EXPECT_THROW(RigidMeshSurface(empty, "femur_bone"), Error);
  geometry::TriMesh flat;
  flat.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  flat.triangles = {{0, 1, 2}};
  try {
    RigidMeshSurface surface(flat, "femur_bone");
    FAIL() << "a zero-area triangle must be rejected";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("femur_bone: triangle 0 has zero area"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace hipfai::fem
