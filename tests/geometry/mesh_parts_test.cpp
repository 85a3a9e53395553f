// Tests for geometry/mesh_parts.h: a mesh split into its connected parts.
#include "geometry/mesh_parts.h"

#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

namespace hipfai::geometry {
namespace {

TEST(ConnectedParts, OnePartComesBackUnchanged) {
  TriMesh box = make_box(Vec3(0, 0, 0), Vec3(1, 2, 3), 2);
  box.vertex_fields["x"] = std::vector<double>(box.num_vertices(), 1.5);
  const std::vector<TriMesh> parts = connected_parts(box);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].vertices, box.vertices);
  EXPECT_EQ(parts[0].triangles, box.triangles);
  EXPECT_EQ(parts[0].vertex_fields, box.vertex_fields);
  EXPECT_TRUE(connected_parts(TriMesh{}).empty());
}

TEST(ConnectedParts, TwoSolidsAndAnUnusedVertexGiveTwoPartsInTheirOrder) {
  // A sphere, an unused vertex, then a box: the parts are the sphere then the box, each with its
  // own vertices in their order, its triangles, its field values and its volume; the unused
  // vertex is in neither.
  TriMesh sphere = make_octasphere(Vec3(10, 0, 0), 2.0, 2);
  TriMesh box = make_box(Vec3(-3, -1, -1), Vec3(-1, 1, 1), 3);
  TriMesh lone;
  lone.vertices = {Vec3(100, 100, 100)};
  sphere.vertex_fields["id"].resize(sphere.num_vertices());
  box.vertex_fields["id"].resize(box.num_vertices());
  lone.vertex_fields["id"] = {-1.0};
  for (std::size_t i = 0; i < sphere.num_vertices(); ++i) sphere.vertex_fields["id"][i] = static_cast<double>(i);
  for (std::size_t i = 0; i < box.num_vertices(); ++i) box.vertex_fields["id"][i] = 1000.0 + static_cast<double>(i);
  const TriMesh both = merge_meshes({&sphere, &lone, &box});
  ASSERT_EQ(both.num_vertices(), sphere.num_vertices() + 1 + box.num_vertices());
  const std::vector<TriMesh> parts = connected_parts(both);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].vertices, sphere.vertices);
  EXPECT_EQ(parts[0].triangles, sphere.triangles);
  EXPECT_EQ(parts[0].vertex_fields.at("id"), sphere.vertex_fields.at("id"));
  EXPECT_EQ(parts[1].vertices, box.vertices);
  EXPECT_EQ(parts[1].triangles, box.triangles);
  EXPECT_EQ(parts[1].vertex_fields.at("id"), box.vertex_fields.at("id"));
  EXPECT_NEAR(signed_volume(parts[0]) + signed_volume(parts[1]), signed_volume(both), 1e-12 * signed_volume(both));
  EXPECT_NEAR(signed_volume(parts[1]), 8.0, 1e-12);
}

TEST(ConnectedParts, TrianglesSharingOnlyAVertexAreOnePart) {
  // Two triangles meeting at one vertex (a bow tie) are connected through it.
  TriMesh bow;
  bow.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)};
  bow.triangles = {{0, 1, 2}, {0, 3, 4}};
  EXPECT_EQ(connected_parts(bow).size(), 1u);
  bow.triangles = {{1, 2, 0}, {3, 4, 3}};  // the second no longer uses vertex 0
  const std::vector<TriMesh> parts = connected_parts(bow);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[1].num_vertices(), 2u);
}

}  // namespace
}  // namespace hipfai::geometry
