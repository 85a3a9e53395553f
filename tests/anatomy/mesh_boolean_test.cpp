// Tests of the CGAL mesh Booleans: closed-form volumes, solid results, one-line input errors.
#include "anatomy/mesh_boolean.h"

#include "core/error.h"
#include "geometry/mesh_check.h"
#include "geometry/primitive_meshes.h"
#include "tests/anatomy/anatomy_checks.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <numbers>
#include <string>
#include <utility>

namespace hipfai::anatomy {
namespace {

using test_support::expect_solid;

using geometry::make_box;
using geometry::make_octasphere;
using geometry::TriMesh;
using geometry::Vec3;

// A Boolean result must itself be a solid: closed, manifold, outward, not self-intersecting.
// Two overlapping boxes: every piece is a box, so the volumes are exact (flat faces are cut
// exactly; only the rounding of new vertices, ~1e-15 relative, remains).
TEST(MeshBoolean, BoxesGiveClosedFormVolumes) {
  const TriMesh a = make_box(Vec3(0, 0, 0), Vec3(2, 2, 2), 3);           // 8
  const TriMesh b = make_box(Vec3(1, 0.5, -1), Vec3(3, 1.5, 1), 4);      // overlap 1 x 1 x 1
  BooleanRequest request;
  request.a = &a;
  request.b = &b;
  request.outputs = {true, true, true};
  const BooleanResult r = compute_booleans(request);
  EXPECT_NEAR(volume(r.difference), 8.0 - 1.0, 1e-9);
  EXPECT_NEAR(volume(r.intersection), 1.0, 1e-9);
  EXPECT_NEAR(volume(r.union_of), 8.0 + 4.0 - 1.0, 1e-9);
  expect_solid(r.difference);
  expect_solid(r.intersection);
  expect_solid(r.union_of);
  EXPECT_TRUE(r.difference.vertex_fields.empty());
}

// A sphere's cap cut off by a box: the result equals the exact volume of the inscribed
// polyhedron minus the polyhedral cap, which we do not know in closed form; instead compare with
// the analytic sphere-cap volume within the polyhedron's own volume deficit (level 5: the
// octasphere's volume is within 0.3 % of the sphere's), and check the additivity
// V(a - b) + V(a ∩ b) = V(a), which holds exactly up to rounding.
TEST(MeshBoolean, SphereMinusHalfSpaceMatchesCapVolume) {
  const double r = 10.0;
  const double h = 4.0;  // cap height: the box removes z > r - h
  const TriMesh sphere = make_octasphere(Vec3::Zero(), r, 5);
  const TriMesh box = make_box(Vec3(-20, -20, r - h), Vec3(20, 20, 20), 2);
  BooleanRequest request;
  request.a = &sphere;
  request.b = &box;
  request.outputs = {false, true, true};
  const BooleanResult out = compute_booleans(request);
  const double v_sphere = volume(sphere);
  const double v_cap = std::numbers::pi * h * h * (3 * r - h) / 3.0;
  const double exact_sphere = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double deficit = exact_sphere - v_sphere;  // what the polyhedron lacks, > 0
  ASSERT_GT(deficit, 0.0);
  EXPECT_NEAR(volume(out.intersection), v_cap, deficit);
  EXPECT_NEAR(volume(out.difference), exact_sphere - v_cap, deficit);
  EXPECT_NEAR(volume(out.difference) + volume(out.intersection), v_sphere, 1e-9 * v_sphere);
  EXPECT_LT(volume(out.difference), v_sphere);
  expect_solid(out.difference);
  expect_solid(out.intersection);
}

// Nested solids: a - b is the hollow shell, a ∩ b is b; disjoint solids: a - b is a.
TEST(MeshBoolean, NestedAndDisjointSolids) {
  const TriMesh outer = make_octasphere(Vec3::Zero(), 10.0, 3);
  const TriMesh inner = make_box(Vec3(-2, -2, -2), Vec3(2, 2, 2), 1);
  EXPECT_NEAR(volume(difference(outer, inner)), volume(outer) - 64.0, 1e-9);
  EXPECT_NEAR(volume(intersection(outer, inner)), 64.0, 1e-9);
  EXPECT_TRUE(difference(inner, outer).empty());
  const TriMesh far = make_box(Vec3(20, 20, 20), Vec3(21, 21, 21), 1);
  EXPECT_NEAR(volume(difference(outer, far)), volume(outer), 1e-9);
  EXPECT_TRUE(intersection(outer, far).empty());
}

// The error must be one line and name the input at fault.
void expect_boolean_error(const TriMesh& bad, const std::string& needle) {
  const TriMesh good = make_box(Vec3(0, 0, 0), Vec3(1, 1, 1), 1);
  try {
    (void)difference(good, bad, "good", "the bad solid");
    FAIL() << "no error for " << needle;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind("the bad solid: ", 0), 0u) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << message;
  }
}

TEST(MeshBoolean, BadInputsGiveOneLineErrors) {
  TriMesh open = make_box(Vec3(0, 0, 0), Vec3(1, 1, 1), 2);
  open.triangles.pop_back();
  EXPECT_FALSE(is_closed(open));
  expect_boolean_error(open, "not closed");

  // Two boxes sharing only an edge: closed, but the shared edge has four triangles.
  const TriMesh b1 = make_box(Vec3(0, 0, 0), Vec3(1, 1, 1), 1);
  TriMesh b2 = make_box(Vec3(1, 1, 0), Vec3(2, 2, 1), 1);
  TriMesh touching = geometry::merge_meshes({&b1, &b2});
  // Weld b2's copies of the shared edge's vertices (1,1,0) and (1,1,1) onto b1's.
  for (auto& t : touching.triangles) {
    for (auto& v : t) {
      for (std::int32_t w = 0; w < static_cast<std::int32_t>(b1.num_vertices()); ++w) {
        if (v >= static_cast<std::int32_t>(b1.num_vertices()) &&
            (touching.vertices[v] - touching.vertices[w]).norm() < 1e-12) {
          v = w;
        }
      }
    }
  }
  EXPECT_TRUE(is_closed(touching));
  EXPECT_FALSE(is_manifold(touching));
  EXPECT_TRUE(does_self_intersect(touching));
  expect_boolean_error(touching, "not manifold");

  // Two overlapping boxes merged without a Boolean: closed and manifold, but self-intersecting.
  const TriMesh c2 = make_box(Vec3(0.5, 0.5, 0.5), Vec3(1.5, 1.5, 1.5), 1);
  const TriMesh overlapping = geometry::merge_meshes({&b1, &c2});
  EXPECT_TRUE(is_closed(overlapping));
  EXPECT_TRUE(is_manifold(overlapping));
  EXPECT_TRUE(does_self_intersect(overlapping));
  expect_boolean_error(overlapping, "intersects itself");

  TriMesh inward = b1;
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  EXPECT_LT(volume(inward), 0.0);
  expect_boolean_error(inward, "not outward");

  EXPECT_THROW((void)volume(open, "open box"), Error);
}

}  // namespace
}  // namespace hipfai::anatomy
