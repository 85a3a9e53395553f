// The angular walk of the one-pass cylindrical query (CylindricalTable::nearest_crossing) finds
// the same nearest crossing as offering every candidate of the circle's ring cell: the same
// triangle, angle and distance to the bit. Circles are taken at the mobile vertices of random
// scenes and, the hard cases, with the vertex angle put exactly on, and 1e-15 .. 1e-3 rad either
// side of, each candidate's extent borders and crossings, at +-pi, on a box whose circles run
// through its edges and corners, around triangles that reach the axis, after a deformation update
// and a reload; the one-pass query with and without the walk, and given the pose instead of a
// posed copy, with and without the outside regions (cylindrical_outside_regions_test.cpp), and over
// vertex clusters (vertex_clusters_test.cpp),
// reports the same pairs on random scenes, the real CT bones and a generated hip.
#include "contact/cylindrical_cache_io.h"
#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "contact/detail/ablation.h"
#include "geometry/hip_generator.h"
#include "geometry/mesh_io.h"
#include "geometry/primitive_meshes.h"
#include "random_shapes.h"
#include "tests/oracle_sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>
#include <unistd.h>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;
using test_shapes::random_pose;
using test_shapes::random_shape;
using test_shapes::random_unit;

// The reference: every candidate of the cell offered.
NearestCrossing every_candidate(const CylindricalTable& table, double r, double z, double theta) {
  NearestCrossing nearest;
  std::array<double, 2> angles{};
  table.for_each_candidate(r, z, [&](std::int32_t t) {
    const auto& tri = table.triangle(t);
    const int n = circle_triangle_crossings(r, z, table.local_vertex(tri[0]), table.local_vertex(tri[1]),
                                            table.local_vertex(tri[2]), angles);
    for (int i = 0; i < n; ++i) nearest.offer(theta, angles[static_cast<std::size_t>(i)], t);
  });
  return nearest;
}

// Compares the walk with the reference at (r, z, theta); returns 1 if a crossing was found.
int expect_same_nearest(const CylindricalTable& table, double r, double z, double theta, const std::string& what) {
  const NearestCrossing want = every_candidate(table, r, z, theta);
  const NearestCrossing got = table.nearest_crossing(r, z, theta);
  EXPECT_EQ(got.triangle, want.triangle) << what << " r " << r << " z " << z << " theta " << theta;
  EXPECT_EQ(got.crossing_theta_rad, want.crossing_theta_rad) << what;
  EXPECT_EQ(got.abs_delta_rad, want.abs_delta_rad) << what;
  EXPECT_EQ(got.delta_rad, want.delta_rad) << what;
  return want.found() ? 1 : 0;
}

// The circle of `point` at its own angle, and at the hard angles of its cell: each candidate's
// extent borders and crossings, exactly and 1e-15 .. 1e-3 rad either side, and +-pi.
int expect_same_at_hard_angles(const CylindricalTable& table, const Vec3& point, const std::string& what) {
  const Cylindrical cyl = to_cylindrical(table.frame().to_local(point));
  int found = expect_same_nearest(table, cyl.r, cyl.z, cyl.theta, what);
  std::vector<double> borders{std::numbers::pi, -std::numbers::pi + 1e-15, 0.0};
  std::array<double, 2> angles{};
  table.for_each_candidate(cyl.r, cyl.z, [&](std::int32_t t) {
    const auto& tri = table.triangle(t);
    const Vec3& a = table.local_vertex(tri[0]);
    const Vec3& b = table.local_vertex(tri[1]);
    const Vec3& c = table.local_vertex(tri[2]);
    const AngularExtent extent = triangle_angular_extent(a, b, c);
    if (!extent.all_angles()) {
      borders.push_back(extent.lo);
      borders.push_back(extent.lo + extent.width);
    }
    const int n = circle_triangle_crossings(cyl.r, cyl.z, a, b, c, angles);
    for (int i = 0; i < n; ++i) borders.push_back(angles[static_cast<std::size_t>(i)]);
  });
  for (const double border : borders) {
    for (const double offset : {0.0, 1e-15, -1e-15, 1e-12, -1e-12, 1e-9, -1e-9, 1e-6, -1e-6, 1e-3, -1e-3}) {
      found += expect_same_nearest(table, cyl.r, cyl.z, wrap_angle(border + offset), what);
    }
  }
  return found;
}

void expect_identical_walk(const PenetrationResult& got, const PenetrationResult& want, const std::string& what) {
  ASSERT_EQ(got.status, want.status) << what;
  ASSERT_EQ(got.pairs.size(), want.pairs.size()) << what;
  for (std::size_t i = 0; i < got.pairs.size(); ++i) {
    ASSERT_EQ(got.pairs[i].mobile_vertex, want.pairs[i].mobile_vertex) << what;
    ASSERT_EQ(got.pairs[i].fixed_triangle, want.pairs[i].fixed_triangle) << what;
    ASSERT_EQ(got.pairs[i].depth_mm, want.pairs[i].depth_mm) << what;
    ASSERT_EQ(got.pairs[i].angle_deg, want.pairs[i].angle_deg) << what;
  }
}

// The one-pass query with the walk (with and without the outside regions), without it, and given
// the pose, on 1 and 2 threads.
std::size_t expect_walk_equals_every_candidate(const CylindricalTable& table, const TriMesh& mobile,
                                               const Eigen::Isometry3d& pose, const std::string& what) {
  TriMesh posed = mobile;
  geometry::apply_transform(posed, pose);
  CylindricalQueryOptions one_thread;
  one_thread.num_threads = 1;
  detail::CylindricalAblation every;
  every.angular_walk = false;
  every.outside_regions = false;
  every.mobile_clusters = false;
  const PenetrationResult want = detail::cylindrical_segmenting(table, posed, one_thread, every);
  for (const int threads : {1, 2}) {
    for (const int variant : {0, 1, 2, 3}) {
      CylindricalQueryOptions options;
      options.num_threads = threads;
      detail::CylindricalAblation walk;
      walk.outside_regions = (variant & 1) != 0;
      walk.mobile_clusters = (variant & 2) != 0;
      const std::string label = what + ", " + std::to_string(threads) + " thread(s)" +
                                (walk.outside_regions ? ", regions" : "") + (walk.mobile_clusters ? ", clusters" : "");
      expect_identical_walk(detail::cylindrical_segmenting(table, posed, options, walk), want, label + ", posed copy");
      expect_identical_walk(detail::cylindrical_segmenting(table, mobile, pose, options, walk), want, label + ", pose given");
    }
    for (const std::size_t cluster_size : {1, 5, 32}) {
      CylindricalQueryOptions walk;
      walk.num_threads = threads;
      expect_identical_walk(cylindrical_segmenting(table, VertexClusters::build(mobile, cluster_size), pose, walk), want,
                       what + ", clusters of " + std::to_string(cluster_size));
    }
  }
  return want.pairs.size();
}

TEST(CylindricalAngularWalk, NearestCrossingEqualsEveryCandidateOnRandomScenes) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int found = 0;
  for (int trial = 0; trial < 15; ++trial) {
    const TriMesh fixed = random_shape(rng, trial % 3);
    const TriMesh mobile = random_shape(rng, (trial / 3) % 3);
    // Every third axis runs through the fixed shape's centroid, so triangles reach the axis and
    // take the all-angle list.
    Vec3 centroid = Vec3::Zero();
    for (const Vec3& p : fixed.vertices) centroid += p;
    centroid /= static_cast<double>(fixed.vertices.size());
    const Vec3 centre = trial % 3 == 0 ? centroid : Vec3(20 * u(rng) - 10, 20 * u(rng) - 10, 20 * u(rng) - 10);
    const Vec3 axis = random_unit(rng);
    CylindricalTableOptions options;
    options.resolution_r_mm = geometry::mean_edge_length(fixed) * (0.3 + 3 * u(rng));
    options.resolution_z_mm = geometry::mean_edge_length(fixed) * (0.3 + 3 * u(rng));
    const CylindricalTable table = CylindricalTable::build(fixed, centre, axis, options);
    const std::string what = "trial " + std::to_string(trial);
    for (std::size_t v = 0; v < mobile.vertices.size(); v += 11 * static_cast<std::size_t>(test::kOracleThinning)) {
      found += expect_same_at_hard_angles(table, mobile.vertices[v], what);
    }
    expect_walk_equals_every_candidate(table, mobile, random_pose(rng, 3.0), what);
  }
  EXPECT_GT(found, 2000 / test::kOracleThinning);  // the circles really cross the shapes
}

TEST(CylindricalAngularWalk, OnePassQueryEqualsEveryCandidateOnCollidingScenes) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t reported = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const TriMesh fixed = random_shape(rng, trial % 3);
    const TriMesh mobile = random_shape(rng, (trial / 3) % 3);
    const Vec3 centre(10 * u(rng) - 5, 10 * u(rng) - 5, 10 * u(rng) - 5);
    const Vec3 axis = random_unit(rng);
    // A table restricted to the mobile mesh, queried at rotations about the axis (the benchmark's
    // use), and a full table at a random rigid pose.
    const CylindricalTable restricted = CylindricalTable::build(fixed, centre, axis, {}, &mobile);
    Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
    turn.linear() = Eigen::AngleAxisd(2.0 * std::numbers::pi * u(rng), axis).toRotationMatrix();
    turn = Eigen::Translation3d(centre) * turn * Eigen::Translation3d(-centre);
    const std::string what = "trial " + std::to_string(trial);
    reported += expect_walk_equals_every_candidate(restricted, mobile, turn, what + " restricted");
    const CylindricalTable full = CylindricalTable::build(fixed, centre, axis);
    reported += expect_walk_equals_every_candidate(full, mobile, random_pose(rng, 4.0), what + " full");
  }
  EXPECT_GT(reported, 500u);  // the scenes really collide
}

TEST(CylindricalAngularWalk, CirclesThroughEdgesAndCornersOfABox) {
  // Vertices at the box's own heights and radii: their circles pass through its edges and
  // corners, where several triangles share a crossing angle (ties broken by triangle index).
  const TriMesh fixed = geometry::make_box(Vec3(2, -3, -4), Vec3(8, 3, 4), 2);
  int found = 0;
  for (const double resolution : {0.0, 0.7, 3.0}) {
    CylindricalTableOptions options;
    options.resolution_r_mm = options.resolution_z_mm = resolution;
    const CylindricalTable table = CylindricalTable::build(fixed, Vec3::Zero(), Vec3::UnitZ(), options);
    for (const double z : {-4.0, -2.0, 0.0, 2.0, 4.0}) {
      for (const double r : {2.0, 5.0, std::hypot(2.0, 3.0), std::hypot(8.0, 3.0), 8.0, 7.0}) {
        for (int k = 0; k < 12; ++k) {
          const double t = 2.0 * std::numbers::pi * k / 12.0;
          found += expect_same_at_hard_angles(table, Vec3(r * std::cos(t), r * std::sin(t), z), "box");
        }
      }
    }
  }
  EXPECT_GT(found, 3000);
}

TEST(CylindricalAngularWalk, UpdatedAndReloadedTablesWalkTheirOwnCells) {
  std::mt19937 rng(8);
  TriMesh fixed = random_shape(rng, 0);
  const TriMesh mobile = random_shape(rng, 1);
  const Vec3 axis = random_unit(rng);
  CylindricalTable table = CylindricalTable::build(fixed, Vec3::Zero(), axis);
  // Move every vertex: the rebinned table's index must follow the new cells and extents.
  std::vector<std::int32_t> all(fixed.triangles.size());
  for (std::size_t t = 0; t < all.size(); ++t) all[t] = static_cast<std::int32_t>(t);
  for (Vec3& p : fixed.vertices) p = 1.3 * p + Vec3(0.5, -0.2, 0.1);
  update_triangles(table, fixed, all);
  const Eigen::Isometry3d pose = random_pose(rng, 3.0);
  expect_walk_equals_every_candidate(table, mobile, pose, "updated");
  for (std::size_t v = 0; v < mobile.vertices.size(); v += 29) {
    expect_same_at_hard_angles(table, mobile.vertices[v], "updated");
  }
  const auto path = std::filesystem::temp_directory_path() /
                    ("hipfai_angular_walk_" + std::to_string(::getpid()) + ".bin");
  save_cylindrical_table(table, path);
  const std::optional<CylindricalTable> loaded = load_cylindrical_table(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(loaded.has_value());
  expect_walk_equals_every_candidate(*loaded, mobile, pose, "reloaded");
  // A table built without the index answers the same (every candidate offered).
  CylindricalTableOptions no_index;
  no_index.angular_index = false;
  const CylindricalTable plain = CylindricalTable::build(fixed, Vec3::Zero(), axis, no_index);
  TriMesh posed = mobile;
  geometry::apply_transform(posed, pose);
  expect_identical_walk(cylindrical_segmenting(plain, posed), cylindrical_segmenting(table, posed), "no index");
}

TEST(CylindricalAngularWalk, RealCtBonesAtSeveralPoses) {
  const std::string folder = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
  const TriMesh pelvis = geometry::read_mesh(folder + "pelvis_no_sacrum.ply");
  const TriMesh femur = geometry::read_mesh(folder + "femur_r.ply");
  const Vec3 hjc(143.80, 243.46, -432.58);
  std::size_t reported = 0;
  int pose_index = 0;  // thinned: every kOracleThinning-th of the 15 (axis, angle) poses
  for (const Vec3& direction : {Vec3(1.0, 0.3, 0.2), Vec3(0.1, 1.0, -0.3), Vec3(0.2, -0.1, 1.0)}) {
    const Vec3 axis = direction.normalized();
    const CylindricalTable table = CylindricalTable::build(pelvis, hjc, axis, {}, &femur);
    for (const double angle_deg : {-60.0, -25.0, 15.0, 40.0, 75.0}) {
      if (pose_index++ % test::kOracleThinning != 0) continue;
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = Eigen::AngleAxisd(angle_deg * std::numbers::pi / 180.0, axis).toRotationMatrix();
      pose = Eigen::Translation3d(hjc) * pose * Eigen::Translation3d(-hjc);
      reported += expect_walk_equals_every_candidate(table, femur, pose, "CT, angle " + std::to_string(angle_deg));
    }
  }
  EXPECT_GT(reported, 0u);
}

TEST(CylindricalWalkOnGeneratedHip, OnePassQueryEqualsEveryCandidateAtSeveralPoses) {
  geometry::HipParameters parameters;
  parameters.ce_deg = 40.0;
  parameters.alpha_deg = 80.0;
  parameters.edge_mm = 5.5;  // the benchmark's coarse hip
  const geometry::HipModel hip = geometry::generate_hip(parameters).model;
  const TriMesh& pelvis = hip.tissue("acetabular_bone");
  const TriMesh& femur = hip.tissue("femur_bone");
  std::size_t reported = 0;
  for (const Vec3& axis : {hip.axes.flexion_axis.normalized(), hip.axes.adduction_axis.normalized()}) {
    const CylindricalTable table = CylindricalTable::build(pelvis, hip.hjc_mm, axis, {}, &femur);
    for (const double angle_deg : {-90.0, -45.0, 30.0, 60.0, 110.0}) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = Eigen::AngleAxisd(angle_deg * std::numbers::pi / 180.0, axis).toRotationMatrix();
      pose = Eigen::Translation3d(hip.hjc_mm) * pose * Eigen::Translation3d(-hip.hjc_mm);
      reported += expect_walk_equals_every_candidate(table, femur, pose, "hip, angle " + std::to_string(angle_deg));
    }
  }
  EXPECT_GT(reported, 0u);  // some pose impinges, or the test would prove little
}

}  // namespace
}  // namespace hipfai::contact
