// A TriMesh through bytes and back (geometry/mesh_bytes.h): bit for bit, and refused when cut short.
#include "core/error.h"
#include "geometry/mesh_bytes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace hipfai::geometry {
namespace {

TriMesh sample_mesh() {
  TriMesh mesh;
  mesh.vertices = {Vec3(0.1, 0.2, 0.3), Vec3(std::nextafter(1.0, 2.0), -0.0, 1e-300), Vec3(3, 4, 5), Vec3(-7, 8, 9)};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.vertex_fields["depth_mm"] = {1.0 / 3.0, 2, 3, 4};
  mesh.vertex_fields["region"] = {0, 1, 1, 0};
  return mesh;
}

TEST(MeshBytes, RoundTripIsBitForBit) {
  const TriMesh mesh = sample_mesh();
  std::string bytes;
  append_mesh_bytes(bytes, mesh);
  append_mesh_bytes(bytes, TriMesh{});
  std::string_view in = bytes;
  const TriMesh back = read_mesh_bytes(in, "test");
  const TriMesh empty = read_mesh_bytes(in, "test");
  EXPECT_TRUE(in.empty());
  EXPECT_TRUE(empty.vertices.empty() && empty.triangles.empty() && empty.vertex_fields.empty());
  ASSERT_EQ(back.vertices.size(), mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(std::signbit(back.vertices[v][c]), std::signbit(mesh.vertices[v][c]));
      EXPECT_EQ(back.vertices[v][c], mesh.vertices[v][c]);
    }
  }
  EXPECT_EQ(back.triangles, mesh.triangles);
  EXPECT_EQ(back.vertex_fields, mesh.vertex_fields);
}

TEST(MeshBytes, CutShortOrImpossibleBytesAreOneLineErrors) {
  std::string bytes;
  append_mesh_bytes(bytes, sample_mesh());
  for (std::size_t length = 0; length < bytes.size(); ++length) {
    std::string_view in(bytes.data(), length);
    EXPECT_THROW((void)read_mesh_bytes(in, "cut"), Error) << "length " << length;
  }
  TriMesh bad = sample_mesh();
  bad.triangles[1][2] = 4;
  std::string bad_bytes;
  append_mesh_bytes(bad_bytes, bad);
  std::string_view in = bad_bytes;
  try {
    (void)read_mesh_bytes(in, "bad");
    ADD_FAILURE() << "an index past the vertices was read";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "bad: triangle vertex index 4 for 4 vertices");
  }
}

}  // namespace
}  // namespace hipfai::geometry
