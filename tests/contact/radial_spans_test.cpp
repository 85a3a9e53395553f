// Radial spans (contact/radial_spans.h): every culling rule has a case where it must NOT cull,
// and the culled query equals the unculled one bit for bit (same vertices, triangles, depths) on
// random meshes, every rule and configuration, and on a generated hip at several poses.
#include "contact/detail/ablation.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_spans.h"
#include "contact/radial_table.h"
#include "contact/ray_triangle.h"
#include "geometry/hip_generator.h"
#include "geometry/primitive_meshes.h"
#include "tests/oracle_sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;

// Bit-for-bit equality: culling may only skip work.
void expect_identical_culled(const PenetrationResult& culled, const PenetrationResult& full, const std::string& what) {
  ASSERT_EQ(culled.status, QueryStatus::kOk) << what << ": " << culled.message;
  ASSERT_EQ(full.status, QueryStatus::kOk) << what << ": " << full.message;
  ASSERT_EQ(culled.pairs.size(), full.pairs.size()) << what;
  for (std::size_t i = 0; i < full.pairs.size(); ++i) {
    ASSERT_EQ(culled.pairs[i].mobile_vertex, full.pairs[i].mobile_vertex) << what;
    EXPECT_EQ(culled.pairs[i].fixed_triangle, full.pairs[i].fixed_triangle) << what;
    EXPECT_EQ(culled.pairs[i].depth_mm, full.pairs[i].depth_mm) << what;
  }
}

PenetrationResult query(const RadialTable& table, const TriMesh& fixed, const TriMesh& mobile,
                        RadialConfiguration configuration, RadialCrossingRule rule, bool cull) {
  RadialQueryOptions options;
  options.configuration = configuration;
  options.rule = rule;
  detail::RadialAblation ablation;
  ablation.cull = cull;
  return detail::radial_segmenting(table, fixed, mobile, options, ablation);
}

// Culled == unculled under every rule and configuration.
void expect_culling_exact(const RadialTable& table, const TriMesh& fixed, const TriMesh& mobile,
                          const std::string& what) {
  for (auto configuration : {RadialConfiguration::kMobileInsideFixed, RadialConfiguration::kFixedInsideMobile}) {
    for (auto rule : {RadialCrossingRule::kAdjacent, RadialCrossingRule::kUnion, RadialCrossingRule::kBeyond}) {
      const std::string name = what + " " + to_string(configuration) + " " + to_string(rule);
      expect_identical_culled(query(table, fixed, mobile, configuration, rule, true),
                       query(table, fixed, mobile, configuration, rule, false), name);
    }
  }
}

// The prepared pair drops vertices once per body pair; at every pose it must equal the unculled
// query on the posed mesh, also for poses that translate (the kept range widens).
void expect_pose_query_exact(const RadialTable& table, const TriMesh& fixed, const TriMesh& mobile,
                             const std::vector<Eigen::Isometry3d>& poses, const std::string& what) {
  for (auto configuration : {RadialConfiguration::kMobileInsideFixed, RadialConfiguration::kFixedInsideMobile}) {
    for (auto rule : {RadialCrossingRule::kAdjacent, RadialCrossingRule::kUnion, RadialCrossingRule::kBeyond}) {
      for (int threads : {1, 2}) {
        RadialQueryOptions options;
        options.configuration = configuration;
        options.rule = rule;
        options.num_threads = threads;
        const RadialPoseQuery prepared(table, fixed, mobile, options);
        ASSERT_EQ(prepared.status(), QueryStatus::kOk) << prepared.message();
        for (std::size_t k = 0; k < poses.size(); ++k) {
          TriMesh posed = mobile;
          geometry::apply_transform(posed, poses[k]);
          expect_identical_culled(prepared.query(poses[k]), query(table, fixed, posed, configuration, rule, false),
                           what + " pose " + std::to_string(k) + " " + to_string(configuration) + " threads " +
                               std::to_string(threads));
        }
      }
    }
  }
}

Eigen::Isometry3d turn_about(const Vec3& centre, const Vec3& axis, double angle_deg, const Vec3& shift) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(angle_deg * 3.14159265358979323846 / 180.0, axis.normalized()).toRotationMatrix();
  return Eigen::Translation3d(centre + shift) * pose * Eigen::Translation3d(-centre);
}

TriMesh one_vertex(const Vec3& p) {
  TriMesh mesh;
  mesh.vertices = {p};
  return mesh;
}

bool reported(const PenetrationResult& result) { return result.pairs.size() == 1; }

// A box above O: its bottom face z = 10 is the nearest surface, so the box's span starts at 10.
TriMesh box_above() { return geometry::make_box(Vec3(-6, -6, 10), Vec3(6, 6, 22), 4); }

TEST(RadialSpans, SpanOfATriangleContainsEveryCrossingAndTheBorderItself) {
  double lo = 0.0, hi = 0.0;
  triangle_radial_span(Vec3(-1, -1, 10), Vec3(3, -1, 10), Vec3(-1, 3, 10), lo, hi);
  EXPECT_LE(lo, 10.0);
  EXPECT_GT(lo, 10.0 * (1.0 - 1e-9));
  EXPECT_GE(hi, std::sqrt(9.0 + 1.0 + 100.0));
  // A vertex exactly at lo or hi is on the border: never outside.
  EXPECT_FALSE(outside_span(SpanCull::kBelowLo, lo, lo, hi));
  EXPECT_FALSE(outside_span(SpanCull::kAboveHi, hi, lo, hi));
  // A plane through O gets the span [0, inf]: never culled by distance.
  triangle_radial_span(Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), lo, hi);
  EXPECT_EQ(lo, 0.0);
  EXPECT_EQ(hi, RadialSpans::kInfinity);
}

TEST(RadialSpans, VertexJustPastTheSpanBorderIsNotCulled) {
  const TriMesh fixed = box_above();
  const RadialTable table = build_radial_table(fixed, Vec3::Zero(), {});
  ASSERT_LE(table.spans.lo, 10.0);
  // On the surface (r == 10, t == 1): touching, reported by neither.
  for (bool cull : {true, false}) {
    EXPECT_FALSE(reported(query(table, fixed, one_vertex(Vec3(0, 0, 10)), RadialConfiguration::kMobileInsideFixed,
                                RadialCrossingRule::kAdjacent, cull)));
  }
  // One ulp-scale step inside the bottom face: penetrates, so the span must not cull it.
  const Vec3 just_inside(0, 0, std::nextafter(10.0, 11.0));
  for (bool cull : {true, false}) {
    const auto result = query(table, fixed, one_vertex(just_inside), RadialConfiguration::kMobileInsideFixed,
                              RadialCrossingRule::kAdjacent, cull);
    ASSERT_TRUE(reported(result)) << "cull " << cull;
    EXPECT_GT(result.pairs[0].depth_mm, 0.0);
  }
  // Just below the border: culled, and indeed outside.
  EXPECT_TRUE(outside_span(SpanCull::kBelowLo, 9.99, table.spans.lo, table.spans.hi));
  EXPECT_FALSE(reported(query(table, fixed, one_vertex(Vec3(0, 0, 9.99)), RadialConfiguration::kMobileInsideFixed,
                              RadialCrossingRule::kAdjacent, true)));
}

TEST(RadialSpans, VertexOnACellBorderIsNotCulled) {
  const TriMesh fixed = box_above();
  RadialTableOptions options;
  options.table_size = 6 * 16 * 16;  // even dimension: the face centre direction is on four cell borders
  const RadialTable table = build_radial_table(fixed, Vec3::Zero(), options);
  ASSERT_EQ(table.grid.dimension % 2, 0);
  // Directions on cell borders of the +z face: (0, 0, 1) (a1 = a2 = pi/4) and the diagonal.
  for (const Vec3& p : {Vec3(0, 0, 12), Vec3(0, 2, 12), Vec3(2, 0, 12), Vec3(1.5, 1.5, 12)}) {
    for (bool cull : {true, false}) {
      const auto result = query(table, fixed, one_vertex(p), RadialConfiguration::kMobileInsideFixed,
                                RadialCrossingRule::kAdjacent, cull);
      ASSERT_TRUE(reported(result)) << p.transpose() << " cull " << cull;
      EXPECT_NEAR(result.pairs[0].depth_mm, (p.norm() * (1.0 - 10.0 / p.z())), 1e-12);
    }
  }
}

TEST(RadialSpans, VertexDeepInsideIsNotCulled) {
  const TriMesh fixed = box_above();
  const RadialTable table = build_radial_table(fixed, Vec3::Zero(), {});
  for (auto rule : {RadialCrossingRule::kAdjacent, RadialCrossingRule::kUnion, RadialCrossingRule::kBeyond}) {
    const auto result = query(table, fixed, one_vertex(Vec3(0.3, -0.2, 16)), RadialConfiguration::kMobileInsideFixed,
                              rule, true);
    ASSERT_TRUE(reported(result));
    EXPECT_NEAR(result.pairs[0].depth_mm, Vec3(0.3, -0.2, 16).norm() * (1.0 - 10.0 / 16.0), 1e-12);
  }
  // The other configuration: O inside a box, a vertex inside it beyond nothing culls.
  const TriMesh around = geometry::make_box(Vec3(-10, -10, -10), Vec3(10, 10, 10), 3);
  const RadialTable around_table = build_radial_table(around, Vec3::Zero(), {});
  EXPECT_TRUE(reported(query(around_table, around, one_vertex(Vec3(1, 2, 3)), RadialConfiguration::kFixedInsideMobile,
                             RadialCrossingRule::kAdjacent, true)));
}

TEST(RadialSpans, VertexBeyondTheSpanWithOddParityIsNotCulled) {
  // An open patch whose normal faces O, like a socket: a ray from O enters it, and a vertex
  // beyond it, seen from O, is inside by the adjacent rule although it is beyond the patch's
  // whole span (one crossing: odd parity).
  TriMesh patch;
  patch.vertices = {Vec3(-5, -5, 10), Vec3(5, -5, 10), Vec3(5, 5, 10), Vec3(-5, 5, 10)};
  patch.triangles = {{0, 2, 1}, {0, 3, 2}};  // normal -z: a ray from O enters
  const RadialTable table = build_radial_table(patch, Vec3::Zero(), {});
  const Vec3 beyond(0.5, 0.5, 30.0);
  ASSERT_GT(beyond.norm(), table.spans.hi);
  for (bool cull : {true, false}) {
    const auto result = query(table, patch, one_vertex(beyond), RadialConfiguration::kMobileInsideFixed,
                              RadialCrossingRule::kAdjacent, cull);
    ASSERT_TRUE(reported(result)) << "cull " << cull;
    EXPECT_NEAR(result.pairs[0].depth_mm, beyond.norm() * (1.0 - 10.0 / 30.0), 1e-12);
  }
  // A closed solid seen from outside: the union rule finds no winding beyond hi (culled, and
  // the full test agrees).
  const TriMesh fixed = box_above();
  const RadialTable box_table = build_radial_table(fixed, Vec3::Zero(), {});
  for (bool cull : {true, false}) {
    EXPECT_FALSE(reported(query(box_table, fixed, one_vertex(Vec3(0, 0, 40)), RadialConfiguration::kMobileInsideFixed,
                                RadialCrossingRule::kUnion, cull)));
  }
}

TEST(RadialSpans, OutsideTheCapIsCulledAndTheCapHoldsEveryTriangle) {
  const TriMesh fixed = box_above();
  const RadialTable table = build_radial_table(fixed, Vec3::Zero(), {});
  ASSERT_GT(table.spans.cap_cos, 0.0);
  EXPECT_TRUE(outside_cap(table.spans, Vec3(0, 0, -1), 1.0));
  // Every point of every triangle (corners, edge midpoints, centroid) is inside the cap.
  for (const auto& tri : fixed.triangles) {
    const Vec3 a = fixed.vertices[static_cast<std::size_t>(tri[0])], b = fixed.vertices[static_cast<std::size_t>(tri[1])],
               c = fixed.vertices[static_cast<std::size_t>(tri[2])];
    for (const Vec3& p : {a, b, c, Vec3((a + b) / 2), Vec3((b + c) / 2), Vec3((a + b + c) / 3)}) {
      EXPECT_FALSE(outside_cap(table.spans, p, p.norm()));
    }
  }
}

TEST(RadialSpans, CubeLocatorFindsTheCellOfCellOfDirection) {
  // Random directions (never within rounding of a border) and directions on the face's axes and
  // diagonals, where the borders of an even grid lie: the same cell as the atan mapping.
  const TriMesh fixed = box_above();
  for (const std::int64_t size : {6, 600, 6 * 16 * 16, 98304}) {
    RadialTableOptions options;
    options.table_size = size;
    const RadialTable table = build_radial_table(fixed, Vec3::Zero(), options);
    ASSERT_EQ(table.spans.cube.dimension, table.grid.dimension);
    std::mt19937_64 rng(static_cast<std::uint64_t>(size));
    std::normal_distribution<double> g;
    for (int k = 0; k < 20000; ++k) {
      const Vec3 d(g(rng), g(rng), g(rng));
      ASSERT_EQ(table.spans.cube.cell(d), cell_of_direction(table.grid, d)) << d.transpose();
    }
    for (const Vec3& d : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(1, 1, 0.5), Vec3(-1, 1, 1), Vec3(2, 1, -2)}) {
      EXPECT_EQ(table.spans.cube.cell(d), cell_of_direction(table.grid, d)) << d.transpose();
    }
  }
}

TEST(RadialSpans, DeformedFixedMeshFallsBackToTheFullTest) {
  TriMesh fixed = box_above();
  const RadialTable table = build_radial_table(fixed, Vec3::Zero(), {});
  EXPECT_TRUE(radial_spans_valid(table.spans, fixed));
  for (auto& v : fixed.vertices) v *= 0.5;  // moved along the rays: the bottom face now at z = 5
  EXPECT_FALSE(radial_spans_valid(table.spans, fixed));
  const auto result = query(table, fixed, one_vertex(Vec3(0, 0, 7)), RadialConfiguration::kMobileInsideFixed,
                            RadialCrossingRule::kAdjacent, true);
  ASSERT_TRUE(reported(result));
  EXPECT_NEAR(result.pairs[0].depth_mm, 2.0, 1e-12);
}

TEST(RadialSpans, CulledEqualsUnculledOnRandomMeshes) {
  std::mt19937_64 rng(18);
  std::normal_distribution<double> g;
  for (int k = 0; k < 6; ++k) {
    const Vec3 centre(g(rng), g(rng), g(rng));
    TriMesh fixed = geometry::make_octasphere(centre, 20.0, 3);
    TriMesh mobile = geometry::make_octasphere(centre + Vec3(g(rng), g(rng), g(rng)), 19.0, 3);
    std::uniform_real_distribution<double> u(-0.08, 0.08);
    for (auto& v : fixed.vertices) v = centre + (v - centre) * (1.0 + u(rng));
    for (auto& v : mobile.vertices) v = centre + (v - centre) * (1.0 + u(rng));
    // A box beside the spheres gives cells with several layers and empty cells.
    const TriMesh box = geometry::make_box(centre + Vec3(5, -8, 8), centre + Vec3(25, 8, 30), 3);
    const TriMesh both = geometry::merge_meshes({&fixed, &box});
    for (auto mapping : {RadialMapping::kCube, RadialMapping::kSpherical, RadialMapping::kCartesian}) {
      RadialTableOptions options;
      options.mapping = mapping;
      options.table_size = 600;
      const RadialTable table = build_radial_table(both, centre, options);
      expect_culling_exact(table, both, mobile, "random " + std::to_string(k) + " " + to_string(mapping));
    }
  }
}

TEST(RadialSpansOnGeneratedHip, CulledEqualsUnculledAtSeveralPoses) {
  geometry::HipParameters parameters;
  parameters.ce_deg = 30.0;
  parameters.alpha_deg = 60.0;
  parameters.edge_mm = 5.5;  // the benchmark's coarse hip
  const geometry::HipModel hip = geometry::generate_hip(parameters).model;
  const TriMesh socket = geometry::merge_meshes({&hip.tissue("acetabular_cartilage"), &hip.tissue("labrum")});
  const TriMesh femur = geometry::merge_meshes({&hip.tissue("femur_bone"), &hip.tissue("femoral_cartilage")});
  const Vec3 centre = hip.hjc_mm;
  RadialTableOptions options;
  options.table_size = 2 * static_cast<std::int64_t>(socket.num_triangles());
  const RadialTable table = build_radial_table(socket, centre, options);
  const double step = 0.6;
  for (const double angle_deg : {0.0, 10.0, 25.0, 40.0, 70.0}) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(angle_deg * 3.14159265358979323846 / 180.0,
                                      hip.axes.flexion_axis.normalized()).toRotationMatrix();
    pose = Eigen::Translation3d(centre + step * hip.superior.normalized()) * pose * Eigen::Translation3d(-centre);
    TriMesh posed = femur;
    geometry::apply_transform(posed, pose);
    expect_culling_exact(table, socket, posed, "hip " + std::to_string(angle_deg) + " deg");
    expect_pose_query_exact(table, socket, femur, {pose}, "hip " + std::to_string(angle_deg) + " deg");
    // At least the sliding pose must penetrate, or the test would prove nothing.
    if (angle_deg == 0.0) {
      EXPECT_FALSE(query(table, socket, posed, RadialConfiguration::kMobileInsideFixed, RadialCrossingRule::kUnion, true)
                       .pairs.empty());
    }
  }
}

// query_rotation poses as the studies do, O + R (v - O): equal bit for bit to the unculled query
// on the mesh posed that way, on a generated hip turned about its centre (the FAI study's use).
TEST(RadialSpansOnGeneratedHip, RotationQueryEqualsTheQueryOnTheMeshTurnedAboutTheCentre) {
  geometry::HipParameters parameters;
  parameters.ce_deg = 40.0;
  parameters.alpha_deg = 80.0;
  parameters.edge_mm = 5.5;
  const geometry::HipModel hip = geometry::generate_hip(parameters).model;
  const TriMesh socket = geometry::merge_meshes({&hip.tissue("acetabular_cartilage"), &hip.tissue("labrum")});
  const TriMesh femur = geometry::merge_meshes({&hip.tissue("femur_bone"), &hip.tissue("femoral_cartilage")});
  const Vec3 centre = hip.hjc_mm;
  RadialTableOptions table_options;
  table_options.table_size = static_cast<std::int64_t>(socket.num_triangles());
  const RadialTable table = build_radial_table(socket, centre, table_options);
  bool any = false;
  for (auto rule : {RadialCrossingRule::kAdjacent, RadialCrossingRule::kUnion, RadialCrossingRule::kBeyond}) {
    RadialQueryOptions options;
    options.rule = rule;
    const RadialPoseQuery prepared(table, socket, femur, options);
    for (const double angle_deg : {0.0, 30.0, 60.0, 90.0}) {
      const Eigen::Matrix3d rotation =
          Eigen::AngleAxisd(angle_deg * 3.14159265358979323846 / 180.0, hip.axes.flexion_axis.normalized()).toRotationMatrix();
      TriMesh posed = femur;
      for (auto& v : posed.vertices) v = centre + rotation * (v - centre);
      const auto full = query(table, socket, posed, RadialConfiguration::kMobileInsideFixed, rule, false);
      expect_identical_culled(prepared.query_rotation(rotation), full,
                       std::string(to_string(rule)) + " " + std::to_string(angle_deg) + " deg");
      any = any || !full.pairs.empty();
    }
  }
  EXPECT_TRUE(any);  // the combined hip impinges in deep flexion: the comparison has pairs
}

TEST(RadialSpans, PoseQueryEqualsTheUnculledQueryOnThePosedMesh) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g;
  const Vec3 centre(0.3, -0.2, 0.1);
  TriMesh inner = geometry::make_octasphere(centre, 24.0, 3);
  for (auto& t : inner.triangles) std::swap(t[1], t[2]);  // a shell: inner surface faces O
  const TriMesh outer = geometry::make_octasphere(centre, 28.0, 2);
  const TriMesh socket = geometry::merge_meshes({&inner, &outer});
  TriMesh ball = geometry::make_octasphere(centre, 24.2, 3);
  // A second, smaller ball inside: vertices that can never reach the socket (dropped once).
  const TriMesh core = geometry::make_octasphere(centre, 10.0, 2);
  const TriMesh mobile = geometry::merge_meshes({&ball, &core});
  const RadialTable table = build_radial_table(socket, centre, {});
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k < 5; ++k) {
    poses.push_back(turn_about(centre, Vec3(g(rng), g(rng), g(rng)), 40.0 * g(rng), k < 3 ? Vec3::Zero() : Vec3(0.5 * g(rng), 0.5 * g(rng), 0.5 * g(rng))));
  }
  expect_pose_query_exact(table, socket, mobile, poses, "shell");
  RadialQueryOptions options;
  const RadialPoseQuery prepared(table, socket, mobile, options);
  EXPECT_LE(prepared.num_kept_vertices(), ball.num_vertices());  // the core is dropped
}

// The pose query's bucket rules against the spans' cap (a box beside O: every fixed point within
// a cone of directions). A ball of mobile vertices around O, turned and shifted: most buckets face
// away from the box and are dropped whole, and the answer equals the unculled query on the posed
// mesh at every pose, every rule and configuration, 1 and 2 threads.
TEST(RadialSpans, PoseQueryDropsBucketsOutsideTheCapAndStaysExact) {
  const TriMesh box = box_above();
  const RadialTable table = build_radial_table(box, Vec3::Zero(), {});
  ASSERT_GT(table.spans.cap_cos, 0.0);
  TriMesh ball = geometry::make_octasphere(Vec3::Zero(), 14.0, 4);
  std::mt19937_64 rng(31);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (auto& v : ball.vertices) v *= 1.0 + 0.4 * u(rng);  // radii 12.3-15.7: the box's bottom at 10
  std::vector<Eigen::Isometry3d> poses{Eigen::Isometry3d::Identity()};
  for (int k = 0; k < 6; ++k) {
    poses.push_back(turn_about(Vec3::Zero(), Vec3(g(rng), g(rng), g(rng)), 60.0 * g(rng),
                               k < 3 ? Vec3::Zero() : Vec3(g(rng), g(rng), g(rng))));
  }
  expect_pose_query_exact(table, box, ball, poses, "ball beside a box");
  const RadialPoseQuery prepared(table, box, ball, {});
  for (const auto& pose : poses) {
    const std::size_t tested = prepared.num_tested_vertices(pose);
    EXPECT_LT(tested, ball.num_vertices() / 2);  // the cap is ~50 deg wide: most buckets dropped
    TriMesh posed = ball;
    geometry::apply_transform(posed, pose);
    EXPECT_GE(tested, query(table, box, posed, RadialConfiguration::kMobileInsideFixed, RadialCrossingRule::kAdjacent, true)
                          .pairs.size());
  }
}

// Must not cull: a vertex inside the box next to the corner that bounds the cap (its direction
// within 1e-9 rad of the cap's border), alone and among far vertices that widen its bucket's cone,
// at rest and turned into place from elsewhere (its rest direction then far outside the cap).
TEST(RadialSpans, PoseQueryKeepsAVertexOnTheCapBorder) {
  const TriMesh box = box_above();
  const RadialTable table = build_radial_table(box, Vec3::Zero(), {});
  Vec3 corner = box.vertices.front();  // the box's widest direction from O: a bottom corner
  for (const Vec3& v : box.vertices) {
    if (v.normalized().dot(table.spans.cap_axis) < corner.normalized().dot(table.spans.cap_axis)) corner = v;
  }
  ASSERT_NEAR(std::acos(corner.normalized().dot(table.spans.cap_axis)), std::acos(table.spans.cap_cos), 1e-9);
  const Vec3 inside = corner + 1e-6 * (Vec3(0, 0, 16) - corner);  // in the box, beside the corner
  const Eigen::Isometry3d away = turn_about(Vec3::Zero(), Vec3(1, -1, 0.3), 150.0, Vec3::Zero());
  for (const bool crowded : {false, true}) {
    TriMesh mobile = one_vertex(inside);
    if (crowded) {
      for (int k = 1; k <= 40; ++k) mobile.vertices.push_back(Vec3(-20.0 + k, 30.0 - k, -10.0 + 0.5 * k));
    }
    for (const bool turned : {false, true}) {
      // Turned: the mobile mesh rests turned away, and the pose brings it back.
      TriMesh rest = mobile;
      if (turned) geometry::apply_transform(rest, away.inverse());
      const Eigen::Isometry3d pose = turned ? away : Eigen::Isometry3d::Identity();
      const RadialPoseQuery prepared(table, box, rest, {});
      const auto result = prepared.query(pose);
      ASSERT_FALSE(result.pairs.empty()) << "crowded " << crowded << " turned " << turned;
      EXPECT_EQ(result.pairs[0].mobile_vertex, 0);
      expect_pose_query_exact(table, box, rest, {pose}, "cap border");
    }
  }
}

TEST(RadialSpans, PoseQueryRejectsANonFinitePose) {
  const TriMesh fixed = box_above();
  const RadialTable table = build_radial_table(fixed, Vec3::Zero(), {});
  const RadialPoseQuery prepared(table, fixed, one_vertex(Vec3(0, 0, 12)), {});
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().x() = std::nan("");
  EXPECT_EQ(prepared.query(pose).status, QueryStatus::kInvalidInput);
  EXPECT_EQ(prepared.query(Eigen::Isometry3d::Identity()).pairs.size(), 1u);
}


// The generated hip's socket (acetabular cartilage and labrum) with its table about the HJC, about
// one cell per triangle (as the bench builds it).
struct Socket {
  TriMesh mesh;
  RadialTable table;
};
Socket generated_socket(double edge_mm) {
  geometry::HipParameters parameters;
  parameters.edge_mm = edge_mm;
  const geometry::HipModel hip = geometry::generate_hip(parameters).model;
  Socket socket;
  socket.mesh = geometry::merge_meshes({&hip.tissue("acetabular_cartilage"), &hip.tissue("labrum")});
  RadialTableOptions options;
  options.table_size = static_cast<std::int64_t>(socket.mesh.num_triangles());
  socket.table = build_radial_table(socket.mesh, hip.hjc_mm, options);
  return socket;
}

// SEPARATED CONES (RadialSpans::separated, ConeSeparation). The claim the query relies on: a ray
// strictly inside the cone over triangle t misses every triangle separated from t. Checked with the
// exact ray test on random directions inside t's cone (positive barycentric weights), for every
// separated pair the table records, on a sphere seen from inside and on a generated hip's socket.
void expect_separations_hold(const RadialTable& table, const TriMesh& fixed, std::size_t min_pairs, const std::string& what) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> w(1e-6, 1.0);
  auto relative = [&](std::int32_t t, int k) {
    return Vec3(fixed.vertices[static_cast<std::size_t>(fixed.triangles[static_cast<std::size_t>(t)][static_cast<std::size_t>(k)])] -
                table.centre);
  };
  std::size_t pairs = 0;
  for (const RadialSpans::Cell& cell : table.spans.cells) {
    for (std::uint32_t i = cell.begin; i < cell.end; ++i) {
      const std::uint32_t bits = table.spans.entries[i].separated;
      if (i < cell.wedge_end) {
        EXPECT_EQ(bits, 0U) << what;  // flat triangles are never separated
      }
      for (std::uint32_t j = cell.wedge_end; j < cell.end && j - cell.wedge_end < 32; ++j) {
        if (((bits >> (j - cell.wedge_end)) & 1U) == 0) continue;
        ++pairs;
        const std::int32_t t = table.spans.entries[i].triangle, u = table.spans.entries[j].triangle;
        for (int k = 0; k < 8; ++k) {
          const Vec3 d = w(rng) * relative(t, 0) + w(rng) * relative(t, 1) + w(rng) * relative(t, 2);
          ASSERT_FALSE(ray_triangle_crossing(d, relative(u, 0), relative(u, 1), relative(u, 2)).hit)
              << what << ": triangles " << t << " and " << u;
        }
      }
    }
  }
  EXPECT_GE(pairs, min_pairs) << what;  // the rule is exercised, not vacuous
}

TEST(RadialSpans, SeparatedConesAreMissedByEveryRayInsideTheOther) {
  const TriMesh sphere = geometry::make_octasphere(Vec3(0.4, -0.3, 0.2), 20.0, 3);
  expect_separations_hold(build_radial_table(sphere, Vec3::Zero(), {}), sphere, 500, "sphere");
  // A box above O: its bottom, side and top faces seen from O overlap pairwise (not separated).
  const TriMesh box = box_above();
  expect_separations_hold(build_radial_table(box, Vec3::Zero(), {}), box, 100, "box");
  const Socket socket = generated_socket(5.5);
  expect_separations_hold(socket.table, socket.mesh, 1000, "socket");
}

TEST(RadialSpans, ConeSeparationHardCases) {
  // Two triangles sharing an edge on a plane z = 10 (seen from O): their cones meet only along the
  // shared edge's plane, which holds the shared vertices exactly: separated.
  TriMesh flat;
  flat.vertices = {Vec3(-1, -1, 10), Vec3(1, -1, 10), Vec3(1, 1, 10), Vec3(-1, 1, 10)};
  flat.triangles = {{0, 1, 2}, {0, 2, 3}};
  auto separated = [](const TriMesh& mesh, const Vec3& centre) {
    std::vector<RadialSpans::TrianglePlanes> planes;
    for (const auto& tri : mesh.triangles) {
      planes.push_back(triangle_planes(mesh.vertices[static_cast<std::size_t>(tri[0])] - centre,
                                       mesh.vertices[static_cast<std::size_t>(tri[1])] - centre,
                                       mesh.vertices[static_cast<std::size_t>(tri[2])] - centre));
    }
    const ConeSeparation separation(mesh, centre, planes);
    EXPECT_EQ(separation.separated(0, 1), separation.separated(1, 0));
    return separation.separated(0, 1);
  };
  EXPECT_TRUE(separated(flat, Vec3::Zero()));
  // The same pair with its shared edge given by copies of the vertices (other indices): the
  // zero of the shared edge is then a rounded value, not known exactly, so no claim is made.
  TriMesh copies = flat;
  copies.vertices.push_back(flat.vertices[0]);
  copies.vertices.push_back(flat.vertices[2]);
  copies.triangles = {{0, 1, 2}, {4, 5, 3}};
  EXPECT_FALSE(separated(copies, Vec3::Zero()));
  // Seen from a centre in their plane (a plane through O): no interior, never separated.
  EXPECT_FALSE(separated(flat, Vec3(5, 0, 10)));
  // One behind the other along the same directions (overlapping cones): not separated.
  TriMesh layered;
  layered.vertices = {Vec3(-1, -1, 10), Vec3(1, -1, 10), Vec3(0, 1, 10), Vec3(-1, -1, 12), Vec3(1, -1, 12), Vec3(0, 1, 12)};
  layered.triangles = {{0, 1, 2}, {3, 4, 5}};
  EXPECT_FALSE(separated(layered, Vec3::Zero()));
  // Touching at a single shared vertex, apart elsewhere: separated.
  TriMesh fan;
  fan.vertices = {Vec3(0, 0, 10), Vec3(1, -1, 10), Vec3(1, 1, 10), Vec3(-1, 2, 10), Vec3(-2, 1, 10)};
  fan.triangles = {{0, 1, 2}, {0, 3, 4}};
  EXPECT_TRUE(separated(fan, Vec3::Zero()));
  // A copy of the second triangle moved across the shared edge's plane by 1e-15 of its size
  // (within the rounding bound, other vertex indices): too close to call, not separated.
  TriMesh grazing = flat;
  for (const int k : {0, 2, 3}) grazing.vertices.push_back(flat.vertices[static_cast<std::size_t>(k)] + 1e-14 * Vec3(1, -1, 0));
  grazing.triangles = {{0, 1, 2}, {4, 5, 6}};
  EXPECT_FALSE(separated(grazing, Vec3::Zero()));
}

// Rays through the fixed mesh's shared vertices and edges (where no crossing is clear) and just
// beside them, at distances before, on and beyond the surface: the separated-cone skips and the
// stop at the first entry beyond r must give the unculled answers bit for bit, for cells of a few
// and of more than 64 entries (a 6-cell table).
TEST(RadialSpans, RaysThroughSharedEdgesAndVerticesMatchTheUnculledQuery) {
  const Vec3 centre(0.3, -0.2, 0.1);
  TriMesh inner = geometry::make_octasphere(centre, 24.0, 3);
  for (auto& t : inner.triangles) std::swap(t[1], t[2]);  // a shell: inner surface faces O
  const TriMesh outer = geometry::make_octasphere(centre, 28.0, 2);
  const TriMesh socket = geometry::merge_meshes({&inner, &outer});
  TriMesh mobile;
  for (std::size_t t = 0; t < inner.triangles.size(); t += static_cast<std::size_t>(test::kOracleThinning)) {
    const auto& tri = inner.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = inner.vertices[static_cast<std::size_t>(tri[static_cast<std::size_t>(k)])];
      const Vec3 b = inner.vertices[static_cast<std::size_t>(tri[static_cast<std::size_t>((k + 1) % 3)])];
      for (const Vec3& p : {a, Vec3(0.5 * (a + b)), Vec3(a + 1e-12 * (b - a))}) {
        for (const double scale : {0.999, 1.0, 1.0 + 1e-15, 1.001, 1.2}) mobile.vertices.push_back(centre + scale * (p - centre));
      }
    }
  }
  for (const std::int64_t size : {6, 600, 4096}) {
    RadialTableOptions options;
    options.table_size = size;
    const RadialTable table = build_radial_table(socket, centre, options);
    expect_culling_exact(table, socket, mobile, "shared edges, table " + std::to_string(size));
  }
}

// THE DISTANCE MAP of the pose query: a socket (lo 24) on one side of O and a box (lo 10) on the
// other. A ball of radius 15-16 is beyond the box's span but short of the socket's, so the global
// span keeps every bucket, the map drops those that face the socket, and the answers equal the
// unculled query at rest, turned, and turned with translations both within the map's reach and
// far beyond it (where it must fall back to the per-vertex test).
TEST(RadialSpans, PoseQueryDistanceMapDropsBucketsFacingFarSurfacesAndStaysExact) {
  TriMesh inner = geometry::make_octasphere(Vec3::Zero(), 24.0, 3);
  for (auto& t : inner.triangles) std::swap(t[1], t[2]);
  TriMesh cap;  // the upper half of the inner shell: a socket patch
  cap.vertices = inner.vertices;
  for (const auto& t : inner.triangles) {
    if (inner.vertices[static_cast<std::size_t>(t[0])].z() > 1.0 && inner.vertices[static_cast<std::size_t>(t[1])].z() > 1.0 &&
        inner.vertices[static_cast<std::size_t>(t[2])].z() > 1.0) {
      cap.triangles.push_back(t);
    }
  }
  const TriMesh box = geometry::make_box(Vec3(-5, -5, -25), Vec3(5, 5, -10), 6);
  const TriMesh fixed = geometry::merge_meshes({&cap, &box});
  TriMesh ball = geometry::make_octasphere(Vec3::Zero(), 15.0, 6);
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto& v : ball.vertices) v *= 1.0 + 0.06 * u(rng);  // radii 15-15.9
  const RadialTable table = build_radial_table(fixed, Vec3::Zero(), {});
  const RadialPoseQuery prepared(table, fixed, ball, {});
  EXPECT_EQ(prepared.num_kept_vertices(), ball.num_vertices());  // the global span keeps them all
  const std::size_t tested = prepared.num_tested_vertices(Eigen::Isometry3d::Identity());
  EXPECT_LT(tested, ball.num_vertices() / 2);  // the buckets facing the socket are dropped
  std::normal_distribution<double> g;
  std::vector<Eigen::Isometry3d> poses{Eigen::Isometry3d::Identity()};
  for (int k = 0; k < 6; ++k) {
    const double reach = k < 2 ? 0.0 : (k < 4 ? 0.3 : (k < 5 ? 6.0 : 20.0));
    poses.push_back(turn_about(Vec3::Zero(), Vec3(g(rng), g(rng), g(rng)), 50.0 * g(rng),
                               reach * Vec3(g(rng), g(rng), g(rng)).normalized()));
  }
  // Shifted sideways by most of the ball's radius: vertices whose rest directions lie 28-48 deg
  // from the box's axis enter it, their directions turned by up to ~50 deg, beyond the map's
  // dilation: the map must not be used for them.
  poses.push_back(turn_about(Vec3::Zero(), Vec3::UnitX(), 0.0, Vec3(-12.0, 0, 0)));
  poses.push_back(turn_about(Vec3::Zero(), Vec3(1, 2, 0.5), 10.0, Vec3(-11.0, 2.0, 0.0)));
  expect_pose_query_exact(table, fixed, ball, poses, "distance map");
  // A translation beyond the ball's radius: no bucket's directions are bounded, the map drops nothing.
  const Eigen::Isometry3d far = turn_about(Vec3::Zero(), Vec3::UnitX(), 0.0, Vec3(0, 0, 20.0));
  EXPECT_EQ(prepared.num_tested_vertices(far), ball.num_vertices());
}

// FLAT WEDGES (RadialSpans::wedges): every ray inside the cone over a triangle of a cell's wedge
// lies within the wedge (checked on random rays with positive barycentric weights), on the
// generated hip's socket (its rim faces lie in planes through O) and on a revolved band whose faces
// are exactly such planes.
void expect_wedges_hold(const RadialTable& table, const TriMesh& fixed, std::size_t min_wedges, const std::string& what) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> w(1e-6, 1.0);
  const RadialSpans& spans = table.spans;
  std::size_t wedges = 0;
  for (const RadialSpans::Cell& cell : spans.cells) {
    if (cell.wedge_end == cell.begin) continue;
    ++wedges;
    const RadialSpans::FlatWedge& wedge = spans.wedges[cell.wedge];
    const Vec3& normal = wedge.normal;
    for (std::uint32_t e = cell.begin; e < cell.wedge_end; ++e) {
      const auto& tri = fixed.triangles[static_cast<std::size_t>(spans.entries[e].triangle)];
      ASSERT_EQ(spans.triangle_lo[static_cast<std::size_t>(spans.entries[e].triangle)], 0.0) << what;
      for (int k = 0; k < 16 / test::kOracleThinning; ++k) {
        Vec3 d = Vec3::Zero();
        for (const auto v : tri) d += w(rng) * (fixed.vertices[static_cast<std::size_t>(v)] - table.centre);
        ASSERT_LE(std::abs(d.dot(normal)), wedge.sin_bound * d.norm()) << what;
      }
    }
  }
  EXPECT_GE(wedges, min_wedges) << what;
}

// A band of faces on the cone of revolution of half-angle 60 deg about z through `centre` (every
// face in a plane through it), from 24 to 28 mm, in `rings` rings of `segments` faces around.
TriMesh revolved_band(const Vec3& centre, int segments, int rings) {
  TriMesh band;
  const double slant = 60.0 * 3.14159265358979323846 / 180.0;
  for (int ring = 0; ring <= rings; ++ring) {
    const double r = 24.0 + 4.0 * ring / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * 3.14159265358979323846 * s / segments;
      band.vertices.push_back(centre + r * Vec3(std::sin(slant) * std::cos(phi), std::sin(slant) * std::sin(phi), std::cos(slant)));
    }
  }
  for (int ring = 0; ring < rings; ++ring) {
    for (int s = 0; s < segments; ++s) {
      const int a = ring * segments + s, b = ring * segments + (s + 1) % segments;
      band.triangles.push_back({a, b, a + segments});
      band.triangles.push_back({b, b + segments, a + segments});
    }
  }
  return band;
}

TEST(RadialSpans, FlatWedgesHoldEveryRayInTheirTrianglesCones) {
  const Vec3 centre(0.2, 0.1, -0.3);
  const TriMesh band = revolved_band(centre, 96, 6);
  RadialTableOptions options;
  options.table_size = 20000;
  expect_wedges_hold(build_radial_table(band, centre, options), band, 100, "revolved band");
  const Socket socket = generated_socket(2.5);
  expect_wedges_hold(socket.table, socket.mesh, 10, "socket");
}

TEST(RadialSpans, FlatWedgeHardCases) {
  using Triangle = std::array<Vec3, 3>;
  auto wedge_of = [](std::vector<Triangle> triangles) { return flat_wedge(triangles); };
  // Faces exactly in the plane z = 0 through O: a wedge around it, as thin as the margin.
  const RadialSpans::FlatWedge plane = wedge_of({{Vec3(10, 0, 0), Vec3(20, 1, 0), Vec3(15, 4, 0)},
                                                 {Vec3(10, 0, 0), Vec3(15, 4, 0), Vec3(9, 3, 0)}});
  EXPECT_LT(plane.sin_bound, 1e-8);
  EXPECT_NEAR(std::abs(plane.normal.z()), 1.0, 1e-12);
  // A face around O in its plane (its cone is nearly a half-space): no wedge.
  EXPECT_GT(wedge_of({{Vec3(10, -1, 1e-9), Vec3(-10, -1, 0), Vec3(0, 10, 0)}}).sin_bound, 1.0);
  // A vertex at O: no wedge.
  EXPECT_GT(wedge_of({{Vec3(0, 0, 0), Vec3(20, 1, 0), Vec3(15, 4, 0)}}).sin_bound, 1.0);
  // Faces in planes through O around the three axes: no plane through O passes near them all.
  EXPECT_GT(wedge_of({{Vec3(10, 0, 0), Vec3(20, 1, 0), Vec3(15, 4, 0)},
                      {Vec3(0, 10, 0), Vec3(0, 20, 1), Vec3(0, 15, 4)},
                      {Vec3(0, 0, 10), Vec3(1, 0, 20), Vec3(4, 0, 15)}})
                .sin_bound,
            1.0);
  // A face 1e-11 mm off a plane through O (a real, very thin cone, no span): a vertex whose ray
  // runs inside that cone, and one just outside, give the unculled answers.
  TriMesh rim;
  rim.vertices = {Vec3(24, 0, 1e-11), Vec3(28, 0, 1e-11), Vec3(26, 3, 1e-11), Vec3(26, -3, 1e-11)};
  rim.triangles = {{0, 1, 2}, {0, 3, 1}};
  const TriMesh shell = geometry::make_box(Vec3(30, -8, -8), Vec3(34, 8, 8), 2);
  const TriMesh fixed = geometry::merge_meshes({&rim, &shell});
  TriMesh mobile;
  for (const double z : {0.0, 5e-12, 1e-11, 1.1e-11, 1e-9, 1e-6}) {
    for (const double x : {20.0, 25.0, 27.0, 31.0, 40.0}) mobile.vertices.push_back(Vec3(x, 0.5, z * x / 25.0));
  }
  const RadialTable table = build_radial_table(fixed, Vec3::Zero(), {});
  std::size_t wedges = 0;
  for (const RadialSpans::Cell& cell : table.spans.cells) wedges += cell.wedge_end > cell.begin ? 1 : 0;
  EXPECT_GT(wedges, 0U);
  expect_culling_exact(table, fixed, mobile, "rim face off a plane through O");
}

// HINTS: the hinted entry is tested first. Rays through every part's centre (where the hint was
// taken), its corners and borders (where another triangle may be the one crossed) and random points,
// at distances on, just before and just after every crossing of the ray and between them, give the
// unculled answers bit for bit, on the generated hip's socket and on a two-layer shell.
void expect_hints_exact(const RadialTable& table, const TriMesh& fixed, const std::string& what) {
  const RadialSpans& spans = table.spans;
  ASSERT_GT(spans.cube.dimension, 0) << what;
  const int n = spans.cube.dimension, side = RadialSpans::kHintSide;
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::size_t hinted = 0;
  for (const RadialSpans::Cell& cell : spans.cells) {
    for (const auto h : cell.hint) hinted += h != RadialSpans::kNoHint ? 1 : 0;
  }
  // Hints are there to be used: more than 3 of a cell's 16 parts hinted on average.
  EXPECT_GT(hinted, 3 * spans.cells.size()) << what;
  TriMesh mobile;
  for (std::size_t id = 0; id < spans.cells.size(); id += 3 * static_cast<std::size_t>(test::kOracleThinning)) {
    const RadialSpans::Cell& cell = spans.cells[id];
    if (cell.begin == cell.end) continue;
    const int i = static_cast<int>(id) % n, j = (static_cast<int>(id) / n) % n, face = static_cast<int>(id) / (n * n), k = face / 2;
    auto direction = [&](double fu, double fw) {
      Vec3 d;
      d[k] = face % 2 == 0 ? 1.0 : -1.0;
      d[(k + 1) % 3] = spans.cube.border[static_cast<std::size_t>(i)] +
                       fu * (spans.cube.border[static_cast<std::size_t>(i) + 1] - spans.cube.border[static_cast<std::size_t>(i)]);
      d[(k + 2) % 3] = spans.cube.border[static_cast<std::size_t>(j)] +
                       fw * (spans.cube.border[static_cast<std::size_t>(j) + 1] - spans.cube.border[static_cast<std::size_t>(j)]);
      return d;
    };
    std::vector<Vec3> directions;
    for (int a = 0; a <= 2 * side; ++a) {
      for (int b = 0; b <= 2 * side; ++b) directions.push_back(direction(0.5 * a / side, 0.5 * b / side));
    }
    for (int r = 0; r < 4; ++r) directions.push_back(direction(u01(rng), u01(rng)));
    for (const Vec3& d : directions) {
      std::vector<double> t{0.5, 2.0};
      for (std::uint32_t e = cell.begin; e < cell.end; ++e) {
        const auto& tri = fixed.triangles[static_cast<std::size_t>(spans.entries[e].triangle)];
        const RayCrossing crossing = ray_triangle_crossing(d, fixed.vertices[static_cast<std::size_t>(tri[0])] - table.centre,
                                                           fixed.vertices[static_cast<std::size_t>(tri[1])] - table.centre,
                                                           fixed.vertices[static_cast<std::size_t>(tri[2])] - table.centre);
        if (!crossing.hit) continue;
        for (const double scale : {1.0 - 1e-3, 1.0 - 1e-12, 1.0, 1.0 + 1e-12, 1.0 + 1e-3}) t.push_back(crossing.t * scale);
      }
      for (const double s : t) mobile.vertices.push_back(table.centre + s * d);
    }
  }
  expect_culling_exact(table, fixed, mobile, what);
  RadialQueryOptions options;
  for (auto configuration : {RadialConfiguration::kMobileInsideFixed, RadialConfiguration::kFixedInsideMobile}) {
    options.configuration = configuration;
    const RadialPoseQuery prepared(table, fixed, mobile, options);
    expect_identical_culled(prepared.query(Eigen::Isometry3d::Identity()),
                     query(table, fixed, mobile, configuration, RadialCrossingRule::kAdjacent, false), what + " pose query");
  }
}

TEST(RadialSpans, HintedEntriesGiveTheUnculledAnswersAtPartBordersAndCrossings) {
  const Socket socket = generated_socket(5.5);
  expect_hints_exact(socket.table, socket.mesh, "socket");
  RadialTableOptions options;
  const Vec3 centre(0.3, -0.2, 0.1);
  TriMesh inner = geometry::make_octasphere(centre, 24.0, 3);
  for (auto& t : inner.triangles) std::swap(t[1], t[2]);
  const TriMesh outer = geometry::make_octasphere(centre, 26.0, 4);
  const TriMesh shell = geometry::merge_meshes({&inner, &outer});
  options.table_size = 600;  // several triangles per cell and part
  expect_hints_exact(build_radial_table(shell, centre, options), shell, "shell");
}

// The distance map leaves faces without a span (planes through O up to rounding) out of its spans
// where they fit in a flat wedge, and must then keep every bucket whose posed cone meets the wedge.
// A shell of radius 24 seen from inside, and a face 1e-11 mm off the plane y = 0 (no span: the
// rounding of its crossing parameter is unbounded) at 12-14 mm along +x; a ball of radius 15-16
// whose vertices lie beyond that face, some inside its very thin cone, where the ray enters it:
// those penetrate, every other ball vertex is short of the shell.
TEST(RadialSpans, PoseQueryDistanceMapKeepsBucketsMeetingTheWedgeOfFacesWithoutASpan) {
  TriMesh shell = geometry::make_octasphere(Vec3::Zero(), 24.0, 3);
  for (auto& t : shell.triangles) std::swap(t[1], t[2]);  // facing O
  TriMesh face;
  face.vertices = {Vec3(12, 1e-11, -1), Vec3(14, 1e-11, -1), Vec3(13, 1e-11, 1)};
  face.triangles = {{0, 1, 2}};
  const TriMesh fixed = geometry::merge_meshes({&shell, &face});
  TriMesh ball = geometry::make_octasphere(Vec3::Zero(), 15.0, 5);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.05, 1.0);
  for (int k = 0; k < 20; ++k) {
    const double wa = u(rng), wb = u(rng), wc = u(rng);
    const Vec3 inside = (wa * face.vertices[0] + wb * face.vertices[1] + wc * face.vertices[2]) / (wa + wb + wc);
    ball.vertices.push_back(inside * (15.0 + 0.05 * k) / inside.norm());
  }
  const RadialTable table = build_radial_table(fixed, Vec3::Zero(), {});
  ASSERT_EQ(table.spans.triangle_lo.back(), 0.0);  // the face has no span
  const RadialPoseQuery prepared(table, fixed, ball, {});
  const PenetrationResult rest = prepared.query(Eigen::Isometry3d::Identity());
  ASSERT_EQ(rest.status, QueryStatus::kOk);
  EXPECT_GE(rest.pairs.size(), 10U);  // the vertices inside the face's cone
  EXPECT_LT(prepared.num_tested_vertices(Eigen::Isometry3d::Identity()), ball.num_vertices() / 4);  // the map drops the rest
  std::vector<Eigen::Isometry3d> poses{Eigen::Isometry3d::Identity()};
  for (const double angle : {0.2, 1.0, 5.0}) poses.push_back(turn_about(Vec3::Zero(), Vec3(0.3, 1, 0.2), angle, Vec3::Zero()));
  poses.push_back(turn_about(Vec3::Zero(), Vec3::UnitZ(), 0.0, Vec3(0, 0.2, 0)));
  expect_pose_query_exact(table, fixed, ball, poses, "face without a span");
}
}  // namespace
}  // namespace hipfai::contact
