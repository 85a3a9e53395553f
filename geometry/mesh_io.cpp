// The dispatcher: the extension picks the format, one file per format does the work
// (geometry/mesh_io_<format>.h), and every read and write is checked the same way here.
#include "geometry/mesh_io.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "geometry/mesh_io_common.h"
#include "geometry/mesh_io_msh.h"
#include "geometry/mesh_io_obj.h"
#include "geometry/mesh_io_ply.h"
#include "geometry/mesh_io_stl.h"
#include "geometry/mesh_io_vtp.h"

#include <cctype>

namespace hipfai::geometry {

MeshFormat mesh_format_from_path(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".stl") return MeshFormat::kStl;
  if (extension == ".obj") return MeshFormat::kObj;
  if (extension == ".ply") return MeshFormat::kPly;
  if (extension == ".vtp") return MeshFormat::kVtp;
  if (extension == ".msh") return MeshFormat::kMsh;
  throw_error(path.string(), ": unknown mesh format '", extension.empty() ? "(no extension)" : extension,
              "' (expected .stl, .obj, .ply, .vtp or .msh)");
}

std::string to_string(MeshFormat format) {
  switch (format) {
    case MeshFormat::kStl: return "STL";
    case MeshFormat::kObj: return "OBJ";
    case MeshFormat::kPly: return "PLY";
    case MeshFormat::kVtp: return "VTP";
    case MeshFormat::kMsh: return "MSH";
  }
  return "?";
}

TriMesh read_mesh(const std::filesystem::path& path) {
  const std::string name = path.string();
  const MeshFormat format = mesh_format_from_path(path);
  const std::string bytes = mesh_io::read_file_bytes(path);
  TriMesh mesh;
  switch (format) {
    case MeshFormat::kStl: mesh = mesh_io::read_stl(name, bytes); break;
    case MeshFormat::kObj: mesh = mesh_io::read_obj(name, bytes); break;
    case MeshFormat::kPly: mesh = mesh_io::read_ply(name, bytes); break;
    case MeshFormat::kVtp: mesh = mesh_io::read_vtp(name, bytes); break;
    case MeshFormat::kMsh: mesh = mesh_io::read_msh(name, bytes); break;
  }
  validate_mesh(mesh, name);
  return mesh;
}

void write_mesh(const TriMesh& mesh, const std::filesystem::path& path, const MeshWriteOptions& options) {
  const std::string name = path.string();
  const MeshFormat format = mesh_format_from_path(path);
  validate_mesh(mesh, name);
  if (mesh.vertices.size() > static_cast<std::size_t>(mesh_io::kMaxIndex)) {
    throw_error(name, ": too many vertices to write");
  }
  std::string bytes;
  switch (format) {
    case MeshFormat::kStl: bytes = mesh_io::write_stl(name, mesh, options.ascii); break;
    case MeshFormat::kObj: bytes = mesh_io::write_obj(mesh); break;
    case MeshFormat::kPly: bytes = mesh_io::write_ply(name, mesh, options.ascii); break;
    case MeshFormat::kVtp: bytes = mesh_io::write_vtp(mesh, options.ascii); break;
    case MeshFormat::kMsh: bytes = mesh_io::write_msh(mesh); break;
  }
  write_file_atomically(path, bytes);
}

}  // namespace hipfai::geometry
