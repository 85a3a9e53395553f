// Property tests of radial segmenting (contact/radial_segmenting.h) against the exhaustive oracle
// (contact/oracle_radial.h) on random meshes, poses and centres, for every mapping, in both
// configurations, with the role swap, both thread counts, and after deformations; plus the
// sphere-vs-cube scenario of thesis Table 2 against its closed form, with a timing printout.
#include "contact/oracle_radial.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_table.h"

#include "core/error.h"
#include "geometry/primitive_meshes.h"
#include "tests/contact/random_shapes.h"
#include "tests/oracle_sample.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>

namespace hipfai::contact {
namespace {

using test_shapes::flipped;

using geometry::TriMesh;

constexpr std::array<RadialConfiguration, 2> kConfigurations = {
    RadialConfiguration::kMobileInsideFixed, RadialConfiguration::kFixedInsideMobile};

Eigen::Isometry3d random_pose(std::mt19937_64& rng, double translation_mm) {
  std::normal_distribution<double> g;
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.toRotationMatrix();
  pose.translation() = translation_mm * Vec3(g(rng), g(rng), g(rng));
  return pose;
}

// Octasphere whose vertices are moved radially by up to +-`noise` of the radius.
TriMesh noisy_sphere(const Vec3& centre, double radius, int levels, double noise,
                         std::mt19937_64& rng) {
  TriMesh mesh = geometry::make_octasphere(centre, radius, levels);
  std::uniform_real_distribution<double> u(-noise, noise);
  for (auto& v : mesh.vertices) v = centre + (v - centre) * (1.0 + u(rng));
  return mesh;
}

// Identical vertex sets, identical triangles (same tie rule), depths within 1e-9 mm.
void expect_same_radial(const PenetrationResult& got, const PenetrationResult& expected,
                 const std::string& what) {
  ASSERT_EQ(got.status, QueryStatus::kOk) << what << ": " << got.message;
  ASSERT_EQ(got.pairs.size(), expected.pairs.size()) << what;
  for (std::size_t i = 0; i < got.pairs.size(); ++i) {
    ASSERT_EQ(got.pairs[i].mobile_vertex, expected.pairs[i].mobile_vertex) << what;
    EXPECT_EQ(got.pairs[i].fixed_triangle, expected.pairs[i].fixed_triangle) << what;
    // Both evaluate the same primitive on the same numbers; 1e-9 mm is the task's bound.
    EXPECT_NEAR(got.pairs[i].depth_mm, expected.pairs[i].depth_mm, 1e-9) << what;
    EXPECT_GT(got.pairs[i].depth_mm, 0.0) << what;
  }
}

struct RadialScene {
  std::string name;
  TriMesh fixed, mobile;
  Vec3 centre;
};

// Random scenes with penetrations in both configurations.
std::vector<RadialScene> random_scenes(std::mt19937_64& rng) {
  std::vector<RadialScene> scenes;
  std::normal_distribution<double> g;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Isometry3d frame = random_pose(rng, 30.0);
    const Vec3 centre = frame.translation();
    const Vec3 jitter = 0.8 * Vec3(g(rng), g(rng), g(rng));
    // Nested perturbed spheres: the mobile one moved off-centre so some vertices cross.
    RadialScene nested{"nested spheres " + std::to_string(k),
                 noisy_sphere(centre, 25.0, 3, 0.03, rng),
                 noisy_sphere(centre + jitter, 24.0, 3, 0.03, rng), centre + 0.5 * jitter};
    geometry::apply_transform(nested.mobile, Eigen::Isometry3d(Eigen::Translation3d(centre)) *
                                                 random_pose(rng, 0.0) *
                                                 Eigen::Translation3d(-centre));
    scenes.push_back(nested);
    // Socket: a thick shell (outer sphere + inverted inner sphere), a sphere sliding inside.
    TriMesh inner = flipped(noisy_sphere(centre, 24.0, 3, 0.02, rng));
    TriMesh outer = noisy_sphere(centre, 28.0, 2, 0.02, rng);
    RadialScene shell{"shell " + std::to_string(k), geometry::merge_meshes({&inner, &outer}),
                noisy_sphere(centre + jitter, 24.5, 3, 0.03, rng), centre};
    scenes.push_back(shell);
    // Box and torus against spheres, randomly rotated and translated.
    const Eigen::Isometry3d pose = random_pose(rng, 3.0);
    RadialScene box{"box " + std::to_string(k), geometry::make_box(Vec3(-12, -14, -10), Vec3(13, 11, 12), 5),
              noisy_sphere(Vec3(1, 0, 0), 14.0, 3, 0.05, rng), Vec3(0.5, -0.3, 0.2)};
    geometry::apply_transform(box.fixed, frame * pose);
    geometry::apply_transform(box.mobile, frame);
    box.centre = frame * box.centre;
    scenes.push_back(box);
    RadialScene torus{"torus " + std::to_string(k), geometry::make_torus(Vec3::Zero(), 20.0, 6.0, 24, 12),
                noisy_sphere(Vec3(0, 0, 0), 19.0, 3, 0.1, rng), Vec3(0.2, 0.1, -0.3)};
    geometry::apply_transform(torus.fixed, frame * pose);
    geometry::apply_transform(torus.mobile, frame);
    torus.centre = frame * torus.centre;
    scenes.push_back(torus);
  }
  return scenes;
}

TEST(RadialSegmenting, EqualsOracleOnRandomScenesAllMappingsBothConfigurations) {
  std::mt19937_64 rng(42);
  const auto scenes = random_scenes(rng);
  std::size_t total_pairs[2] = {0, 0};
  for (const auto& scene : scenes) {
    for (const auto configuration : kConfigurations) {
      const auto expected = oracle_radial(scene.fixed, scene.mobile, scene.centre, configuration);
      total_pairs[configuration == RadialConfiguration::kMobileInsideFixed ? 0 : 1] +=
          expected.pairs.size();
      for (const auto mapping : kRadialMappings) {
        for (const std::int64_t size : {16, 2000}) {
          const RadialTable table = build_radial_table(scene.fixed, scene.centre, {mapping, size});
          for (const int threads : {1, 2}) {
            RadialQueryOptions options;
            options.configuration = configuration;
            options.num_threads = threads;
            expect_same_radial(radial_segmenting(table, scene.fixed, scene.mobile, options), expected,
                        scene.name + " " + to_string(mapping) + " " + to_string(configuration) +
                            " size " + std::to_string(size));
          }
        }
      }
    }
  }
  // The scenes must exercise both configurations (otherwise equality would be vacuous).
  EXPECT_GT(total_pairs[0], 200u);
  EXPECT_GT(total_pairs[1], 200u);
}

TEST(RadialSegmenting, RoleSwapEqualsOracleWithRolesExchanged) {
  std::mt19937_64 rng(43);
  const auto scenes = random_scenes(rng);
  std::size_t total = 0;
  for (const auto& scene : scenes) {
    for (const auto configuration : kConfigurations) {
      // Swapped: F's vertices against M's triangles, nesting reversed.
      const auto expected =
          oracle_radial(scene.mobile, scene.fixed, scene.centre, swapped(configuration));
      total += expected.pairs.size();
      for (const auto mapping : kRadialMappings) {
        RadialQueryOptions options;
        options.configuration = configuration;
        expect_same_radial(radial_swap_roles(scene.fixed, scene.mobile, scene.centre, {mapping, 500},
                                      options),
                    expected, scene.name + " swapped " + to_string(mapping));
      }
    }
  }
  EXPECT_GT(total, 200u);
}

TEST(RadialSegmenting, TableIsReusedAcrossPoses) {
  std::mt19937_64 rng(44);
  const Vec3 centre(1, 2, 3);
  const TriMesh fixed = flipped(noisy_sphere(centre, 25.0, 4, 0.01, rng));  // socket
  const TriMesh head = noisy_sphere(centre + Vec3(0.3, 0, 0), 24.8, 3, 0.01, rng);
  for (const auto mapping : kRadialMappings) {
    const RadialTable table = build_radial_table(fixed, centre, {mapping, 4000});
    std::size_t hits = 0;
    for (int pose = 0; pose < 5; ++pose) {
      TriMesh mobile = head;
      geometry::rotate_about_axis(mobile, centre, Vec3(1, 1, pose).normalized(), 0.3 * pose);
      const auto expected =
          oracle_radial(fixed, mobile, centre, RadialConfiguration::kMobileInsideFixed);
      hits += expected.pairs.size();
      expect_same_radial(radial_segmenting(table, fixed, mobile, {}), expected, "pose");
    }
    EXPECT_GT(hits, 20u);
  }
}

std::vector<std::int32_t> sorted(std::vector<std::int32_t> v) {
  std::sort(v.begin(), v.end());
  return v;
}

TEST(RadialSegmenting, UpdateTrianglesEqualsFullRebuild) {
  std::mt19937_64 rng(45);
  std::normal_distribution<double> g;
  const Vec3 centre(0, 0, 0);
  for (const auto mapping : kRadialMappings) {
    TriMesh fixed = flipped(noisy_sphere(centre, 25.0, 3, 0.01, rng));
    RadialTable table = build_radial_table(fixed, centre, {mapping, 1500});
    // Move a tenth of the vertices far in non-radial directions.
    std::set<int> moved;
    for (std::size_t v = 0; v < fixed.num_vertices(); v += 10) {
      fixed.vertices[v] += 3.0 * Vec3(g(rng), g(rng), g(rng));
      moved.insert(static_cast<int>(v));
    }
    std::vector<std::int32_t> changed;
    for (std::size_t t = 0; t < fixed.num_triangles(); ++t) {
      for (const int v : fixed.triangles[t]) {
        if (moved.count(v)) {
          changed.push_back(static_cast<std::int32_t>(t));
          break;
        }
      }
    }
    update_triangles(table, fixed, changed);
    const RadialTable rebuilt = build_radial_table(fixed, centre, {mapping, 1500});
    ASSERT_EQ(table.cells.size(), rebuilt.cells.size());
    for (std::size_t c = 0; c < table.cells.size(); ++c) {
      ASSERT_EQ(sorted(table.cells[c]), sorted(rebuilt.cells[c])) << "cell " << c;
    }
    EXPECT_EQ(sorted(table.always_candidates), sorted(rebuilt.always_candidates));
    const TriMesh mobile = noisy_sphere(Vec3(0.5, 0, 0), 24.5, 3, 0.02, rng);
    expect_same_radial(radial_segmenting(table, fixed, mobile, {}),
                oracle_radial(fixed, mobile, centre, RadialConfiguration::kMobileInsideFixed),
                "after update");
    EXPECT_THROW(update_triangles(table, fixed, std::vector<std::int32_t>{-1}), std::exception);
  }
}

TEST(RadialSegmenting, RadialDeformationNeedsNoUpdateAndNeighbourSearchCoversSmallTurns) {
  std::mt19937_64 rng(46);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 centre(2, -1, 0.5);
  for (const auto mapping : kRadialMappings) {
    const TriMesh original = flipped(noisy_sphere(centre, 25.0, 3, 0.01, rng));
    const RadialTable table = build_radial_table(original, centre, {mapping, 3000});
    const TriMesh mobile = noisy_sphere(centre + Vec3(0.4, 0.2, 0), 24.6, 4, 0.02, rng);
    // 1) Radial deformation (§3.3.4): directions unchanged, the old table stays exact.
    TriMesh radial = original;
    for (auto& v : radial.vertices) v = centre + (v - centre) * (1.0 + 0.03 * (u(rng) - 0.5));
    expect_same_radial(radial_segmenting(table, radial, mobile, {}),
                oracle_radial(radial, mobile, centre, RadialConfiguration::kMobileInsideFixed),
                "radial deformation");
    // 2) Every vertex turned about O by up to 0.4 of the neighbour radius (one nominal cell):
    //    the old table with neighbour_cells = 1 must still find every crossing. (Interior points
    //    of a triangle turn by at most ~1.01x its vertices' largest turn on this sphere.)
    const double max_turn = 0.4 * table.grid.nominal_cell_angle_rad();
    TriMesh turned = original;
    for (auto& v : turned.vertices) {
      const Eigen::AngleAxisd turn(max_turn * u(rng), Vec3(g(rng), g(rng), g(rng)).normalized());
      v = centre + turn * (v - centre);
    }
    RadialQueryOptions neighbours;
    neighbours.neighbour_cells = 1;
    const auto expected =
        oracle_radial(turned, mobile, centre, RadialConfiguration::kMobileInsideFixed);
    EXPECT_GT(expected.pairs.size(), 10u);
    expect_same_radial(radial_segmenting(table, turned, mobile, neighbours), expected,
                std::string("neighbour search ") + to_string(mapping));
  }
}

TEST(RadialSegmenting, InvalidInputIsAStatusNotACrash) {
  std::mt19937_64 rng(47);
  const TriMesh fixed = noisy_sphere(Vec3::Zero(), 25.0, 2, 0.0, rng);
  const RadialTable table = build_radial_table(fixed, Vec3::Zero(), {});
  TriMesh mobile = noisy_sphere(Vec3::Zero(), 20.0, 1, 0.0, rng);
  mobile.vertices[3].x() = std::nan("");
  EXPECT_EQ(radial_segmenting(table, fixed, mobile, {}).status, QueryStatus::kInvalidInput);
  TriMesh other = noisy_sphere(Vec3::Zero(), 25.0, 1, 0.0, rng);
  const auto mismatch = radial_segmenting(table, other, other, {});
  EXPECT_EQ(mismatch.status, QueryStatus::kInvalidInput);
  EXPECT_NE(mismatch.message.find("triangles"), std::string::npos);
  RadialQueryOptions three;
  three.num_threads = 3;
  EXPECT_EQ(radial_segmenting(table, fixed, fixed, three).status, QueryStatus::kInvalidInput);
  EXPECT_THROW(build_radial_table(TriMesh{}, Vec3::Zero(), {}), hipfai::Error);
}

// Thesis Table 2 / Fig. 29: sphere (mobile, levels 2..8) against a box capping ~17 % of its area
// (fixed; box divisions as in Table 2: 98 .. 24 578 vertices). The cap of area fraction f has
// height 2 f R, so the box bottom is at z = (1 - 0.34) R. Closed form: a sphere vertex v (|v| =
// R) penetrates iff v_z > 0.66 R (the box is wider than the cap, so its ray enters through the
// bottom), with depth |v| - 0.66 R |v| / v_z. Checked at every level and mapping; the oracle is
// also run on the small levels. Prints pre-processing and per-pose query times.
TEST(RadialSegmenting, SphereVersusCubeTable2MatchesClosedFormWithTimings) {
  const double radius = 25.0, bottom = 0.66 * radius;
  std::printf("\n%-10s %7s %7s %8s %11s %10s %12s %8s\n", "mapping", "sphereV", "boxTri",
              "cells", "preproc_ms", "query_ms", "query2t_ms", "pairs");
  // Thinned (tests/oracle_sample.h): up to level 6, a sixteenth of level 8's vertices.
  const int top_level = test::kOracleSamplesThinned ? 6 : 8;
  for (int level = 2; level <= top_level; ++level) {
    const int divisions = std::min(4 << (level - 2), 64);
    const TriMesh box = geometry::make_box(Vec3(-radius, -radius, bottom),
                                           Vec3(radius, radius, 2 * radius), divisions);
    TriMesh sphere = geometry::make_octasphere(Vec3::Zero(), radius, level);
    // The sphere's rotation: a pose about an oblique axis through O.
    geometry::rotate_about_axis(sphere, Vec3::Zero(), Vec3(1, 2, 3).normalized(), 0.37);
    std::size_t expected_count = 0;
    for (const auto& v : sphere.vertices) expected_count += v.z() > bottom ? 1 : 0;
    for (const auto mapping : kRadialMappings) {
      const auto t0 = std::chrono::steady_clock::now();
      const RadialTable table =
          build_radial_table(box, Vec3::Zero(), {mapping, std::int64_t(box.num_triangles())});
      const auto t1 = std::chrono::steady_clock::now();
      const auto result = radial_segmenting(table, box, sphere, {});
      const auto t2 = std::chrono::steady_clock::now();
      RadialQueryOptions two_threads;
      two_threads.num_threads = 2;
      const auto result2 = radial_segmenting(table, box, sphere, two_threads);
      const auto t3 = std::chrono::steady_clock::now();
      expect_same_radial(result2, result, "two threads");
      ASSERT_EQ(result.pairs.size(), expected_count) << to_string(mapping) << " level " << level;
      for (const auto& pair : result.pairs) {
        const Vec3& v = sphere.vertices[static_cast<std::size_t>(pair.mobile_vertex)];
        ASSERT_GT(v.z(), bottom);
        // Closed form vs Eq. 36 through the triangle: a few ulps of 25 mm.
        EXPECT_NEAR(pair.depth_mm, v.norm() - bottom * v.norm() / v.z(), 1e-9);
      }
      if (level <= 4) {
        expect_same_radial(result,
                    oracle_radial(box, sphere, Vec3::Zero(), RadialConfiguration::kMobileInsideFixed),
                    "sphere-cube");
      }
      using ms = std::chrono::duration<double, std::milli>;
      std::printf("%-10s %7zu %7zu %8d %11.3f %10.3f %12.3f %8zu\n", to_string(mapping),
                  sphere.num_vertices(), box.num_triangles(), table.grid.num_cells(),
                  ms(t1 - t0).count(), ms(t2 - t1).count(), ms(t3 - t2).count(),
                  result.pairs.size());
    }
  }
}

}  // namespace
}  // namespace hipfai::contact
