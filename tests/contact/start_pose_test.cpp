// The start-pose check against boxes whose overlaps are known by hand, an edge-only overlap, and
// the real CT bones at their scanned pose and pushed 5 mm together.
#include "contact/start_pose.h"
#include "geometry/mesh_io.h"
#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

namespace hipfai::contact {
namespace {

using geometry::make_box;
using geometry::TriMesh;

// The fixed box of most cases: [0, 10]^3, one quad (two triangles) per face.
TriMesh fixed_box() { return make_box(Vec3(0, 0, 0), Vec3(10, 10, 10), 1); }

TEST(StartPose, SeparateBoxesDoNotOverlap) {
  const StartPoseOverlap o = check_start_pose(fixed_box(), make_box(Vec3(11, 3, 4), Vec3(14, 5, 6), 1));
  ASSERT_EQ(o.status, QueryStatus::kOk) << o.message;
  EXPECT_FALSE(o.overlaps());
  EXPECT_EQ(o.mobile_vertices_inside + o.fixed_vertices_inside + o.mobile_edges_through + o.fixed_edges_through, 0u);
  EXPECT_EQ(o.deepest_mm(), 0.0);
  EXPECT_EQ(o.summary(),
            "no mobile vertex inside the fixed mesh, no fixed vertex inside the mobile mesh, no edge through the "
            "other surface");
}

// The mobile box [9, 12] x [3, 5] x [4, 6] pokes 1 mm through the face x = 10: its four corners at
// x = 9 are inside, each 1 mm from that face (3 and 4 mm from the faces y = 0, z = 0). Its edges
// along x are inside from x = 9 to 10, midpoint 0.5 mm deep; the fixed face's diagonal crosses
// the mobile box with its inside stretch's midpoint 0.5 mm from two of the mobile faces.
TEST(StartPose, OverlappingBoxesCountVerticesAndDepth) {
  const StartPoseOverlap o = check_start_pose(fixed_box(), make_box(Vec3(9, 3, 4), Vec3(12, 5, 6), 1));
  ASSERT_EQ(o.status, QueryStatus::kOk) << o.message;
  EXPECT_TRUE(o.overlaps());
  EXPECT_EQ(o.mobile_vertices_inside, 4u);
  EXPECT_NEAR(o.mobile_deepest_mm, 1.0, 1e-12);
  EXPECT_GE(o.mobile_deepest_vertex, 0);
  EXPECT_EQ(o.fixed_vertices_inside, 0u);
  EXPECT_EQ(o.fixed_deepest_vertex, -1);
  EXPECT_GT(o.mobile_edges_through, 0u);
  EXPECT_NEAR(o.edge_deepest_mm, 0.5, 1e-12);
  EXPECT_NEAR(o.deepest_mm(), 1.0, 1e-12);
  EXPECT_EQ(o.summary().substr(0, 60), "4 mobile vertices inside the fixed mesh (deepest 1 mm), no f");
}

// A corner of each box inside the other: the mobile cube [-1, 1]^3 holds the fixed corner at the
// origin (1 mm from three mobile faces) and its own corner (1, 1, 1) lies 1 mm inside the fixed box.
TEST(StartPose, CornersInsideEachOtherCountInBothRoles) {
  const StartPoseOverlap o = check_start_pose(fixed_box(), make_box(Vec3(-1, -1, -1), Vec3(1, 1, 1), 1));
  ASSERT_EQ(o.status, QueryStatus::kOk) << o.message;
  EXPECT_EQ(o.mobile_vertices_inside, 1u);
  EXPECT_NEAR(o.mobile_deepest_mm, 1.0, 1e-12);
  EXPECT_EQ(o.fixed_vertices_inside, 1u);
  EXPECT_NEAR(o.fixed_deepest_mm, 1.0, 1e-12);
  EXPECT_EQ(o.fixed_deepest_vertex, 0);  // make_box's first vertex is its min corner
}

// Faces lying on each other touch; so does a shift inside the tolerance (default 1 um). A shift
// of 10 um into the fixed box is an overlap of 10 um.
TEST(StartPose, TouchingFacesWithinTheToleranceDoNotOverlap) {
  for (const int divisions : {1, 3}) {
    const StartPoseOverlap on_face =
        check_start_pose(fixed_box(), make_box(Vec3(10, 3, 4), Vec3(12, 5, 6), divisions));
    ASSERT_EQ(on_face.status, QueryStatus::kOk) << on_face.message;
    EXPECT_FALSE(on_face.overlaps()) << on_face.summary();
    const StartPoseOverlap within =
        check_start_pose(fixed_box(), make_box(Vec3(10 - 5e-4, 3, 4), Vec3(12, 5, 6), divisions));
    EXPECT_FALSE(within.overlaps()) << within.summary();
    const StartPoseOverlap beyond =
        check_start_pose(fixed_box(), make_box(Vec3(10 - 0.01, 3, 4), Vec3(12, 5, 6), divisions));
    EXPECT_TRUE(beyond.overlaps());
    EXPECT_EQ(beyond.mobile_vertices_inside, static_cast<std::size_t>((divisions + 1) * (divisions + 1)));
    EXPECT_NEAR(beyond.mobile_deepest_mm, 0.01, 1e-9);
  }
  // A tolerance above the overlap makes it touching again.
  StartPoseOptions loose;
  loose.touching_mm = 0.02;
  EXPECT_FALSE(check_start_pose(fixed_box(), make_box(Vec3(10 - 0.01, 3, 4), Vec3(12, 5, 6), 1), loose).overlaps());
}

// Two bars crossing like a plus sign: the fixed bar [-10, 10] x [-1, 1]^2 and the mobile bar
// [-1, 1] x [-10, 10] x [0.5, 3] overlap in [-1, 1]^2 x [0.5, 1], 0.5 mm thick, yet every vertex
// of each bar is outside the other. Only edges cross: the fixed top edges through the mobile bar
// and the mobile bottom edges through the fixed one, each inside stretch 0.5 mm deep at its
// midpoint (to the mobile bottom face, resp. the fixed top face).
TEST(StartPose, EdgeOnlyOverlapIsFoundByTheEdges) {
  const TriMesh fixed = make_box(Vec3(-10, -1, -1), Vec3(10, 1, 1), 1);
  const TriMesh mobile = make_box(Vec3(-1, -10, 0.5), Vec3(1, 10, 3), 1);
  const StartPoseOverlap o = check_start_pose(fixed, mobile);
  ASSERT_EQ(o.status, QueryStatus::kOk) << o.message;
  EXPECT_EQ(o.mobile_vertices_inside, 0u);
  EXPECT_EQ(o.fixed_vertices_inside, 0u);
  EXPECT_GE(o.fixed_edges_through, 2u);   // the two long top edges (and the top face's diagonal)
  EXPECT_GE(o.mobile_edges_through, 2u);  // the two long bottom edges (and the bottom diagonal)
  EXPECT_NEAR(o.edge_deepest_mm, 0.5, 1e-12);
  EXPECT_TRUE(o.overlaps());
  // Vertices alone miss it (the documented reason for the edge pass).
  StartPoseOptions vertices_only;
  vertices_only.check_edges = false;
  EXPECT_FALSE(check_start_pose(fixed, mobile, vertices_only).overlaps());
  // A 0.5 mm overlap is touching for a 0.6 mm tolerance.
  StartPoseOptions loose;
  loose.touching_mm = 0.6;
  EXPECT_FALSE(check_start_pose(fixed, mobile, loose).overlaps());
}

TEST(StartPose, InvalidInputIsAStatus) {
  EXPECT_EQ(check_start_pose(TriMesh{}, fixed_box()).status, QueryStatus::kInvalidInput);
  StartPoseOptions negative;
  negative.touching_mm = -1.0;
  const StartPoseOverlap o = check_start_pose(fixed_box(), fixed_box(), negative);
  EXPECT_EQ(o.status, QueryStatus::kInvalidInput);
  EXPECT_NE(o.message.find("touching_mm"), std::string::npos);
}

std::filesystem::path lhdl_folder() {
  return std::filesystem::path(HIPFAI_SOURCE_DIR) / "meshes/real-hips/LHDL_CT";
}

// The LHDL CT femur and pelvis (35k + 48k vertices) in their scanned pose, about the hip joint
// centre of hip.json. The scan leaves a joint space between the bones: nothing overlaps. Pushed
// 5 mm together along the line from the femoral head centre to the nearest pelvis vertex (the
// acetabular surface), the head sinks into the acetabulum by 5 mm less that joint space.
TEST(StartPose, RealCtBonesApartAtTheScannedPoseAndOverlappingWhenPushedTogether) {
  const std::filesystem::path folder = lhdl_folder();
  const TriMesh pelvis = geometry::read_mesh(folder / "pelvis_no_sacrum.ply");
  TriMesh femur = geometry::read_mesh(folder / "femur_r.ply");
  StartPoseOptions options;
  options.centre = Vec3(143.80, 243.46, -432.58);  // hip.json hjc_mm
  const auto start = std::chrono::steady_clock::now();
  const StartPoseOverlap scanned = check_start_pose(pelvis, femur, options);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(scanned.status, QueryStatus::kOk) << scanned.message;
  std::printf("LHDL CT scanned pose: %s (%.0f ms)\n", scanned.summary().c_str(), ms);
  EXPECT_FALSE(scanned.overlaps());

  // Joint space: distance from the head's surface (sphere fit, hip.json) to the nearest pelvis vertex.
  const Vec3 head_centre(143.33, 243.35, -432.43);
  Vec3 nearest = pelvis.vertices.front();
  for (const Vec3& p : pelvis.vertices) {
    if ((p - head_centre).norm() < (nearest - head_centre).norm()) nearest = p;
  }
  const double joint_space_mm = (nearest - head_centre).norm() - 23.08;
  const Vec3 push = 5.0 * (nearest - head_centre).normalized();
  for (Vec3& p : femur.vertices) p += push;
  const StartPoseOverlap pushed = check_start_pose(pelvis, femur, options);
  ASSERT_EQ(pushed.status, QueryStatus::kOk) << pushed.message;
  std::printf("LHDL CT femur pushed 5 mm towards the acetabulum (joint space %.2f mm): %s\n", joint_space_mm,
              pushed.summary().c_str());
  EXPECT_TRUE(pushed.overlaps());
  EXPECT_GT(pushed.mobile_vertices_inside, 0u);
  EXPECT_GT(pushed.fixed_vertices_inside, 0u);
  EXPECT_GT(pushed.deepest_mm(), 0.5 * (5.0 - joint_space_mm));
  EXPECT_LT(pushed.deepest_mm(), 5.0);
}

}  // namespace
}  // namespace hipfai::contact
