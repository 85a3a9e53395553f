// Writes the seed corpora of the mesh-reader harnesses: a tetrahedron with a vertex field, in
// every variant the project's writers make (STL/PLY ascii and binary, OBJ, VTP ascii and binary,
// MSH), into <out>/<format>/.
#include "geometry/mesh_io_msh.h"
#include "geometry/mesh_io_obj.h"
#include "geometry/mesh_io_ply.h"
#include "geometry/mesh_io_stl.h"
#include "geometry/mesh_io_vtp.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace {

void put(const std::filesystem::path& file, const std::string& bytes) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << bytes;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_fuzz_seeds OUT_DIR\n";
    return 2;
  }
  using namespace hipfai::geometry;
  using namespace hipfai::geometry::mesh_io;
  TriMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), Vec3(0, 0, 10)};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  mesh.vertex_fields["depth_mm"] = {0.0, 0.5, 1.0, 1.5};
  const std::filesystem::path out = argv[1];
  put(out / "stl" / "ascii.stl", write_stl("seed", mesh, true));
  put(out / "stl" / "binary.stl", write_stl("seed", mesh, false));
  put(out / "ply" / "ascii.ply", write_ply("seed", mesh, true));
  put(out / "ply" / "binary.ply", write_ply("seed", mesh, false));
  put(out / "obj" / "mesh.obj", write_obj(mesh));
  put(out / "vtp" / "ascii.vtp", write_vtp(mesh, true));
  put(out / "vtp" / "binary.vtp", write_vtp(mesh, false));
  put(out / "msh" / "mesh.msh", write_msh(mesh));
  return 0;
}
