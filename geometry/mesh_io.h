// hipfai — reading and writing triangle surface meshes (STL, OBJ, PLY, VTK XML PolyData).
//
// Users bring their own bones segmented from CT/MR in whatever format their tool exports, so the
// readers accept the common variants and reject everything else with a one-line hipfai::Error
// "<path>: <problem>" — never a crash, never a silently wrong mesh:
//   .stl  ASCII and binary. Binary is recognised by its size (84 + 50 n bytes), so binary files
//         whose header starts with "solid" are read correctly. Exactly-equal vertices are welded,
//         so triangles that share a corner share the vertex index.
//   .obj  `v` and `f` lines; `f a/b/c` forms, negative (relative) indices; polygons are
//         fan-triangulated. Other statements (vt, vn, g, usemtl, ...) are ignored.
//   .ply  ascii, binary_little_endian, binary_big_endian; any numeric vertex property type;
//         x, y, z are the position and every other scalar vertex property becomes a vertex field;
//         faces as a list property `vertex_indices` (or `vertex_index`) with any integer count
//         type; polygons fan-triangulated; other elements are skipped.
//   .vtp  VTK XML PolyData, one Piece: Points, Polys (connectivity/offsets), Strips; scalar
//         PointData arrays become vertex fields. DataArrays ascii or inline base64 binary with a
//         UInt32 or UInt64 header, either byte order. Compressed and appended data are rejected.
// The format is chosen by the file extension, case-insensitively. Every read ends with
// validate_mesh(), so a returned mesh is non-empty, finite and has in-range indices.
//
// Writers store vertex fields where the format can hold them (PLY, VTP) and drop them otherwise
// (STL, OBJ). They write to a temporary file beside the target and rename it into place, so a
// failed write never leaves a half-written mesh under the target name.
#pragma once

#include "geometry/tri_mesh.h"

#include <filesystem>
#include <string>

namespace hipfai::geometry {

enum class MeshFormat { stl, obj, ply, vtp };

// The format named by the extension of `path` (case-insensitive); throws hipfai::Error
// "<path>: unknown mesh format '.ext' (expected .stl, .obj, .ply or .vtp)" otherwise.
MeshFormat mesh_format_from_path(const std::filesystem::path& path);

std::string to_string(MeshFormat format);

// Reads a surface mesh. Throws hipfai::Error "<path>: <problem>" on a missing, unreadable,
// truncated or malformed file, a non-finite coordinate, an out-of-range index or an empty mesh.
TriMesh read_mesh(const std::filesystem::path& path);

struct MeshWriteOptions {
  // Text output where the format has both (STL, PLY, VTP); OBJ is always text.
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
