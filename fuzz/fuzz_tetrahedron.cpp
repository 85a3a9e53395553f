#include "fuzz_tetrahedron.h"

namespace hipfai::fuzz {

geometry::TriMesh tetrahedron() {
  using geometry::Vec3;
  geometry::TriMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), Vec3(0, 0, 10)};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  mesh.vertex_fields["depth_mm"] = {0.0, 0.5, 1.0, 1.5};
  return mesh;
}

}  // namespace hipfai::fuzz
