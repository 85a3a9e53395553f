// Each benchmark peer checked against an independent reference on small cases: the exhaustive
// radial / cylindrical oracles of contact/, closed forms, and exact geometry. Correctness only: no
// timing assertions.
#include "bench/peer_cgal.h"
#include "bench/peer_embree.h"
#include "bench/peer_fcl.h"
#include "bench/scenarios.h"
#include "bench/spatial_hashing.h"
#include "bench/stepping_rom.h"
#include "contact/oracle_radial.h"
#include "contact/range_finder.h"
#include "core/error.h"
#include "geometry/gmsh_runtime.h"
#include "geometry/primitive_meshes.h"

#include <gmsh.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <thread>

namespace hipfai::bench {
namespace {

using contact::RadialConfiguration;
using Eigen::Vector3d;

std::set<std::int32_t> vertex_set(const contact::PenetrationResult& r) {
  std::set<std::int32_t> s;
  for (const auto& p : r.pairs) s.insert(p.mobile_vertex);
  return s;
}

// A cube around the centre whose corners stick out of a fixed sphere: the fixed sphere is inside
// the mobile cube where the cube's vertices are inside the sphere (kFixedInsideMobile).
Scenario fixed_inside_mobile_case() {
  Scenario s;
  s.radial = true;
  s.fixed = geometry::make_octasphere(Vector3d::Zero(), 25.0, 3);
  s.mobile = geometry::make_box(Vector3d::Constant(-20.0), Vector3d::Constant(20.0), 6);
  s.centre = Vector3d(0.3, -0.2, 0.1);  // off the grid planes, so no ray runs along a mesh edge
  s.axis = Vector3d(0.0, 0.0, 1.0);
  s.angle_deg = 11.0;
  s.configuration = RadialConfiguration::kFixedInsideMobile;
  return s;
}

std::vector<Scenario> radial_cases() { return {make_sphere_cube(3), make_sphere_cube(4), fixed_inside_mobile_case()}; }

TEST(RadialPeers, EmbreeMatchesTheOracle) {
  for (const auto& s : radial_cases()) {
    const auto posed = s.posed_mobile();
    const auto oracle = contact::oracle_radial(s.fixed, posed, s.centre, s.configuration);
    ASSERT_FALSE(oracle.pairs.empty());
    EmbreeRadialCaster caster(s.fixed, s.centre, 1);
    for (int threads : {1, 2}) {
      const auto result = caster.query(s.mobile, s.pose(), s.configuration, threads);
      EXPECT_EQ(vertex_set(result), vertex_set(oracle)) << s.name;
      ASSERT_EQ(result.pairs.size(), oracle.pairs.size());
      for (std::size_t i = 0; i < result.pairs.size(); ++i) {
        // Embree works in single precision on coordinates up to ~70 mm from the centre: float
        // rounding (6e-8 relative) of the hit distance stays far below 1e-4 mm.
        EXPECT_NEAR(result.pairs[i].depth_mm, oracle.pairs[i].depth_mm, 1e-4);
      }
    }
  }
}

TEST(RadialPeers, CgalMatchesTheOracle) {
  for (const auto& s : radial_cases()) {
    const auto posed = s.posed_mobile();
    const auto oracle = contact::oracle_radial(s.fixed, posed, s.centre, s.configuration);
    CgalRadialCaster caster(s.fixed, s.centre);
    for (int threads : {1, 2}) {
      const auto result = caster.query(posed, s.configuration, threads);
      ASSERT_EQ(vertex_set(result), vertex_set(oracle)) << s.name;
      for (std::size_t i = 0; i < result.pairs.size(); ++i) {
        // Exact predicates, double-precision construction of the hit point: ~1e-14 relative.
        EXPECT_NEAR(result.pairs[i].depth_mm, oracle.pairs[i].depth_mm, 1e-9);
      }
    }
  }
}

TEST(SpatialHashing, SurfaceRadialQueryEqualsTheOracleExactly) {
  for (const auto& s : radial_cases()) {
    const auto posed = s.posed_mobile();
    const auto oracle = contact::oracle_radial(s.fixed, posed, s.centre, s.configuration);
    // Default cell (mean edge), tiny cells (long walks across many cells) and one huge cell.
    for (double cell : {0.0, 0.37, 500.0}) {
      SpatialHashOptions options;
      options.cell_size_mm = cell;
      SurfaceSpatialHash hash(s.fixed, options);
      for (int threads : {1, 2}) {
        const auto result = hash.radial_query(posed, s.centre, s.configuration, threads);
        ASSERT_EQ(result.pairs.size(), oracle.pairs.size()) << s.name << " cell " << cell;
        for (std::size_t i = 0; i < result.pairs.size(); ++i) {
          // Same watertight primitive and crossing rule as the oracle: bit-identical answers.
          EXPECT_EQ(result.pairs[i].mobile_vertex, oracle.pairs[i].mobile_vertex);
          EXPECT_EQ(result.pairs[i].fixed_triangle, oracle.pairs[i].fixed_triangle);
          EXPECT_EQ(result.pairs[i].depth_mm, oracle.pairs[i].depth_mm);
        }
      }
    }
  }
}

TEST(SpatialHashing, TetrahedraOfABoxFillItsVolumeAndFindTheOraclesVertices) {
  const Scenario s = make_sphere_cube(4);
  const TetMesh tets = tetrahedralize(s.fixed);
  double volume = 0.0;
  for (const auto& t : tets.tets) {
    const Vector3d a = tets.nodes[static_cast<std::size_t>(t[0])];
    volume += std::abs((tets.nodes[static_cast<std::size_t>(t[1])] - a)
                           .dot((tets.nodes[static_cast<std::size_t>(t[2])] - a).cross(tets.nodes[static_cast<std::size_t>(t[3])] - a))) / 6.0;
  }
  // Box 50 x 50 x 50 mm; the tets must tile it (rounding of ~1e5 terms: 1e-6 relative).
  EXPECT_NEAR(volume, 125000.0, 125000.0 * 1e-6);
  const auto posed = s.posed_mobile();
  const auto oracle = contact::oracle_radial(s.fixed, posed, s.centre, s.configuration);
  TetSpatialHash hash(tets);
  for (int threads : {1, 2}) {
    const auto found = hash.penetrating_vertices(posed, threads);
    // Every sphere vertex inside the box is radially penetrating (the ray from the sphere centre
    // enters through the bottom face) and vice versa.
    EXPECT_EQ(std::set<std::int32_t>(found.begin(), found.end()), vertex_set(oracle));
  }
}

TEST(SpatialHashing, TriangleIntersectionClosedForms) {
  const std::array<Vector3d, 3> base{Vector3d(0, 0, 0), Vector3d(4, 0, 0), Vector3d(0, 4, 0)};
  // A vertical triangle piercing the base through (1, 1, 0).
  EXPECT_TRUE(triangles_intersect(base, {Vector3d(1, 1, -1), Vector3d(1, 1, 1), Vector3d(2, 2, 1)}));
  // The same shifted past the hypotenuse x + y = 4: no intersection.
  EXPECT_FALSE(triangles_intersect(base, {Vector3d(3, 3, -1), Vector3d(3, 3, 1), Vector3d(4, 4, 1)}));
  // Above the plane.
  EXPECT_FALSE(triangles_intersect(base, {Vector3d(1, 1, 0.5), Vector3d(1, 2, 1), Vector3d(2, 1, 1)}));
  EXPECT_TRUE(segment_crosses_triangle(Vector3d(1, 1, -1), Vector3d(1, 1, 1), base[0], base[1], base[2]));
  EXPECT_FALSE(segment_crosses_triangle(Vector3d(1, 1, 0.5), Vector3d(1, 1, 1), base[0], base[1], base[2]));
}

TEST(Fcl, ReportsEveryTriangleThatStraddlesTheSurface) {
  const Scenario s = make_sphere_cube(4);
  const auto posed = s.posed_mobile();
  const auto oracle = contact::oracle_radial(s.fixed, posed, s.centre, s.configuration);
  const auto inside = vertex_set(oracle);
  for (auto bv : {FclBoundingVolume::kObbRss, FclBoundingVolume::kObb}) {
    FclModel fixed(s.fixed, bv), mobile(s.mobile, bv);
    const auto result = fixed.collide(mobile, s.pose());
    ASSERT_TRUE(result.collides);
    std::set<std::int32_t> reported;
    for (const auto& [f, m] : result.triangle_pairs) reported.insert(m);
    // A mobile triangle with one vertex inside the box and one outside crosses the box surface
    // (continuity), so FCL must report it.
    std::size_t straddling = 0;
    for (std::size_t t = 0; t < s.mobile.triangles.size(); ++t) {
      int in = 0;
      for (auto v : s.mobile.triangles[t]) in += inside.count(v) ? 1 : 0;
      if (in == 1 || in == 2) {
        ++straddling;
        EXPECT_TRUE(reported.count(static_cast<std::int32_t>(t))) << "triangle " << t;
      }
    }
    EXPECT_GT(straddling, 10u);
    // Implied vertices: a superset of the straddling triangles' vertices, never all of the inside.
    const auto implied = implied_mobile_vertices(s.mobile, result);
    EXPECT_LT(std::set<std::int32_t>(implied.begin(), implied.end()).size(), s.mobile.vertices.size());
    // FCL's default of one contact.
    FclCollideOptions one;
    one.all_contacts = false;
    EXPECT_EQ(fixed.collide(mobile, s.pose(), one).triangle_pairs.size(), 1u);
    // Far apart: nothing.
    const auto apart = fixed.collide(mobile, rotation_about(Vector3d::Zero(), Vector3d::UnitZ(), 0.0, Vector3d(0, 0, -200)));
    EXPECT_FALSE(apart.collides);
    EXPECT_TRUE(apart.triangle_pairs.empty());
  }
}

TEST(SteppingRom, ClosedFormPredicate) {
  const auto collides = [](double a) { return a >= 37.3 || a <= -12.05; };
  SteppingRomOptions options;
  const auto one = stepping_range_of_motion(collides, options);
  EXPECT_DOUBLE_EQ(one.anticlockwise_deg, 37.0);
  EXPECT_DOUBLE_EQ(one.clockwise_deg, 12.0);
  EXPECT_EQ(one.detections, 38 + 13);
  options.step_deg = 0.1;
  const auto fine = stepping_range_of_motion(collides, options);
  EXPECT_NEAR(fine.anticlockwise_deg, 37.2, 1e-9);  // k * 0.1 with k = 372 (no accumulated sum)
  EXPECT_NEAR(fine.clockwise_deg, 12.0, 1e-9);
  options.max_deg = 5.0;
  const auto capped = stepping_range_of_motion([](double) { return false; }, options);
  EXPECT_NEAR(capped.anticlockwise_deg, 5.0, 1e-9);
  EXPECT_FALSE(capped.anticlockwise_limited);
}

TEST(SteppingRom, FclAndHashingBracketTheExactRange) {
  // A bar swinging about z into a block: the first contact is a corner of the bar on the block's
  // face (vertex-on-triangle), which the one-pass range finder finds exactly.
  const auto bar = geometry::make_box(Vector3d(5, -1, -1), Vector3d(30, 1, 1), 2);
  const auto block = geometry::make_box(Vector3d(-40, 12, -5), Vector3d(40, 22, 5), 3);
  const Vector3d centre = Vector3d::Zero(), axis = Vector3d::UnitZ();
  const auto exact = contact::range_of_motion(block, bar, centre, axis);
  ASSERT_LT(exact.anticlockwise_deg, 90.0);
  FclModel fixed(block, FclBoundingVolume::kObbRss), mobile(bar, FclBoundingVolume::kObbRss);
  SurfaceSpatialHash hash(block);
  SteppingRomOptions options;
  options.step_deg = 0.5;
  const auto rad = std::numbers::pi / 180.0;
  const auto fcl_rom = stepping_range_of_motion([&](double a) {
    return fixed.collide(mobile, rotation_about(centre, axis, a * rad)).collides;
  }, options);
  const auto hash_rom = stepping_range_of_motion([&](double a) {
    return hash.first_collision(transformed(bar, rotation_about(centre, axis, a * rad)));
  }, options);
  for (const auto& rom : {fcl_rom, hash_rom}) {
    EXPECT_LE(rom.anticlockwise_deg, exact.anticlockwise_deg + 1e-9);
    EXPECT_GT(rom.anticlockwise_deg, exact.anticlockwise_deg - options.step_deg);
    EXPECT_LE(rom.clockwise_deg, std::min(exact.clockwise_deg, 180.0) + 1e-9);
    EXPECT_GT(rom.clockwise_deg, std::min(exact.clockwise_deg, 180.0) - options.step_deg);
  }
}

TEST(Scenarios, SubdivisionKeepsTheSolidAndMultipliesCounts) {
  const auto sphere = geometry::make_octasphere(Vector3d::Zero(), 25.0, 2);
  const auto finer = subdivide_midpoint(sphere, 1);
  EXPECT_EQ(finer.num_vertices(), 258u);  // octasphere level 3 count: same edge-midpoint scheme
  EXPECT_EQ(finer.num_triangles(), 4 * sphere.num_triangles());
  // Planar midpoint split: the enclosed volume is unchanged up to rounding.
  EXPECT_NEAR(geometry::signed_volume(finer), geometry::signed_volume(sphere), 1e-9 * geometry::signed_volume(sphere));
}

TEST(Scenarios, SphereCubeCapsAbout17PercentOfTheSphere) {
  const Scenario s = make_sphere_cube(6);
  double capped = 0.0, total = 0.0;
  for (std::size_t t = 0; t < s.mobile.triangles.size(); ++t) {
    const double area = geometry::triangle_area(s.mobile, t);
    Vector3d centroid = Vector3d::Zero();
    for (auto v : s.mobile.triangles[t]) centroid += s.mobile.vertices[static_cast<std::size_t>(v)] / 3.0;
    total += area;
    if (centroid.z() > 0.66 * 25.0) capped += area;
  }
  // Archimedes: cap area fraction (1 - h / R) / 2 = 0.17; the faceted sphere's triangles are
  // counted by centroid, which moves the fraction by well under 0.01 at level 6.
  EXPECT_NEAR(capped / total, 0.17, 0.01);
}

}  // namespace
}  // namespace hipfai::bench

namespace hipfai::bench {
namespace {

double tet_volume(const TetMesh& tets) {
  double volume = 0.0;
  for (const auto& t : tets.tets) {
    const Vector3d a = tets.nodes[static_cast<std::size_t>(t[0])];
    volume += std::abs((tets.nodes[static_cast<std::size_t>(t[1])] - a)
                           .dot((tets.nodes[static_cast<std::size_t>(t[2])] - a).cross(tets.nodes[static_cast<std::size_t>(t[3])] - a))) / 6.0;
  }
  return volume;
}

TEST(SpatialHashing, SuccessiveTetrahedralizationsInOneProcess) {
  // gmsh keeps global state between calls: each call must start from a clean model.
  const auto sphere = geometry::make_octasphere(Vector3d(1, 2, 3), 10.0, 3);
  const auto box = geometry::make_box(Vector3d(-25, -25, 16.5), Vector3d(25, 25, 66.5), 8);
  (void)tetrahedralize(sphere);
  {
    // Global size options another gmsh user (the hip generator) leaves behind must not matter; the
    // coarsest box of the sphere-cube ladder (4 divisions) made HXT abort with these.
    const auto gmsh_lock = geometry::lock_gmsh();  // the runtime the library uses
    gmsh::option::setNumber("Mesh.MeshSizeMax", 5.5);
    gmsh::option::setNumber("Mesh.MeshSizeMin", 0.55);
    gmsh::option::setNumber("General.NumThreads", 1);
  }
  const TetMesh coarse = tetrahedralize(make_sphere_cube(2).fixed);
  EXPECT_NEAR(tet_volume(coarse), 125000.0, 125000.0 * 1e-6);
  // Two overlapping spheres in one surface: self-intersecting, gmsh must fail (and recover).
  const auto other = geometry::make_octasphere(Vector3d(6, 2, 3), 10.0, 3);
  const auto overlapping = geometry::merge_meshes({&sphere, &other});
  for (int round = 0; round < 2; ++round) {
    EXPECT_THROW((void)tetrahedralize(overlapping), Error);
    const TetMesh a = tetrahedralize(sphere);
    EXPECT_NEAR(tet_volume(a), geometry::signed_volume(sphere), 1e-6 * geometry::signed_volume(sphere));
    const TetMesh b = tetrahedralize(box);
    EXPECT_NEAR(tet_volume(b), 125000.0, 125000.0 * 1e-6);
  }
}

TEST(SpatialHashing, TetrahedralizationsFromTwoThreadsAreSerialised) {
  // gmsh has one global model: without the process-wide lock two threads would mesh into it at once.
  const auto sphere = geometry::make_octasphere(Vector3d(1, 2, 3), 10.0, 3);
  const auto box = geometry::make_box(Vector3d(-25, -25, 16.5), Vector3d(25, 25, 66.5), 8);
  double sphere_volume = 0.0, box_volume = 0.0;
  std::thread other([&] {
    for (int i = 0; i < 3; ++i) sphere_volume = tet_volume(tetrahedralize(sphere));
  });
  for (int i = 0; i < 3; ++i) box_volume = tet_volume(tetrahedralize(box));
  other.join();
  EXPECT_NEAR(sphere_volume, geometry::signed_volume(sphere), 1e-6 * geometry::signed_volume(sphere));
  EXPECT_NEAR(box_volume, 125000.0, 125000.0 * 1e-6);
}

}  // namespace
}  // namespace hipfai::bench
