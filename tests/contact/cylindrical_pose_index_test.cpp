// The pose cache's arc index (cylindrical_segmenting.h) returns exactly what the pass over every
// tracked vertex returns: same pairs, same triangles, same depths to the bit. Angles are drawn at
// random and, the hard cases, exactly on and around every crossing of sampled vertices (where a
// vertex starts or stops penetrating), with the default and a zero touching tolerance, on closed
// random shapes, on a box whose circles run through its edges and corners, on a reloaded cache
// and on the real CT bones.
#include "core/numbers.h"
#include "contact/cylindrical_cache_io.h"
#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "geometry/mesh_io.h"
#include "geometry/primitive_meshes.h"
#include "random_shapes.h"

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
using test_shapes::random_shape;
using test_shapes::random_unit;
using hipfai::kDegPerRad;

void expect_identical_indexed(const PenetrationResult& got, const PenetrationResult& want, const std::string& what) {
  ASSERT_EQ(got.status, want.status) << what;
  ASSERT_EQ(got.pairs.size(), want.pairs.size()) << what;
  for (std::size_t i = 0; i < got.pairs.size(); ++i) {
    ASSERT_EQ(got.pairs[i].mobile_vertex, want.pairs[i].mobile_vertex) << what;
    ASSERT_EQ(got.pairs[i].fixed_triangle, want.pairs[i].fixed_triangle) << what;
    ASSERT_EQ(got.pairs[i].depth_mm, want.pairs[i].depth_mm) << what;
    ASSERT_EQ(got.pairs[i].angle_deg, want.pairs[i].angle_deg) << what;
  }
}

// Random angles, plus each sampled vertex's crossings approached from both sides: the pose angle
// that puts the vertex exactly on a crossing, and 1e-15 .. 1e-3 rad either way.
std::vector<double> hard_angles_deg(const CylindricalPoseCache& cache, std::mt19937& rng, int samples) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> angles;
  for (int i = 0; i < 40; ++i) angles.push_back(720.0 * u(rng) - 360.0);
  const auto& tracked = cache.tracked();
  if (tracked.empty()) return angles;
  for (int s = 0; s < samples; ++s) {
    const auto& vertex = tracked[static_cast<std::size_t>(u(rng) * static_cast<double>(tracked.size())) % tracked.size()];
    for (std::size_t k = vertex.first; k < vertex.last; ++k) {
      const double on = cache.crossing_theta_rad(k) - vertex.theta0_rad;
      for (const double offset : {0.0, 1e-15, 1e-13, 1e-12, 1e-11, 1e-9, 1e-6, 1e-3}) {
        angles.push_back((on + offset) * kDegPerRad);
        angles.push_back((on - offset) * kDegPerRad);
      }
    }
  }
  return angles;
}

std::size_t expect_index_equals_full_pass(const CylindricalPoseCache& cache, const std::vector<double>& angles,
                                          const std::string& what) {
  std::size_t reported = 0;
  for (const double angle : angles) {
    const PenetrationResult full = cache.query_every_vertex(angle);
    expect_identical_indexed(cache.query(angle), full, what + ", angle " + std::to_string(angle) + " deg");
    reported += full.pairs.size();
  }
  return reported;
}

TEST(CylindricalPoseIndex, EqualsTheFullPassOnRandomScenes) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t reported = 0;
  for (int trial = 0; trial < 18; ++trial) {
    const TriMesh fixed = random_shape(rng, trial % 3);
    const TriMesh mobile = random_shape(rng, (trial / 3) % 3);
    const Vec3 centre(10 * u(rng) - 5, 10 * u(rng) - 5, 10 * u(rng) - 5);
    const Vec3 axis = random_unit(rng);
    const CylindricalTable table = CylindricalTable::build(fixed, centre, axis, {}, &mobile);
    for (const double touching : {kDefaultTouchingMm, 0.0}) {
      CylindricalQueryOptions options;
      options.touching_mm = touching;
      const CylindricalPoseCache cache(table, mobile, options);
      reported += expect_index_equals_full_pass(cache, hard_angles_deg(cache, rng, 30),
                                                "trial " + std::to_string(trial) + ", touching " + std::to_string(touching));
    }
  }
  EXPECT_GT(reported, 20000u);  // the scenes really collide
}

TEST(CylindricalPoseIndex, WithoutTheIndexTheQueryIsTheFullPass) {
  // What the range finder builds (pose_index = false): no arcs, the same answers.
  std::mt19937 rng(5);
  const TriMesh fixed = random_shape(rng, 1);
  const TriMesh mobile = random_shape(rng, 0);
  const CylindricalTable table = CylindricalTable::build(fixed, Vec3(1, 2, 3), random_unit(rng), {}, &mobile);
  CylindricalQueryOptions options;
  options.pose_index = false;
  const CylindricalPoseCache plain(table, mobile, options);
  const CylindricalPoseCache indexed(table, mobile);
  EXPECT_EQ(plain.num_candidate_arcs(), 0u);
  EXPECT_GT(indexed.num_candidate_arcs(), 0u);
  std::size_t reported = 0;
  for (double angle = -180.0; angle < 180.0; angle += 7.5) {
    expect_identical_indexed(plain.query(angle), indexed.query(angle), "angle " + std::to_string(angle));
    reported += plain.query(angle).pairs.size();
  }
  EXPECT_GT(reported, 0u);
}

TEST(CylindricalPoseIndex, CirclesThroughEdgesAndCorners) {
  // An axis-aligned box about the z axis, and a mobile grid whose vertices sit at the box's own
  // heights and radii: their circles pass through its edges and corners, where two or three
  // triangles share a crossing angle.
  const TriMesh fixed = geometry::make_box(Vec3(2, -3, -4), Vec3(8, 3, 4), 2);
  TriMesh mobile;
  for (const double z : {-4.0, -2.0, 0.0, 2.0, 4.0}) {
    for (const double r : {2.0, 5.0, std::hypot(2.0, 3.0), std::hypot(8.0, 3.0), 8.0, 7.0}) {
      for (int k = 0; k < 12; ++k) {
        const double t = 2.0 * std::numbers::pi * k / 12.0;
        mobile.vertices.emplace_back(r * std::cos(t), r * std::sin(t), z);
      }
    }
  }
  const CylindricalTable table = CylindricalTable::build(fixed, Vec3::Zero(), Vec3::UnitZ(), {}, &mobile);
  std::mt19937 rng(3);
  for (const double touching : {kDefaultTouchingMm, 0.0}) {
    CylindricalQueryOptions options;
    options.touching_mm = touching;
    const CylindricalPoseCache cache(table, mobile, options);
    ASSERT_GT(cache.tracked().size(), 100u);
    EXPECT_GT(expect_index_equals_full_pass(cache, hard_angles_deg(cache, rng, 100), "box"), 500u);
  }
}

TEST(CylindricalPoseIndex, ReloadedCacheOnTheRealCtBones) {
  // The CT femur against its pelvis, rotated about an oblique axis through the HJC, so the
  // femur's circles sweep through the socket, the rim and the pelvis beyond.
  const std::string folder = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
  const TriMesh pelvis = geometry::read_mesh(folder + "pelvis_no_sacrum.ply");
  const TriMesh femur = geometry::read_mesh(folder + "femur_r.ply");
  const Vec3 hjc(143.80, 243.46, -432.58);
  const Vec3 axis = Vec3(1.0, 0.3, 0.2).normalized();
  const CylindricalTable table = CylindricalTable::build(pelvis, hjc, axis, {}, &femur);
  const CylindricalPoseCache cache(table, femur);
  std::mt19937 rng(11);
  const std::vector<double> angles = hard_angles_deg(cache, rng, 60);
  EXPECT_GT(expect_index_equals_full_pass(cache, angles, "CT bones"), 1000u);
  EXPECT_GT(cache.num_candidate_arcs(), 0u);

  const auto path = std::filesystem::temp_directory_path() /
                    ("hipfai_pose_index_" + std::to_string(::getpid()) + ".bin");
  save_pose_cache(cache, path);
  const std::optional<CylindricalPoseCache> loaded = load_pose_cache(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->num_candidate_arcs(), cache.num_candidate_arcs());
  for (const double angle : angles) {
    expect_identical_indexed(loaded->query(angle), cache.query_every_vertex(angle), "reloaded, angle " + std::to_string(angle));
  }
  // Angles beyond the index's range take the full pass; the answer is the same.
  expect_identical_indexed(cache.query(1e6 + 30.0), cache.query_every_vertex(1e6 + 30.0), "huge angle");
}

}  // namespace
}  // namespace hipfai::contact
