// The joint range finder against closed forms, the exhaustive oracle, and ever finer stepping.
#include "contact/oracle_cylindrical.h"
#include "contact/range_finder.h"
#include "core/numbers.h"
#include "geometry/mesh_io.h"
#include "geometry/primitive_meshes.h"
#include "tests/contact/random_shapes.h"
#include "tests/oracle_sample.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <string>

namespace hipfai::contact {
namespace {

using test_shapes::random_unit;

using geometry::TriMesh;
using hipfai::kPi;
constexpr double kDeg = 180.0 / kPi;

// Face x = 5 of this box is met by circles of radius 6 (about z through the origin) at
// theta = +-acos(5/6); no other face is.
TriMesh wall() { return geometry::make_box(Vec3(5, -4, -1), Vec3(7, 4, 1), 1); }

TriMesh arc_triangle_at_radius_6() {
  TriMesh mesh;
  for (const auto& [deg, z] : {std::pair{90.0, 0.0}, {91.0, 0.5}, {92.0, 0.0}}) {
    mesh.vertices.emplace_back(6 * std::cos(deg / kDeg), 6 * std::sin(deg / kDeg), z);
  }
  mesh.triangles.push_back({0, 1, 2});
  return mesh;
}

TEST(RangeFinder, ClosedFormMobileVertexLimits) {
  const RangeOfMotion range = range_of_motion(wall(), arc_triangle_at_radius_6(), Vec3::Zero(), Vec3::UnitZ());
  ASSERT_EQ(range.status, QueryStatus::kOk);
  const double crossing_deg = std::acos(5.0 / 6.0) * kDeg;
  // Clockwise the vertex at 90 degrees reaches the face at +33.56; anticlockwise the vertex at 92
  // degrees reaches it at -33.56 = 326.44. 1e-9 degrees: rounding of acos/atan2 only.
  EXPECT_NEAR(range.clockwise_deg, 90.0 - crossing_deg, 1e-9);
  EXPECT_NEAR(range.anticlockwise_deg, 360.0 - crossing_deg - 92.0, 1e-9);
  EXPECT_EQ(range.clockwise_limit.kind, ContactKind::kMobileVertexOnFixedTriangle);
  EXPECT_EQ(range.clockwise_limit.vertex, 0);
  EXPECT_EQ(range.anticlockwise_limit.vertex, 2);
  const RangeOfMotion oracle = oracle_range_of_motion(wall(), arc_triangle_at_radius_6(), Vec3::Zero(), Vec3::UnitZ());
  EXPECT_NEAR(oracle.clockwise_deg, range.clockwise_deg, 1e-9);
  EXPECT_NEAR(oracle.anticlockwise_deg, range.anticlockwise_deg, 1e-9);
}

TEST(RangeFinder, ClosedFormFixedVertexLimits) {
  // Roles swapped: the box turns, the triangle stays. The box turning anticlockwise moves the
  // triangle's vertices clockwise relative to it, so the anticlockwise range is 90 - 33.56.
  const TriMesh box = wall();
  const TriMesh triangle = arc_triangle_at_radius_6();
  const RangeOfMotion range = range_of_motion(triangle, box, Vec3::Zero(), Vec3::UnitZ());
  const double crossing_deg = std::acos(5.0 / 6.0) * kDeg;
  EXPECT_NEAR(range.anticlockwise_deg, 90.0 - crossing_deg, 1e-9);
  EXPECT_NEAR(range.clockwise_deg, 360.0 - crossing_deg - 92.0, 1e-9);
  EXPECT_EQ(range.anticlockwise_limit.kind, ContactKind::kFixedVertexOnMobileTriangle);
  EXPECT_EQ(range.anticlockwise_limit.vertex, 0);
  EXPECT_EQ(range.clockwise_limit.vertex, 2);
  // Without the swapped pass nothing limits the box: its corners never meet the triangle.
  RangeOfMotionOptions options;
  options.include_fixed_vertices = false;
  const RangeOfMotion vertices_only = range_of_motion(triangle, box, Vec3::Zero(), Vec3::UnitZ(), options);
  EXPECT_EQ(vertices_only.anticlockwise_deg, 360.0);
  EXPECT_EQ(vertices_only.anticlockwise_limit.kind, ContactKind::kNone);
}

TEST(RangeFinder, RestingContactLimitsOnlyTheEnteringDirection) {
  // A vertex exactly on the face x = 5 at theta = +33.56 degrees: turning clockwise enters the
  // box at once; anticlockwise it travels to the other crossing at -33.56.
  TriMesh point;
  point.vertices = {Vec3(5, std::sqrt(11.0), 0)};
  point.triangles = {{0, 0, 0}};
  const RangeOfMotion range = range_of_motion(wall(), point, Vec3::Zero(), Vec3::UnitZ());
  EXPECT_EQ(range.clockwise_deg, 0.0);
  EXPECT_NEAR(range.anticlockwise_deg, 360.0 - 2 * std::acos(5.0 / 6.0) * kDeg, 1e-9);
  const RangeOfMotion oracle = oracle_range_of_motion(wall(), point, Vec3::Zero(), Vec3::UnitZ());
  EXPECT_EQ(oracle.clockwise_deg, 0.0);
  EXPECT_NEAR(oracle.anticlockwise_deg, range.anticlockwise_deg, 1e-9);
}

// Collision-free start: a small perturbed sphere (mobile) beside a box or torus (fixed), with a
// random centre between them and a random axis.
struct RangeScene {
  TriMesh fixed, mobile;
  Vec3 centre, axis;
};

// Exact-enough static test (generic positions): does segment pq cross the closed triangle abc?
// Signed volumes: p and q on opposite sides of the plane (or on it), and the line pq passing
// inside the three edges.
double orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).cross(c - a).dot(d - a);
}
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double o1 = orient(a, b, c, p), o2 = orient(a, b, c, q);
  if ((o1 > 0 && o2 > 0) || (o1 < 0 && o2 < 0)) return false;
  const double e1 = orient(p, q, a, b), e2 = orient(p, q, b, c), e3 = orient(p, q, c, a);
  return (e1 >= 0 && e2 >= 0 && e3 >= 0) || (e1 <= 0 && e2 <= 0 && e3 <= 0);
}
// Two non-coplanar triangles intersect iff an edge of one crosses the other.
bool triangles_intersect(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u) {
  for (int k = 0; k < 3; ++k) {
    if (segment_crosses_triangle(t[k], t[(k + 1) % 3], u[0], u[1], u[2])) return true;
    if (segment_crosses_triangle(u[k], u[(k + 1) % 3], t[0], t[1], t[2])) return true;
  }
  return false;
}
// Brute force: any triangle of the rotated mobile mesh meets any fixed triangle (the surfaces
// touch or cross: any first contact, vertex-face or edge-edge).
bool surfaces_intersect(const TriMesh& fixed, const TriMesh& mobile, const Vec3& centre, const Vec3& axis,
                        double angle_deg) {
  TriMesh posed = mobile;
  geometry::rotate_about_axis(posed, centre, axis, angle_deg / kDeg);
  auto corners = [](const TriMesh& m, const std::array<std::int32_t, 3>& tri) {
    return std::array<Vec3, 3>{m.vertices[static_cast<std::size_t>(tri[0])], m.vertices[static_cast<std::size_t>(tri[1])],
                               m.vertices[static_cast<std::size_t>(tri[2])]};
  };
  for (const auto& tf : fixed.triangles) {
    const auto a = corners(fixed, tf);
    for (const auto& tm : posed.triangles) {
      if (triangles_intersect(a, corners(posed, tm))) return true;
    }
  }
  return false;
}

bool penetrates(const RangeScene& scene, double angle_deg) {
  TriMesh posed = scene.mobile;
  geometry::rotate_about_axis(posed, scene.centre, scene.axis, angle_deg / kDeg);
  return !oracle_cylindrical(scene.fixed, posed, scene.centre, scene.axis).pairs.empty() ||
         !oracle_cylindrical(posed, scene.fixed, scene.centre, scene.axis).pairs.empty();
}

RangeScene random_scene(std::mt19937& rng, int levels) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (;;) {
    RangeScene scene;
    scene.fixed = u(rng) < 0.5 ? geometry::make_box(Vec3(-4, -3, -5), Vec3(4, 3, 5), 2)
                               : geometry::make_torus(Vec3::Zero(), 6.0, 2.0, 12, 6);
    scene.mobile = geometry::make_octasphere(Vec3::Zero(), 3.0 + 2 * u(rng), levels);
    for (Vec3& p : scene.mobile.vertices) p = p * (1.0 + 0.15 * (u(rng) - 0.5)) + Vec3(12, 0, 0);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(2 * kPi * u(rng), random_unit(rng)).toRotationMatrix();
    geometry::apply_transform(scene.mobile, pose);
    scene.centre = Vec3(4 * u(rng) - 2, 4 * u(rng) - 2, 4 * u(rng) - 2);
    scene.axis = random_unit(rng);
    if (!penetrates(scene, 0.0)) return scene;
  }
}

TEST(RangeFinder, EqualsOracleOnRandomScenes) {
  std::mt19937 rng(31);
  int limited = 0;
  for (int trial = 0; trial < 25; ++trial) {
    const RangeScene scene = random_scene(rng, 3);
    // The oracle enumerates vertex contacts only: compare the finder's vertex passes with it.
    RangeOfMotionOptions vertex_contacts;
    vertex_contacts.include_edge_edge = false;
    const RangeOfMotion range = range_of_motion(scene.fixed, scene.mobile, scene.centre, scene.axis, vertex_contacts);
    const RangeOfMotion oracle = oracle_range_of_motion(scene.fixed, scene.mobile, scene.centre, scene.axis);
    const std::string what = "trial " + std::to_string(trial);
    ASSERT_EQ(range.status, QueryStatus::kOk) << what;
    // Same crossings evaluated by the same closed form: equal up to rounding.
    EXPECT_NEAR(range.anticlockwise_deg, oracle.anticlockwise_deg, 1e-9) << what;
    EXPECT_NEAR(range.clockwise_deg, oracle.clockwise_deg, 1e-9) << what;
    EXPECT_EQ(range.anticlockwise_limit.kind, oracle.anticlockwise_limit.kind) << what;
    EXPECT_EQ(range.anticlockwise_limit.vertex, oracle.anticlockwise_limit.vertex) << what;
    EXPECT_EQ(range.clockwise_limit.vertex, oracle.clockwise_limit.vertex) << what;
    limited += range.anticlockwise_deg < 360.0;
  }
  EXPECT_GT(limited, 10);
}

// The full finder (vertex and edge-edge contacts) against stepping with an exact static test of
// the surfaces (every triangle pair), an independent reference that sees every kind of contact.
TEST(RangeFinder, FinerSteppingConvergesToTheRangeFromAbove) {
  std::mt19937 rng(77);
  // Thinned (the sanitizer build): the two coarser steps, a quarter of the stepping's cost.
  const std::vector<double> steps =
      test::kOracleSamplesThinned ? std::vector<double>{2.0, 0.5} : std::vector<double>{2.0, 0.5, 0.125};
  int checked = 0, edge_limited = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const RangeScene scene = random_scene(rng, 2);
    const RangeOfMotion range = range_of_motion(scene.fixed, scene.mobile, scene.centre, scene.axis);
    edge_limited += (range.anticlockwise_limit.kind == ContactKind::kEdgeOnEdge) +
                    (range.clockwise_limit.kind == ContactKind::kEdgeOnEdge);
    for (const double direction : {1.0, -1.0}) {
      const double exact = direction > 0 ? range.anticlockwise_deg : range.clockwise_deg;
      if (exact >= 200.0) continue;  // keep the stepping short
      double previous_error = 1e300;
      for (const double step : steps) {
        int k = 1;
        while (k * step < 360.0 &&
               !surfaces_intersect(scene.fixed, scene.mobile, scene.centre, scene.axis, direction * k * step)) {
          ++k;
        }
        const double first = k * step;
        // The first penetrating step is at or after the first contact, and the step before it is
        // not (1e-9: rounding of the exact angle).
        EXPECT_LE(exact, first + 1e-9) << "trial " << trial << " step " << step;
        EXPECT_GT(exact, first - step - 1e-9) << "trial " << trial << " step " << step;
        EXPECT_LE(first - exact, previous_error + 1e-9);
        previous_error = first - exact;
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 2 * static_cast<int>(steps.size()));  // at least two limits stepped
  EXPECT_GE(edge_limited, 1);  // the scenes exercise edge-edge first contacts
}

// Two sharp rims, no vertex ever touches: a radial blade edge (3..8 mm along x at z = 0) of the
// mobile wedge turns about z into the vertical rim edge (r = 5 at 60 degrees, z in [-1, 1]) of
// the fixed wedge, meeting it inside both edges at exactly 60 degrees. The vertex-only finder
// sees no contact at all; the edge-edge pass finds the closed form.
TEST(RangeFinder, EdgeEdgeFirstContactOfSharpRims) {
  auto at = [](double r, double deg, double z) { return Vec3(r * std::cos(deg / kDeg), r * std::sin(deg / kDeg), z); };
  TriMesh fixed;  // tetrahedron: rim edge A-B, body behind it (larger azimuth, r in [4.6, 5])
  fixed.vertices = {at(5, 60, -1), at(5, 60, 1), at(4.6, 75, 0.5), at(4.6, 75, -0.5)};
  TriMesh mobile;  // tetrahedron: blade edge P0-P1, body behind it (negative azimuth), |z| <= 0.1
  mobile.vertices = {Vec3(3, 0, 0), Vec3(8, 0, 0), Vec3(5.5, -0.3, 0.1), Vec3(5.5, -0.3, -0.1)};
  for (TriMesh* mesh : {&fixed, &mobile}) {
    mesh->triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
    if (geometry::signed_volume(*mesh) < 0) {
      for (auto& tri : mesh->triangles) std::swap(tri[1], tri[2]);
    }
  }
  RangeOfMotionOptions vertex_contacts;
  vertex_contacts.include_edge_edge = false;
  const RangeOfMotion vertices_only = range_of_motion(fixed, mobile, Vec3::Zero(), Vec3::UnitZ(), vertex_contacts);
  EXPECT_EQ(vertices_only.anticlockwise_limit.kind, ContactKind::kNone);
  const RangeOfMotion range = range_of_motion(fixed, mobile, Vec3::Zero(), Vec3::UnitZ());
  // Closed form 60 degrees; 1e-9: rounding of atan2/acos.
  EXPECT_NEAR(range.anticlockwise_deg, 60.0, 1e-9);
  ASSERT_EQ(range.anticlockwise_limit.kind, ContactKind::kEdgeOnEdge);
  EXPECT_EQ(range.anticlockwise_limit.mobile_edge, (std::array<std::int32_t, 2>{0, 1}));
  EXPECT_EQ(range.anticlockwise_limit.fixed_edge, (std::array<std::int32_t, 2>{0, 1}));
  // Both directions against stepping with the exact surface test: the first intersecting step
  // is at or after the exact angle and less than a step after it.
  for (const double direction : {1.0, -1.0}) {
    const double exact = direction > 0 ? range.anticlockwise_deg : range.clockwise_deg;
    const double step = 0.05;
    int k = 1;
    while (k * step < 360.0 && !surfaces_intersect(fixed, mobile, Vec3::Zero(), Vec3::UnitZ(), direction * k * step)) ++k;
    EXPECT_LE(exact, k * step + 1e-9) << direction;
    EXPECT_GT(exact, (k - 1) * step - 1e-9) << direction;
  }
}

TEST(RangeFinder, FanAndSphereOfAxes) {
  std::mt19937 rng(5);
  const RangeScene scene = random_scene(rng, 2);
  RangeOfMotionOptions vertex_contacts;  // the oracle enumerates vertex contacts only
  vertex_contacts.include_edge_edge = false;
  const std::vector<AxisRangeOfMotion> fan =
      range_of_motion_fan(scene.fixed, scene.mobile, scene.centre, Vec3(0, 0, 2), 6, vertex_contacts);
  ASSERT_EQ(fan.size(), 6u);
  for (std::size_t i = 0; i < fan.size(); ++i) {
    EXPECT_NEAR(fan[i].axis.norm(), 1.0, 1e-15);
    EXPECT_NEAR(fan[i].axis.z(), 0.0, 1e-15);  // in the plane normal to z
    EXPECT_DOUBLE_EQ(fan[i].angle_deg, 30.0 * static_cast<double>(i));
    const RangeOfMotion oracle = oracle_range_of_motion(scene.fixed, scene.mobile, scene.centre, fan[i].axis);
    EXPECT_NEAR(fan[i].range.anticlockwise_deg, oracle.anticlockwise_deg, 1e-9);
    EXPECT_NEAR(fan[i].range.clockwise_deg, oracle.clockwise_deg, 1e-9);
  }
  const std::vector<AxisRangeOfMotion> sphere =
      range_of_motion_sphere(scene.fixed, scene.mobile, scene.centre, Vec3(0, 1, 0), 2, 4);
  ASSERT_EQ(sphere.size(), 9u);  // the pole plus 2 rings of 4
  EXPECT_NEAR((sphere[0].axis - Vec3(0, 1, 0)).norm(), 0.0, 1e-15);
  for (const auto& entry : sphere) {
    EXPECT_NEAR(entry.axis.norm(), 1.0, 1e-15);
    EXPECT_NEAR(std::acos(entry.axis.y()) * kDeg, entry.angle_deg, 1e-6);
    EXPECT_EQ(entry.range.status, QueryStatus::kOk);
  }
  // An axis and its opposite: same motion, directions swapped.
  const RangeOfMotion forward = range_of_motion(scene.fixed, scene.mobile, scene.centre, scene.axis);
  const RangeOfMotion backward = range_of_motion(scene.fixed, scene.mobile, scene.centre, -scene.axis);
  EXPECT_NEAR(forward.anticlockwise_deg, backward.clockwise_deg, 1e-9);
  EXPECT_NEAR(forward.clockwise_deg, backward.anticlockwise_deg, 1e-9);
}

// Points of `mesh` as a mesh of zero-area triangles (i, i, i): only the vertices can touch.
TriMesh subsample(const TriMesh& mesh, std::size_t every, const std::set<std::int32_t>& extra,
                  std::vector<std::int32_t>& original) {
  std::set<std::int32_t> chosen(extra);
  for (std::size_t v = 0; v < mesh.vertices.size(); v += every) chosen.insert(static_cast<std::int32_t>(v));
  TriMesh points;
  original.assign(chosen.begin(), chosen.end());
  for (std::int32_t v : original) {
    points.vertices.push_back(mesh.vertices[static_cast<std::size_t>(v)]);
    const auto i = static_cast<std::int32_t>(points.vertices.size() - 1);
    points.triangles.push_back({i, i, i});
  }
  return points;
}

TEST(RangeFinder, RealFemurAgainstPelvisMatchesOracleOnSubsamples) {
  const std::string folder = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
  const TriMesh pelvis = geometry::read_mesh(folder + "pelvis_no_sacrum.ply");
  const TriMesh femur = geometry::read_mesh(folder + "femur_r.ply");
  const Vec3 hjc(143.80, 243.46, -432.58), axis(0, 0, 1);
  const RangeOfMotion full = range_of_motion(pelvis, femur, hjc, axis);
  ASSERT_LT(full.anticlockwise_deg, 360.0);
  ASSERT_LT(full.clockwise_deg, 360.0);
  // Limiting vertices of each kind, so the subsampled problems keep the true limits.
  std::set<std::int32_t> femur_extra, pelvis_extra;
  for (const LimitingContact& limit : {full.anticlockwise_limit, full.clockwise_limit}) {
    (limit.kind == ContactKind::kMobileVertexOnFixedTriangle ? femur_extra : pelvis_extra).insert(limit.vertex);
  }
  // Femur points against pelvis triangles; pelvis points against femur triangles.
  std::vector<std::int32_t> femur_ids, pelvis_ids;
  const auto thin = static_cast<std::size_t>(test::kOracleThinning);
  const TriMesh femur_points = subsample(femur, 240 * thin, femur_extra, femur_ids);
  const TriMesh pelvis_points = subsample(pelvis, 320 * thin, pelvis_extra, pelvis_ids);
  RangeOfMotionOptions vertices_only;
  vertices_only.include_fixed_vertices = false;
  const RangeOfMotion mobile_fast = range_of_motion(pelvis, femur_points, hjc, axis, vertices_only);
  const RangeOfMotion mobile_oracle = oracle_range_of_motion(pelvis, femur_points, hjc, axis, false);
  const RangeOfMotion fixed_fast = range_of_motion(pelvis_points, femur, hjc, axis);
  const RangeOfMotion fixed_oracle = oracle_range_of_motion(pelvis_points, femur, hjc, axis, true);
  // Same closed form on the same coordinates: equal to rounding (1e-9 degrees).
  EXPECT_NEAR(mobile_fast.anticlockwise_deg, mobile_oracle.anticlockwise_deg, 1e-9);
  EXPECT_NEAR(mobile_fast.clockwise_deg, mobile_oracle.clockwise_deg, 1e-9);
  EXPECT_NEAR(fixed_fast.anticlockwise_deg, fixed_oracle.anticlockwise_deg, 1e-9);
  EXPECT_NEAR(fixed_fast.clockwise_deg, fixed_oracle.clockwise_deg, 1e-9);
  // The full range is the smaller of the two contact types, and the subsamples keep its limits.
  EXPECT_NEAR(full.anticlockwise_deg,
              std::min(mobile_oracle.anticlockwise_deg, fixed_oracle.anticlockwise_deg), 1e-9);
  EXPECT_NEAR(full.clockwise_deg, std::min(mobile_oracle.clockwise_deg, fixed_oracle.clockwise_deg), 1e-9);
}

TEST(RangeFinder, InvalidInput) {
  EXPECT_EQ(range_of_motion(wall(), wall(), Vec3::Zero(), Vec3::Zero()).status, QueryStatus::kInvalidInput);
  EXPECT_EQ(oracle_range_of_motion(wall(), wall(), Vec3::Zero(), Vec3::Zero()).status,
            QueryStatus::kInvalidInput);
  EXPECT_EQ(range_of_motion_fan(wall(), wall(), Vec3::Zero(), Vec3::UnitZ(), 0)[0].range.status,
            QueryStatus::kInvalidInput);
}

}  // namespace
}  // namespace hipfai::contact
