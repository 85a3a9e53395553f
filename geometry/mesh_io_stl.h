// hipfai — STL, ASCII and binary (geometry/mesh_io.h dispatches here by extension).
//
// Reading: binary is recognised by its size (84 + 50 n bytes), so binary files whose header
// starts with "solid" are read correctly; otherwise a file starting with "solid" is ASCII.
// Exactly-equal vertices are welded, so triangles that share a corner share the vertex index.
// Writing: binary stores float32 coordinates; ASCII keeps full double precision. Normals are
// recomputed from the triangles, vertex fields are dropped (STL cannot hold them).
#pragma once

#include "geometry/tri_mesh.h"

#include <string>
#include <string_view>

namespace hipfai::geometry::mesh_io {

// `name` prefixes every error message ("<name>: truncated binary STL: ...").
TriMesh read_stl(const std::string& name, std::string_view bytes);
std::string write_stl(const std::string& name, const TriMesh& mesh, bool ascii);

}  // namespace hipfai::geometry::mesh_io
