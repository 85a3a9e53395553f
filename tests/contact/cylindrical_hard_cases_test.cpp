// Hard cases of cylindrical segmenting, each its own test: ring borders and table edges, the axis
// and the centre, slivers and zero-area triangles, tangent arcs, arcs of pi, vertices on the
// surface, open meshes, coordinates far from the origin, and the real CT femur against the pelvis.
#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "contact/oracle_cylindrical.h"
#include "contact/range_finder.h"
#include "core/numbers.h"
#include "geometry/mesh_io.h"
#include "geometry/primitive_meshes.h"
#include "tests/oracle_sample.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <set>
#include <string>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;
using hipfai::kPi;

// Exact equality of vertex sets, depths to 1e-9 mm (same closed form on the same coordinates up
// to pose rounding ~1e-13 mm; see cylindrical_segmenting_test.cpp).
void expect_same_hard(const PenetrationResult& got, const PenetrationResult& want, const std::string& what,
                 double depth_tolerance_mm = 1e-9) {
  ASSERT_NE(got.status, QueryStatus::kInvalidInput) << what << ": " << got.message;
  ASSERT_EQ(got.pairs.size(), want.pairs.size()) << what;
  for (std::size_t i = 0; i < got.pairs.size(); ++i) {
    ASSERT_EQ(got.pairs[i].mobile_vertex, want.pairs[i].mobile_vertex) << what;
    EXPECT_NEAR(got.pairs[i].depth_mm, want.pairs[i].depth_mm, depth_tolerance_mm) << what;
    EXPECT_TRUE(std::isfinite(got.pairs[i].depth_mm) && std::isfinite(got.pairs[i].angle_deg)) << what;
  }
}

// Runs every query path on the (already posed) mobile mesh and checks them against the oracle.
PenetrationResult all_paths(const TriMesh& fixed, const TriMesh& mobile, const Vec3& centre,
                            const Vec3& axis, const std::string& what) {
  const PenetrationResult oracle = oracle_cylindrical(fixed, mobile, centre, axis);
  EXPECT_EQ(oracle.status, QueryStatus::kOk);
  expect_same_hard(cylindrical_segmenting(fixed, mobile, centre, axis), oracle, what + " one-shot");
  const CylindricalTable table = CylindricalTable::build(fixed, centre, axis);
  expect_same_hard(cylindrical_segmenting(table, mobile), oracle, what + " table");
  expect_same_hard(CylindricalPoseCache(table, mobile).query(0.0), oracle, what + " pose cache");
  return oracle;
}

// A mobile "mesh" made of points: each point is a zero-area triangle (i, i, i), so only the
// vertices matter.
TriMesh degenerate_points(const std::vector<Vec3>& pts) {
  TriMesh mesh;
  mesh.vertices = pts;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto v = static_cast<std::int32_t>(i);
    mesh.triangles.push_back({v, v, v});
  }
  return mesh;
}

TriMesh perturbed_sphere(std::mt19937& rng, const Vec3& centre, double radius, int levels) {
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  TriMesh mesh = geometry::make_octasphere(Vec3::Zero(), radius, levels);
  for (Vec3& p : mesh.vertices) p = centre + p * (1.0 + u(rng));
  return mesh;
}

TEST(CylindricalHardCases, RingBordersAndTableEdgesFindAllCandidates) {
  std::mt19937 rng(1);
  const TriMesh fixed = perturbed_sphere(rng, Vec3(3, 1, 0), 8.0, 3);
  CylindricalTableOptions options;
  options.resolution_r_mm = 0.7;
  options.resolution_z_mm = 0.45;
  const Vec3 centre(0, 0, 0), axis(0.2, 0.1, 1.0);
  const CylindricalTable table = CylindricalTable::build(fixed, centre, axis, options);
  ASSERT_EQ(table.status(), QueryStatus::kOk);
  std::vector<CylindricalBounds> bounds;
  for (std::size_t t = 0; t < table.num_triangles(); ++t) {
    const auto& tri = table.triangle(static_cast<std::int32_t>(t));
    bounds.push_back(triangle_cylindrical_bounds(table.local_vertex(tri[0]), table.local_vertex(tri[1]),
                                                 table.local_vertex(tri[2])));
  }
  // Probe radii and heights: every ring border, the table's own edges, and every triangle's exact
  // bounds (the values at which a vertex just touches a triangle's bounding volume).
  std::vector<double> radii, heights;
  for (long long i = 0; i <= table.num_r_cells(); ++i) radii.push_back(table.r_lo_mm() + i * table.resolution_r_mm());
  for (long long i = 0; i <= table.num_z_cells(); ++i) heights.push_back(table.z_lo_mm() + i * table.resolution_z_mm());
  for (std::size_t t = 0; t < bounds.size(); t += 5) {
    radii.push_back(bounds[t].r_min);
    radii.push_back(bounds[t].r_max);
    heights.push_back(bounds[t].z_min);
    heights.push_back(bounds[t].z_max);
  }
  std::size_t checked = 0;
  for (double r : radii) {
    for (double z : heights) {
      std::set<std::int32_t> candidates;
      table.for_each_candidate(r, z, [&](std::int32_t t) { candidates.insert(t); });
      for (std::size_t t = 0; t < bounds.size(); ++t) {
        if (bounds[t].r_min <= r && r <= bounds[t].r_max && bounds[t].z_min <= z && z <= bounds[t].z_max) {
          ASSERT_TRUE(candidates.count(static_cast<std::int32_t>(t)))
              << "triangle " << t << " missing at r=" << r << " z=" << z;
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 1000u);

  // Mobile vertices snapped onto ring borders (up to the rounding of the back-transform).
  TriMesh mobile = perturbed_sphere(rng, Vec3(-2, 4, 1), 7.0, 3);
  const AxisFrame frame = make_axis_frame(centre, axis).frame;
  for (Vec3& p : mobile.vertices) {
    const Cylindrical cyl = to_cylindrical(frame.to_local(p));
    const double r = table.r_lo_mm() + std::round((cyl.r - table.r_lo_mm()) / table.resolution_r_mm()) * table.resolution_r_mm();
    const double z = table.z_lo_mm() + std::round((cyl.z - table.z_lo_mm()) / table.resolution_z_mm()) * table.resolution_z_mm();
    p = frame.centre + r * std::cos(cyl.theta) * frame.e1 + r * std::sin(cyl.theta) * frame.e2 + z * frame.axis;
  }
  const PenetrationResult oracle = all_paths(fixed, mobile, centre, axis, "snapped");
  EXPECT_FALSE(oracle.pairs.empty());
}

TEST(CylindricalHardCases, VerticesOnTheAxisAndAtTheCentre) {
  const TriMesh fixed = geometry::make_box(Vec3(-5, -5, -5), Vec3(5, 5, 5), 2);
  const Vec3 centre = Vec3::Zero(), axis = Vec3::UnitZ();
  const TriMesh mobile = degenerate_points({Vec3(0, 0, 0), Vec3(0, 0, 2), Vec3(0, 0, -7), Vec3(1e-300, 0, 0),
                                 Vec3(4.5, 2.25, 0)});
  const PenetrationResult oracle = all_paths(fixed, mobile, centre, axis, "axis");
  // Points on the axis do not move under the rotation: never reported. The last point is inside
  // the box and leaves it through the face x = 5 after turning back to theta = acos(5 / r).
  ASSERT_EQ(oracle.pairs.size(), 1u);
  EXPECT_EQ(oracle.pairs[0].mobile_vertex, 4);
  const double r = std::hypot(4.5, 2.25);
  // Closed form; 1e-12 mm covers the rounding of atan2/acos at r ~ 5.
  EXPECT_NEAR(oracle.pairs[0].depth_mm, r * (std::atan2(2.25, 4.5) - std::acos(5.0 / r)), 1e-12);
  // The range finder also copes: the box surrounds the axis points, which never move.
  const RangeOfMotion range = range_of_motion(fixed, mobile, centre, axis);
  EXPECT_EQ(range.status, QueryStatus::kOk);
  EXPECT_TRUE(std::isfinite(range.anticlockwise_deg) && std::isfinite(range.clockwise_deg));
}

TEST(CylindricalHardCases, SliverAndZeroAreaTriangles) {
  const TriMesh box = geometry::make_box(Vec3(-5, -4, -3), Vec3(5, 4, 3), 3);
  std::mt19937 rng(4);
  const TriMesh mobile = perturbed_sphere(rng, Vec3(6, 3, 0), 5.0, 3);
  const Vec3 centre(0.5, -0.3, 0.2), axis(0.3, -0.2, 1.0);
  const PenetrationResult reference = all_paths(box, mobile, centre, axis, "box");
  ASSERT_FALSE(reference.pairs.empty());
  for (double offset : {0.0, 1e-7}) {  // zero-area, then sliver
    // Split every 4th triangle (a, b, c) at a point m on (or 1e-7 off) edge ab, towards c:
    // (a, m, c), (m, b, c) and the thin (a, b, m) facing the neighbour across ab. The surface is
    // unchanged geometrically and stays closed and consistently oriented.
    TriMesh mesh = box;
    const std::size_t original = mesh.triangles.size();
    for (std::size_t t = 0; t < original; t += 4) {
      const auto [a, b, c] = mesh.triangles[t];
      const Vec3 pa = mesh.vertices[static_cast<std::size_t>(a)], pb = mesh.vertices[static_cast<std::size_t>(b)];
      const Vec3 pc = mesh.vertices[static_cast<std::size_t>(c)];
      const Vec3 mid = 0.5 * (pa + pb);
      mesh.vertices.push_back(mid + offset * (pc - mid).normalized());
      const auto m = static_cast<std::int32_t>(mesh.vertices.size() - 1);
      mesh.triangles[t] = {a, m, c};
      mesh.triangles.push_back({m, b, c});
      mesh.triangles.push_back({a, b, m});
    }
    const std::string what = offset == 0.0 ? "zero-area" : "sliver";
    const PenetrationResult result = all_paths(mesh, mobile, centre, axis, what);
    // Same surface (to 1e-7 mm): same penetrating vertices; depths within the angle the sliver
    // offset can shift a crossing, r * (1e-7 / r) / sin(grazing) -- 1e-4 mm is generous.
    expect_same_hard(result, reference, what + " vs plain box", 1e-4);
  }
}

TEST(CylindricalHardCases, TangentArcs) {
  // Face x = 5 of the box [5, 7] x [-1, 1]^2 (outward normal -x). Circles of radius exactly 5
  // touch it at (5, 0, 0): the crossing is a double root and T.N = 0 (App. D first case).
  const TriMesh outside_box = geometry::make_box(Vec3(5, -1, -1), Vec3(7, 1, 1), 1);
  const TriMesh mobile = degenerate_points({Vec3(0, 5, 0), Vec3(-5, 0, 0), Vec3(5, 0, 0), Vec3(0, -5, 0)});
  const PenetrationResult outside = all_paths(outside_box, mobile, Vec3::Zero(), Vec3::UnitZ(), "touch");
  EXPECT_TRUE(outside.pairs.empty());
  // Box [3, 5] x [-1, 1]^2: the circle of radius 5 runs inside it near theta = 0 and touches the
  // face x = 5 (normal +x) from inside. The vertex at theta = 0.1 is inside (x = 4.975, y = 0.499)
  // and its nearest way out is back to the tangent point: depth 5 * 0.1.
  const TriMesh inside_box = geometry::make_box(Vec3(3, -1, -1), Vec3(5, 1, 1), 1);
  const TriMesh inside = degenerate_points({Vec3(5 * std::cos(0.1), 5 * std::sin(0.1), 0), Vec3(0, 5, 0)});
  const PenetrationResult result = all_paths(inside_box, inside, Vec3::Zero(), Vec3::UnitZ(), "tangent");
  ASSERT_EQ(result.pairs.size(), 1u);
  EXPECT_EQ(result.pairs[0].mobile_vertex, 0);
  // r is 5 up to rounding (1e-15); a near-tangent root moves by sqrt(2 * 1e-16) ~ 1.5e-8 rad,
  // i.e. < 1e-7 mm of arc: 1e-6 mm covers it.
  EXPECT_NEAR(result.pairs[0].depth_mm, 0.5, 1e-6);
}

TEST(CylindricalHardCases, ArcsOfPi) {
  // Face x = 5 of [5, 7] x [-4, 4] x [-1, 1]: the circle of radius 6 crosses it at +-acos(5/6).
  const TriMesh box = geometry::make_box(Vec3(5, -4, -1), Vec3(7, 4, 1), 1);
  // (-6, 0, 0): both crossings at exactly the same distance pi - acos(5/6) -- a tie, outside.
  // (6, 0, 0): inside, depth 6 acos(5/6) either way.
  // (-5, 0, 0): radius 5 touches the face at (5, 0, 0), exactly pi away (T.A = 0 and T.N = 0).
  const TriMesh mobile = degenerate_points({Vec3(-6, 0, 0), Vec3(6, 0, 0), Vec3(-5, 0, 0)});
  const PenetrationResult result = all_paths(box, mobile, Vec3::Zero(), Vec3::UnitZ(), "pi");
  ASSERT_EQ(result.pairs.size(), 1u);
  EXPECT_EQ(result.pairs[0].mobile_vertex, 1);
  // Closed form; 1e-12 mm covers the rounding of acos at r = 6.
  EXPECT_NEAR(result.pairs[0].depth_mm, 6 * std::acos(5.0 / 6.0), 1e-12);
  EXPECT_NEAR(result.pairs[0].angle_deg, std::acos(5.0 / 6.0) * 180 / kPi, 1e-10);
}

TEST(CylindricalHardCases, VertexExactlyOnTheSurface) {
  const TriMesh box = geometry::make_box(Vec3(5, -4, -1), Vec3(7, 4, 1), 2);
  // On face x = 5, on the face's internal edges, on a box corner.
  const TriMesh mobile = degenerate_points({Vec3(5, 0.5, 0.25), Vec3(5, std::sqrt(11.0), 0), Vec3(5, 0, 0),
                                 Vec3(5, 4, 1)});
  const PenetrationResult result = all_paths(box, mobile, Vec3::Zero(), Vec3::UnitZ(), "surface");
  EXPECT_TRUE(result.pairs.empty());  // touching is not penetrating
  // A point on the face z = 1, which is perpendicular to the axis: its circle lies in that face
  // and crosses no triangle of it, so it is judged by the face x = 5 it meets, like a point just
  // inside (documented); all paths still agree with the oracle.
  all_paths(box, degenerate_points({Vec3(6, 1, 1)}), Vec3::Zero(), Vec3::UnitZ(), "in-face circle");
  // Moved 1e-6 mm into the solid they are reported, with the arc back to the face x = 5.
  const std::vector<Vec3> inner = {Vec3(5 + 1e-6, 0.5, 0.25), Vec3(5 + 1e-6, std::sqrt(11.0), 0)};
  const PenetrationResult deeper = all_paths(box, degenerate_points(inner), Vec3::Zero(), Vec3::UnitZ(), "pushed");
  ASSERT_EQ(deeper.pairs.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const double r = std::hypot(inner[i].x(), inner[i].y());
    const double expected = r * std::abs(std::atan2(inner[i].y(), inner[i].x()) - std::acos(5.0 / r));
    // Closed form; rounding of r (1e-15 relative) moves acos by <= 1e-14 rad at these angles.
    EXPECT_NEAR(deeper.pairs[i].depth_mm, expected, 1e-11);
    EXPECT_GE(deeper.pairs[i].depth_mm, 1e-6);  // an arc is never shorter than the straight path
  }
}

TEST(CylindricalHardCases, OpenMeshWithHoles) {
  std::mt19937 rng(9);
  TriMesh fixed = perturbed_sphere(rng, Vec3::Zero(), 10.0, 3);
  std::vector<geometry::Triangle> kept;
  for (std::size_t t = 0; t < fixed.triangles.size(); ++t) {
    if (t % 5 != 0) kept.push_back(fixed.triangles[t]);
  }
  fixed.triangles = kept;
  const TriMesh mobile = perturbed_sphere(rng, Vec3(8, 2, 1), 6.0, 3);
  for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(1, 2, 0.5)}) {
    const PenetrationResult result = all_paths(fixed, mobile, Vec3(1, 0, 0), axis, "open");
    EXPECT_FALSE(result.pairs.empty());
    RangeOfMotionOptions vertex_contacts;  // the oracle enumerates vertex contacts only
    vertex_contacts.include_edge_edge = false;
    const RangeOfMotion range = range_of_motion(fixed, mobile, Vec3(1, 0, 0), axis, vertex_contacts);
    const RangeOfMotion oracle = oracle_range_of_motion(fixed, mobile, Vec3(1, 0, 0), axis);
    EXPECT_NEAR(range.anticlockwise_deg, oracle.anticlockwise_deg, 1e-9);
    EXPECT_NEAR(range.clockwise_deg, oracle.clockwise_deg, 1e-9);
  }
}

TEST(CylindricalHardCases, CoordinatesFarFromTheOrigin) {
  std::mt19937 rng(12);
  const TriMesh fixed = perturbed_sphere(rng, Vec3::Zero(), 9.0, 3);
  const TriMesh mobile = perturbed_sphere(rng, Vec3(7, 3, -2), 6.0, 3);
  const Vec3 centre(1, 1, 1), axis(0.4, -0.3, 1.0);
  const PenetrationResult near_origin = all_paths(fixed, mobile, centre, axis, "near");
  ASSERT_FALSE(near_origin.pairs.empty());
  const Vec3 shift(1e4, -1e4, 1e4);
  TriMesh far_fixed = fixed, far_mobile = mobile;
  for (Vec3& p : far_fixed.vertices) p += shift;
  for (Vec3& p : far_mobile.vertices) p += shift;
  const PenetrationResult far = all_paths(far_fixed, far_mobile, centre + shift, axis, "far");
  // Translation by 1e4 mm rounds coordinates by ~1e-12 mm; depths agree far within 1e-6 mm.
  expect_same_hard(far, near_origin, "far vs near", 1e-6);
  // Rotation centre 1e4 mm from the meshes: radii ~1e4 mm, arcs are nearly straight lines.
  const PenetrationResult distant_centre =
      all_paths(fixed, mobile, Vec3(0, 1e4, 0), Vec3(1, 0, 0), "distant centre");
  EXPECT_FALSE(distant_centre.pairs.empty());
}

TEST(CylindricalHardCases, RealFemurAgainstPelvis) {
  const std::string folder = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
  const TriMesh pelvis = geometry::read_mesh(folder + "pelvis_no_sacrum.ply");
  const TriMesh femur = geometry::read_mesh(folder + "femur_r.ply");
  const Vec3 hjc(143.80, 243.46, -432.58);  // hip.json hjc_mm
  std::size_t penetrating = 0;
  // One pose per axis, chosen where the bones meet (y and z at -40 degrees) or nearly (x).
  const std::vector<std::pair<Vec3, double>> poses = {
      {Vec3(1, 0, 0), 25.0}, {Vec3(0, 1, 0), -40.0}, {Vec3(0, 0, 1), -40.0}};
  for (const auto& [axis, angle_deg] : poses) {
    const auto start = std::chrono::steady_clock::now();
    const CylindricalTable table = CylindricalTable::build(pelvis, hjc, axis, {}, &femur);
    const CylindricalPoseCache cache(table, femur);
    const auto built = std::chrono::steady_clock::now();
    {
      const auto query_start = std::chrono::steady_clock::now();
      const PenetrationResult result = cache.query(angle_deg);
      const auto query_end = std::chrono::steady_clock::now();
      std::cout << "[ timing ] axis (" << axis.transpose() << ") pre-processing "
                << std::chrono::duration<double, std::milli>(built - start).count() << " ms, query "
                << angle_deg << " deg: "
                << std::chrono::duration<double, std::milli>(query_end - query_start).count()
                << " ms, " << result.pairs.size() << " penetrating of " << femur.vertices.size()
                << " femur vertices, " << cache.tracked().size() << " tracked, "
                << cache.num_crossings() << " crossings\n";
      // Oracle subsample (it is O(V x T)): every 150th femur vertex whose circle meets the
      // pelvis, plus every 4th vertex reported penetrating; other vertices' circles cross no
      // triangle, which the oracle checks on every 2000th femur vertex (each stride times the
      // thinning of tests/oracle_sample.h).
      const auto thin = static_cast<std::size_t>(test::kOracleThinning);
      std::set<std::int32_t> chosen;
      for (std::size_t i = 0; i < cache.tracked().size(); i += 150 * thin) chosen.insert(cache.tracked()[i].vertex);
      for (std::size_t i = 0; i < result.pairs.size(); i += 4 * thin) chosen.insert(result.pairs[i].mobile_vertex);
      for (std::size_t v = 0; v < femur.vertices.size(); v += 2000 * thin) chosen.insert(static_cast<std::int32_t>(v));
      const std::vector<std::int32_t> original(chosen.begin(), chosen.end());
      TriMesh posed;
      for (std::int32_t v : original) posed.vertices.push_back(femur.vertices[static_cast<std::size_t>(v)]);
      geometry::rotate_about_axis(posed, hjc, axis, angle_deg * kPi / 180);
      const PenetrationResult oracle = oracle_cylindrical(pelvis, posed, hjc, axis);
      PenetrationResult mapped;
      for (const auto& pair : result.pairs) {
        const auto it = std::lower_bound(original.begin(), original.end(), pair.mobile_vertex);
        if (it != original.end() && *it == pair.mobile_vertex) {
          PenetrationPair copy = pair;
          copy.mobile_vertex = static_cast<std::int32_t>(it - original.begin());
          mapped.pairs.push_back(copy);
        }
      }
      expect_same_hard(mapped, oracle, "axis (" + std::to_string(axis.x()) + ", " + std::to_string(axis.y()) +
                                      ") angle " + std::to_string(angle_deg));
      penetrating += oracle.pairs.size();
    }
  }
  EXPECT_GT(penetrating, 0u);  // the poses really collide somewhere

  // Timing report (printed, never asserted): per-pose cost of a sweep with the pose cache vs the
  // one-shot query on a posed femur, about the flexion-like axis y.
  const Vec3 axis(0, 1, 0);
  for (int threads : {1, 2}) {
    CylindricalQueryOptions options;
    options.num_threads = threads;
    const auto start = std::chrono::steady_clock::now();
    const CylindricalTable table = CylindricalTable::build(pelvis, hjc, axis, {}, &femur);
    const auto table_done = std::chrono::steady_clock::now();
    const CylindricalPoseCache cache(table, femur, options);
    const auto cache_done = std::chrono::steady_clock::now();
    std::size_t pairs = 0;
    constexpr int kPoses = 36;
    for (int i = 0; i < kPoses; ++i) pairs += cache.query(-90.0 + 5.0 * i).pairs.size();
    const auto sweep_done = std::chrono::steady_clock::now();
    TriMesh posed = femur;
    geometry::rotate_about_axis(posed, hjc, axis, -40.0 * kPi / 180);
    const PenetrationResult one_shot = cylindrical_segmenting(table, posed, options);
    const auto one_shot_done = std::chrono::steady_clock::now();
    const auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    std::cout << "[ timing ] " << threads << " thread(s), pelvis " << pelvis.num_triangles()
              << " triangles, femur " << femur.num_vertices() << " vertices: table "
              << ms(start, table_done) << " ms, pose cache " << ms(table_done, cache_done)
              << " ms, per pose " << ms(cache_done, sweep_done) / kPoses << " ms (" << pairs
              << " pairs over " << kPoses << " poses), one-shot query on the table "
              << ms(sweep_done, one_shot_done) << " ms (" << one_shot.pairs.size() << " pairs)\n";
  }
}

}  // namespace
}  // namespace hipfai::contact
