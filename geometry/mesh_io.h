// hipfai — reading and writing triangle surface meshes (STL, OBJ, PLY, VTK XML PolyData, gmsh MSH).
//
// Users bring their own bones segmented from CT/MR in whatever format their tool exports, so the
// readers accept the common variants and reject everything else with a one-line hipfai::Error
// "<path>: <problem>" — never a crash, never a silently wrong mesh. One file per format says
// which variants it takes (geometry/mesh_io_<format>.h); this header is the dispatcher:
//   .stl  ASCII and binary (mesh_io_stl.h)          .obj  Wavefront OBJ (mesh_io_obj.h)
//   .ply  ascii and binary PLY (mesh_io_ply.h)       .vtp  VTK XML PolyData, via expat (mesh_io_vtp.h)
//   .msh  gmsh MSH 2.2 ASCII triangles (mesh_io_msh.h)
// The format is chosen by the file extension, case-insensitively. Every read ends with
// validate_mesh(), so a returned mesh is non-empty, finite and has in-range indices.
//
// Writers store vertex fields where the format can hold them (PLY, VTP) and drop them otherwise
// (STL, OBJ, MSH). They write through core/atomic_file.h (a temporary file renamed into place),
// so a failed write never leaves a half-written mesh under the target name.
#pragma once

#include "geometry/tri_mesh.h"

#include <filesystem>
#include <string>

namespace hipfai::geometry {

// kCamel like the project's other enumerators. The lower-case names are the old spelling, kept
// as aliases because tests/geometry/mesh_io_test.cpp (the readers' contract) still uses them.
enum class MeshFormat {
  kStl,
  kObj,
  kPly,
  kVtp,
  kMsh,
  stl = kStl,
  obj = kObj,
  ply = kPly,
  vtp = kVtp,
};

// The format named by the extension of `path` (case-insensitive); throws hipfai::Error
// "<path>: unknown mesh format '.ext' (expected .stl, .obj, .ply, .vtp or .msh)" otherwise.
MeshFormat mesh_format_from_path(const std::filesystem::path& path);

std::string to_string(MeshFormat format);

// Reads a surface mesh. Throws hipfai::Error "<path>: <problem>" on a missing, unreadable,
// truncated or malformed file, a non-finite coordinate, an out-of-range index or an empty mesh.
TriMesh read_mesh(const std::filesystem::path& path);

struct MeshWriteOptions {
  // Text output where the format has both (STL, PLY, VTP); OBJ and MSH are always text.
  bool ascii = false;
};

// Writes `mesh` in the format named by the extension of `path`, atomically (temporary file +
// rename). Coordinates keep full double precision (shortest exact decimal in text formats)
// except in binary STL, which stores float32.
// Throws hipfai::Error "<path>: <problem>" when the mesh is invalid (see validate_mesh), a field
// name cannot be stored in the format, or the file cannot be written.
void write_mesh(const TriMesh& mesh, const std::filesystem::path& path,
                const MeshWriteOptions& options = {});

}  // namespace hipfai::geometry
