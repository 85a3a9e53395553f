// The joint range finder against closed forms, the exhaustive oracle, and ever finer stepping.
#include "contact/range_finder.h"
#include "contact/oracle_cylindrical.h"
#include "geometry/mesh_io.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <string>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;
constexpr double kPi = std::numbers::pi;
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

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  return Vec3(normal(rng), normal(rng), normal(rng)).normalized();
}

// Collision-free start: a small perturbed sphere (mobile) beside a box or torus (fixed), with a
// random centre between them and a random axis.
struct Scene {
  TriMesh fixed, mobile;
  Vec3 centre, axis;
};

bool penetrates(const Scene& scene, double angle_deg) {
  TriMesh posed = scene.mobile;
  geometry::rotate_about_axis(posed, scene.centre, scene.axis, angle_deg / kDeg);
  return !oracle_cylindrical(scene.fixed, posed, scene.centre, scene.axis).pairs.empty() ||
         !oracle_cylindrical(posed, scene.fixed, scene.centre, scene.axis).pairs.empty();
}

Scene random_scene(std::mt19937& rng, int levels) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (;;) {
    Scene scene;
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
    const Scene scene = random_scene(rng, 3);
    const RangeOfMotion range = range_of_motion(scene.fixed, scene.mobile, scene.centre, scene.axis);
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

TEST(RangeFinder, FinerSteppingConvergesToTheRangeFromAbove) {
  std::mt19937 rng(77);
  int checked = 0;
  for (int trial = 0; trial < 3; ++trial) {
    const Scene scene = random_scene(rng, 2);
    const RangeOfMotion range = range_of_motion(scene.fixed, scene.mobile, scene.centre, scene.axis);
    for (const double direction : {1.0, -1.0}) {
      const double exact = direction > 0 ? range.anticlockwise_deg : range.clockwise_deg;
      if (exact >= 200.0) continue;  // keep the stepping short
      double previous_error = 1e300;
      for (const double step : {2.0, 0.5, 0.125}) {
        int k = 1;
        while (k * step < 360.0 && !penetrates(scene, direction * k * step)) ++k;
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
  EXPECT_GE(checked, 6);
}

TEST(RangeFinder, FanAndSphereOfAxes) {
  std::mt19937 rng(5);
  const Scene scene = random_scene(rng, 2);
  const std::vector<AxisRangeOfMotion> fan =
      range_of_motion_fan(scene.fixed, scene.mobile, scene.centre, Vec3(0, 0, 2), 6);
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
  const std::string folder = std::string(HIPFAI_SHARED_DIR) + "/data/real-hips/LHDL_CT/";
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
  const TriMesh femur_points = subsample(femur, 240, femur_extra, femur_ids);
  const TriMesh pelvis_points = subsample(pelvis, 320, pelvis_extra, pelvis_ids);
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
