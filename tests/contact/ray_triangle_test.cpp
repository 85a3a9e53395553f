// Tests of the watertight ray-triangle primitive (contact/ray_triangle.h) against closed-form
// geometry, the thesis' own barycentric form (App. F, Eq. 34-35) and closed meshes.
#include "contact/ray_triangle.h"

#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace hipfai::contact {
namespace {

TEST(RayTriangle, ClosedFormHitPointWeightsAndFacing) {
  // Triangle in the plane z = 10, counter-clockwise seen from +z: outward normal +z.
  const Vec3 a(-1, -1, 10), b(2, -1, 10), c(-1, 2, 10);
  const Vec3 direction(0.01, 0.02, 1.0);
  const RayCrossing crossing = ray_triangle_crossing(direction, a, b, c);
  ASSERT_TRUE(crossing.hit);
  // Closed form: the plane z = 10 is met at t = 10 / d_z = 10, point (0.1, 0.2, 10).
  EXPECT_NEAR(crossing.t, 10.0, 1e-12);  // a few ulps of the triple products (|values| ~ 10^2)
  EXPECT_EQ(crossing.facing, 1);         // normal along the ray: the ray exits
  const Vec3 point = crossing.weight_a * a + crossing.weight_b * b + crossing.weight_c * c;
  EXPECT_NEAR((point - crossing.t * direction).norm(), 0.0, 1e-12);
  EXPECT_NEAR(crossing.weight_a + crossing.weight_b + crossing.weight_c, 1.0, 1e-15);
  // Reversed winding: same point, entering.
  const RayCrossing reversed = ray_triangle_crossing(direction, a, c, b);
  ASSERT_TRUE(reversed.hit);
  EXPECT_EQ(reversed.facing, -1);
  EXPECT_DOUBLE_EQ(reversed.t, crossing.t);
  // Eq. 34 gives the same distance along the unit direction.
  EXPECT_NEAR(radial_plane_distance(direction, a, b, c), 10.0 * direction.norm(), 1e-12);
}

TEST(RayTriangle, BehindCentreParallelAndDegenerateDoNotCross) {
  const Vec3 a(-1, -1, 10), b(2, -1, 10), c(-1, 2, 10);
  EXPECT_FALSE(ray_triangle_crossing(Vec3(0, 0, -1), a, b, c).hit);  // line hits, ray does not
  EXPECT_NEAR(radial_plane_distance(Vec3(0, 0, -1), a, b, c), -10.0, 1e-12);
  EXPECT_FALSE(ray_triangle_crossing(Vec3(1, 0, 0), a, b, c).hit);   // parallel to the plane
  EXPECT_TRUE(std::isnan(radial_plane_distance(Vec3(1, 0, 0), a, b, c)));
  // In-plane ray: a triangle containing O's plane direction.
  const Vec3 p(1, -1, 0), q(1, 1, 0), r(2, 0, 0);
  EXPECT_FALSE(ray_triangle_crossing(Vec3(1, 0, 0), p, q, r).hit);
  // Zero-area (collinear) triangle.
  EXPECT_FALSE(ray_triangle_crossing(Vec3(0, 0, 1), Vec3(0, 0, 5), Vec3(1, 0, 5), Vec3(2, 0, 5)).hit);
  // Miss beside the triangle.
  EXPECT_FALSE(ray_triangle_crossing(Vec3(1, 1, 1), a, b, c).hit);
}

TEST(RayTriangle, EdgeFunctionIsExactlyAntisymmetric) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  for (int i = 0; i < 10000; ++i) {
    const Vec3 d(u(rng), u(rng), u(rng)), p(u(rng), u(rng), u(rng)), q(u(rng), u(rng), u(rng));
    ASSERT_EQ(edge_function(d, p, q), -edge_function(d, q, p));  // bit-exact, not approximate
  }
}

// A ray exactly through a vertex P (d = 2 P, exact) lies in the plane of every edge at P: the
// float triple product is rounding noise, the exact predicate must say 0 on both orders.
TEST(RayTriangle, EdgeSignIsExactThroughVertices) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-30.0, 30.0);
  int noisy = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng)), q(u(rng), u(rng), u(rng));
    const Vec3 d = 2.0 * p;
    noisy += (d.dot(p.cross(q)) != 0.0);
    ASSERT_EQ(edge_sign(d, p, q), 0);
    ASSERT_EQ(edge_sign(d, q, p), 0);
    // And a clearly non-degenerate case keeps the float sign.
    const Vec3 off = d + q.cross(p).normalized();
    ASSERT_EQ(edge_sign(off, p, q), off.dot(p.cross(q)) > 0 ? 1 : -1);
  }
  EXPECT_GT(noisy, 1000);  // the float evaluation alone would have decided wrongly/randomly
}

// The thesis' own test (App. F, Eq. 34-35): plane distance, then u, v in the xy projection.
bool thesis_hit(const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c, double& dist) {
  const Vec3 unit = d.normalized();
  const Vec3 normal = (b - a).cross(c - a);
  dist = a.dot(normal) / unit.dot(normal);
  const double b0 = b.x() - a.x(), b1 = b.y() - a.y(), c0 = c.x() - a.x(), c1 = c.y() - a.y();
  const double p0 = dist * unit.x() - a.x(), p1 = dist * unit.y() - a.y();
  const double l = c1 * b0 - c0 * b1;
  const double uu = (p1 * c0 - p0 * c1) / (-l);
  const double vv = (p1 * b0 - p0 * b1) / l;
  return dist > 0 && uu >= 0 && vv >= 0 && uu + vv <= 1;
}

TEST(RayTriangle, AgreesWithThesisBarycentricFormAwayFromEdges) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0, compared = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a = Vec3(u(rng), u(rng), u(rng) * 0.3) + Vec3(0, 0, 5);
    const Vec3 b = Vec3(u(rng), u(rng), u(rng) * 0.3) + Vec3(0, 0, 5);
    const Vec3 c = Vec3(u(rng), u(rng), u(rng) * 0.3) + Vec3(0, 0, 5);
    const Vec3 d(u(rng) * 0.3, u(rng) * 0.3, 1.0);
    const Vec3 normal = (b - a).cross(c - a);
    if (std::abs(normal.normalized().z()) < 0.2) continue;  // Eq. 35 projects on xy
    // Skip rays within 1e-9 (relative) of an edge, where two correct rounding paths may differ.
    const double scale = d.norm() * 25.0;
    if (std::abs(edge_function(d, a, b)) < 1e-9 * scale ||
        std::abs(edge_function(d, b, c)) < 1e-9 * scale ||
        std::abs(edge_function(d, c, a)) < 1e-9 * scale)
      continue;
    double dist = 0.0;
    const bool expected = thesis_hit(d, a, b, c, dist);
    const RayCrossing crossing = ray_triangle_crossing(d, a, b, c);
    ++compared;
    ASSERT_EQ(crossing.hit, expected) << "sample " << i;
    if (expected) {
      ++hits;
      // Both are the same plane distance computed two ways; |dist| ~ 5, conditioning bounded
      // by the |n_z| >= 0.2 filter: 1e-9 relative is ample.
      EXPECT_NEAR(crossing.t * d.norm(), dist, 1e-9 * std::abs(dist));
    }
  }
  EXPECT_GT(hits, 300);
  EXPECT_GT(compared, 10000);
}

// Rays from inside a closed mesh: every direction crosses it, including directions exactly
// through vertices and edge midpoints (shared by several triangles), and the crossings exit.
TEST(RayTriangle, WatertightOnClosedMeshThroughVerticesAndEdges) {
  for (const Vec3& offset : {Vec3(0, 0, 0), Vec3(1e4, -1e4, 1e4)}) {
    const auto sphere = geometry::make_octasphere(offset + Vec3(0.3, -0.2, 0.1), 25.0, 3);
    const Vec3 centre = offset;
    std::vector<Vec3> directions;
    for (const auto& v : sphere.vertices) directions.push_back(v - centre);
    for (const auto& t : sphere.triangles) {
      directions.push_back(0.5 * (sphere.vertices[t[0]] + sphere.vertices[t[1]]) - centre);
    }
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g;
    for (int i = 0; i < 2000; ++i) directions.emplace_back(g(rng), g(rng), g(rng));
    for (const Vec3& d : directions) {
      int crossings = 0;
      for (const auto& t : sphere.triangles) {
        const RayCrossing c = ray_triangle_crossing(d, sphere.vertices[t[0]] - centre,
                                                    sphere.vertices[t[1]] - centre,
                                                    sphere.vertices[t[2]] - centre);
        if (!c.hit) continue;
        ++crossings;
        EXPECT_EQ(c.facing, 1);
        // The crossing lies on the mesh, inside the sphere of radius 25 (chords are inside).
        EXPECT_LE((c.t * d + centre - (offset + Vec3(0.3, -0.2, 0.1))).norm(), 25.0 + 1e-9);
      }
      ASSERT_GE(crossings, 1) << "ray fell through a crack: " << d.transpose();
    }
  }
}

}  // namespace
}  // namespace hipfai::contact
