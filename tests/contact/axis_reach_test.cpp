// The body-pair cull about an axis (contact/axis_reach.h): it keeps everything that can meet (checked
// against a brute force over every pair of boxes, and on exact borders), and the range finder on
// what it keeps equals the range finder on the whole meshes, bit for bit, contacts included.
#include "contact/axis_reach.h"
#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "contact/range_finder.h"
#include "geometry/mesh_io.h"
#include "geometry/primitive_meshes.h"
#include "random_shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;
using test_shapes::random_pose;
using test_shapes::random_shape;

struct RzBox {
  double r_lo, r_hi, z_lo, z_hi;
  bool overlaps(const RzBox& o) const { return r_lo <= o.r_hi && o.r_lo <= r_hi && z_lo <= o.z_hi && o.z_lo <= z_hi; }
};

std::vector<RzBox> triangle_boxes(const TriMesh& mesh, const AxisFrame& frame) {
  std::vector<RzBox> boxes;
  for (const auto& tri : mesh.triangles) {
    const auto b = triangle_cylindrical_bounds(frame.to_local(mesh.vertices[static_cast<std::size_t>(tri[0])]),
                                               frame.to_local(mesh.vertices[static_cast<std::size_t>(tri[1])]),
                                               frame.to_local(mesh.vertices[static_cast<std::size_t>(tri[2])]));
    boxes.push_back({b.r_min, b.r_max, b.z_min, b.z_max});
  }
  return boxes;
}

RzBox point_box(const Vec3& p, const AxisFrame& frame) {
  const Vec3 l = frame.to_local(p);
  const double r = std::hypot(l.x(), l.y());
  return {r, r, l.z(), l.z()};
}

// Brute force: every triangle of `a` whose box overlaps a box of `b` (triangles and vertices), and
// every vertex of `a` inside a box of `b`, must be among the kept ones.
void expect_keeps_every_overlap(const TriMesh& a, const TriMesh& b, const AxisFrame& frame,
                                const std::vector<std::int32_t>& kept_vertices,
                                const std::vector<std::int32_t>& kept_triangles, const std::string& what) {
  const auto a_boxes = triangle_boxes(a, frame), b_boxes = triangle_boxes(b, frame);
  std::vector<RzBox> b_all = b_boxes;
  for (const Vec3& p : b.vertices) b_all.push_back(point_box(p, frame));
  std::vector<bool> vertex_kept(a.vertices.size()), triangle_kept(a.triangles.size());
  for (const auto v : kept_vertices) vertex_kept[static_cast<std::size_t>(v)] = true;
  for (const auto t : kept_triangles) triangle_kept[static_cast<std::size_t>(t)] = true;
  int overlapping = 0;
  for (std::size_t t = 0; t < a.triangles.size(); ++t) {
    bool overlap = false;
    for (const RzBox& box : b_all) overlap = overlap || a_boxes[t].overlaps(box);
    overlapping += overlap;
    if (overlap) {
      EXPECT_TRUE(triangle_kept[t]) << what << ": triangle " << t;
    }
  }
  for (std::size_t v = 0; v < a.vertices.size(); ++v) {
    bool inside = false;
    for (const RzBox& box : b_boxes) inside = inside || point_box(a.vertices[v], frame).overlaps(box);
    if (inside) {
      EXPECT_TRUE(vertex_kept[v]) << what << ": vertex " << v;
    }
  }
  EXPECT_GE(static_cast<int>(kept_triangles.size()), overlapping) << what;
}

void expect_same_contact(const LimitingContact& a, const LimitingContact& b, const std::string& what) {
  EXPECT_EQ(a.kind, b.kind) << what;
  EXPECT_EQ(a.vertex, b.vertex) << what;
  EXPECT_EQ(a.triangle, b.triangle) << what;
  EXPECT_EQ(a.mobile_edge, b.mobile_edge) << what;
  EXPECT_EQ(a.fixed_edge, b.fixed_edge) << what;
}

void expect_same_range(const TriMesh& fixed, const TriMesh& mobile, const Vec3& centre, const Vec3& axis,
                       const std::string& what) {
  RangeOfMotionOptions whole;
  whole.cull_unreachable = false;
  const RangeOfMotion culled = range_of_motion(fixed, mobile, centre, axis);
  const RangeOfMotion reference = range_of_motion(fixed, mobile, centre, axis, whole);
  ASSERT_EQ(culled.status, reference.status) << what;
  EXPECT_EQ(culled.anticlockwise_deg, reference.anticlockwise_deg) << what;
  EXPECT_EQ(culled.clockwise_deg, reference.clockwise_deg) << what;
  expect_same_contact(culled.anticlockwise_limit, reference.anticlockwise_limit, what + " anticlockwise");
  expect_same_contact(culled.clockwise_limit, reference.clockwise_limit, what + " clockwise");
}

TEST(AxisReach, KeepsEveryOverlapOnRandomShapes) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int culled_some = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const TriMesh fixed = random_shape(rng, trial % 3);
    TriMesh mobile = random_shape(rng, (trial + 1) % 3);
    for (Vec3& p : mobile.vertices) p += Vec3(10.0 + 10.0 * u(rng), 0, 0);
    const Vec3 centre(4 * u(rng) - 2, 4 * u(rng) - 2, 4 * u(rng) - 2);
    const Vec3 axis = test_shapes::random_unit(rng);
    const AxisReach reach = reach_about_axis(fixed, mobile, centre, axis);
    const AxisFrame frame = make_axis_frame(centre, axis).frame;
    const std::string what = "trial " + std::to_string(trial);
    expect_keeps_every_overlap(fixed, mobile, frame, reach.fixed_vertices, reach.fixed_triangles, what + " fixed");
    expect_keeps_every_overlap(mobile, fixed, frame, reach.mobile_vertices, reach.mobile_triangles, what + " mobile");
    // The kept meshes are the kept elements, renumbered in order.
    ASSERT_EQ(reach.fixed.triangles.size(), reach.fixed_triangles.size());
    for (std::size_t k = 0; k < reach.fixed_triangles.size(); ++k) {
      for (int c = 0; c < 3; ++c) {
        const auto original = fixed.triangles[static_cast<std::size_t>(reach.fixed_triangles[k])][static_cast<std::size_t>(c)];
        EXPECT_EQ(reach.fixed_vertices[static_cast<std::size_t>(reach.fixed.triangles[k][static_cast<std::size_t>(c)])], original);
      }
    }
    culled_some += reach.fixed_triangles.size() < fixed.triangles.size() ||
                   reach.mobile_triangles.size() < mobile.triangles.size();
    expect_same_range(fixed, mobile, centre, axis, what);
  }
  EXPECT_GT(culled_some, 10);  // the cull does cull
}

// A mobile vertex exactly on the border of a fixed triangle's (r, z) box (the fixed vertex turned
// 90 degrees about the axis: same r and z, a corner of the box), then 1e-12 mm outside it (within
// the rounding margin: kept too), at the end of a far-off mobile sliver.
TEST(AxisReach, KeepsAVertexOnTheBorderOfABox) {
  TriMesh fixed;
  fixed.vertices = {Vec3(10, 0, 0), Vec3(12, 0.5, 0.25), Vec3(11, -0.5, 0.5)};
  fixed.triangles = {{0, 1, 2}};
  for (const double r_offset : {0.0, -1e-12}) {
    TriMesh mobile;
    // (0, 10, 0): r = 10 = the box's r_min, z = 0 = its z_min: a corner of the box.
    mobile.vertices = {Vec3(0, 10 + r_offset, 0), Vec3(-40, 60, 30), Vec3(-41, 61, 31)};
    mobile.triangles = {{0, 1, 2}};
    const AxisReach reach = reach_about_axis(fixed, mobile, Vec3::Zero(), Vec3::UnitZ());
    ASSERT_FALSE(reach.mobile_vertices.empty());
    EXPECT_EQ(reach.mobile_vertices.front(), 0);
    EXPECT_EQ(reach.fixed_triangles, std::vector<std::int32_t>{0});
  }
  // Deep inside the box: kept; far beyond every box (r 100, z 50): the sliver's own vertices are
  // kept only with their triangle, which reaches the fixed box through vertex 0.
  TriMesh mobile;
  mobile.vertices = {Vec3(0, 11, 0.2), Vec3(0, 100, 50), Vec3(0, 101, 51)};
  mobile.triangles = {{1, 2, 1}};  // a degenerate far triangle: nothing of it reaches
  const AxisReach reach = reach_about_axis(fixed, mobile, Vec3::Zero(), Vec3::UnitZ());
  EXPECT_EQ(reach.mobile_vertices, std::vector<std::int32_t>{0});
  EXPECT_TRUE(reach.mobile_triangles.empty());
}

TEST(AxisReach, RealFemurAgainstPelvisSameRangeOnThreeAxes) {
  const std::string folder = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
  const TriMesh pelvis = geometry::read_mesh(folder + "pelvis_no_sacrum.ply");
  const TriMesh femur = geometry::read_mesh(folder + "femur_r.ply");
  const Vec3 hjc(143.80, 243.46, -432.58);
  for (const Vec3& axis : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.3, -0.4, 0.866).normalized()}) {
    const AxisReach reach = reach_about_axis(pelvis, femur, hjc, axis);
    EXPECT_LT(reach.fixed.triangles.size(), pelvis.triangles.size() / 2);
    expect_same_range(pelvis, femur, hjc, axis, "axis " + std::to_string(axis.x()));
  }
}

TEST(AxisReach, BodiesThatCanNeverMeetAreFreeBothWays) {
  // Two spheres on the axis at different heights: their (r, z) never overlap.
  const TriMesh fixed = geometry::make_octasphere(Vec3(0, 0, 0), 3.0, 2);
  const TriMesh mobile = geometry::make_octasphere(Vec3(0, 0, 20), 3.0, 2);
  const AxisReach reach = reach_about_axis(fixed, mobile, Vec3::Zero(), Vec3::UnitZ());
  EXPECT_TRUE(reach.fixed.triangles.empty());
  EXPECT_TRUE(reach.mobile.triangles.empty());
  const RangeOfMotion range = range_of_motion(fixed, mobile, Vec3::Zero(), Vec3::UnitZ());
  EXPECT_EQ(range.status, QueryStatus::kOk);
  EXPECT_EQ(range.anticlockwise_deg, 360.0);
  EXPECT_EQ(range.clockwise_deg, 360.0);
  expect_same_range(fixed, mobile, Vec3::Zero(), Vec3::UnitZ(), "apart");
}

// The range finder's vertex passes read the crossings straight from the tables and skip the
// triangles whose angular extent cannot beat the running minima: the ranges and contacts equal
// those of pose caches that store every crossing (range_of_motion of two caches), on random scenes
// and the CT, with 1 and 2 threads.
TEST(AxisReach, TableScanEqualsThePoseCachesScan) {
  const auto check = [](const TriMesh& fixed, const TriMesh& mobile, const Vec3& centre, const Vec3& axis,
                        const std::string& what) {
    RangeOfMotionOptions vertices_only;
    vertices_only.include_edge_edge = false;
    vertices_only.cull_unreachable = false;
    CylindricalQueryOptions query;
    query.pose_index = false;
    const CylindricalPoseCache mobile_on_fixed(CylindricalTable::build(fixed, centre, axis, {}, &mobile), mobile, query);
    const CylindricalPoseCache fixed_on_mobile(CylindricalTable::build(mobile, centre, axis, {}, &fixed), fixed, query);
    const RangeOfMotion reference = range_of_motion(mobile_on_fixed, &fixed_on_mobile, 1);
    for (const int threads : {1, 2}) {
      vertices_only.query.num_threads = threads;
      const RangeOfMotion range = range_of_motion(fixed, mobile, centre, axis, vertices_only);
      const std::string label = what + ", " + std::to_string(threads) + " threads";
      EXPECT_EQ(range.anticlockwise_deg, reference.anticlockwise_deg) << label;
      EXPECT_EQ(range.clockwise_deg, reference.clockwise_deg) << label;
      expect_same_contact(range.anticlockwise_limit, reference.anticlockwise_limit, label + " anticlockwise");
      expect_same_contact(range.clockwise_limit, reference.clockwise_limit, label + " clockwise");
    }
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 30; ++trial) {
    const TriMesh fixed = random_shape(rng, trial % 3);
    TriMesh mobile = random_shape(rng, (trial + 2) % 3);
    for (Vec3& p : mobile.vertices) p += Vec3(8.0 + 12.0 * u(rng), 0, 0);
    check(fixed, mobile, Vec3(4 * u(rng) - 2, 4 * u(rng) - 2, 4 * u(rng) - 2), test_shapes::random_unit(rng),
          "trial " + std::to_string(trial));
  }
  const std::string folder = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
  check(geometry::read_mesh(folder + "pelvis_no_sacrum.ply"), geometry::read_mesh(folder + "femur_r.ply"),
        Vec3(143.80, 243.46, -432.58), Vec3(0, 0, 1), "CT");
}

// Angular pruning (vertex and edge candidates) changes nothing: on boxes against boxes, where sharp
// edges often meet first, and on the CT, with and without the edge-edge pass.
TEST(AxisReach, AngularPruningChangesNoRangeNorContact) {
  const auto check = [](const TriMesh& fixed, const TriMesh& mobile, const Vec3& centre, const Vec3& axis,
                        const std::string& what) {
    RangeOfMotionOptions pruned, reference;
    reference.angular_pruning = false;
    const RangeOfMotion a = range_of_motion(fixed, mobile, centre, axis, pruned);
    const RangeOfMotion b = range_of_motion(fixed, mobile, centre, axis, reference);
    EXPECT_EQ(a.anticlockwise_deg, b.anticlockwise_deg) << what;
    EXPECT_EQ(a.clockwise_deg, b.clockwise_deg) << what;
    expect_same_contact(a.anticlockwise_limit, b.anticlockwise_limit, what + " anticlockwise");
    expect_same_contact(a.clockwise_limit, b.clockwise_limit, what + " clockwise");
    return (a.anticlockwise_limit.kind == ContactKind::kEdgeOnEdge) + (a.clockwise_limit.kind == ContactKind::kEdgeOnEdge);
  };
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int edge_limited = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const TriMesh fixed = random_shape(rng, 2);
    TriMesh mobile = random_shape(rng, trial % 2 == 0 ? 2 : 1);
    for (Vec3& p : mobile.vertices) p += Vec3(14.0 + 8.0 * u(rng), 0, 0);
    edge_limited += check(fixed, mobile, Vec3(4 * u(rng) - 2, 4 * u(rng) - 2, 4 * u(rng) - 2),
                          test_shapes::random_unit(rng), "trial " + std::to_string(trial));
  }
  EXPECT_GT(edge_limited, 5);  // edge-edge contacts do limit in these scenes
  const std::string folder = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
  check(geometry::read_mesh(folder + "pelvis_no_sacrum.ply"), geometry::read_mesh(folder + "femur_r.ply"),
        Vec3(143.80, 243.46, -432.58), Vec3(0.3, -0.4, 0.866).normalized(), "CT");
}

}  // namespace
}  // namespace hipfai::contact
