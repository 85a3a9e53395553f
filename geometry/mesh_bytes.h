// hipfai — a TriMesh as bytes in memory, exactly (doubles and indices as they are), to hand meshes
// from a child process to its parent (geometry/hip_generator.cpp meshes in a child, core/child_process.h).
// Not a file format: the bytes are native-endian and meant for the same build on the same machine.
#pragma once

#include "geometry/tri_mesh.h"

#include <string>
#include <string_view>

namespace hipfai::geometry {

// Appends `mesh` (vertices, triangles, vertex fields) to `out`.
void append_mesh_bytes(std::string& out, const TriMesh& mesh);

// Reads one mesh written by append_mesh_bytes from the front of `in` and advances `in` past it.
// Throws hipfai::Error "<what>: truncated mesh bytes" when `in` ends early, and "<what>: ..."
// when a count or an index is impossible.
TriMesh read_mesh_bytes(std::string_view& in, const std::string& what);

}  // namespace hipfai::geometry
