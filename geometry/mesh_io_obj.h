// hipfai — Wavefront OBJ (geometry/mesh_io.h dispatches here by extension).
//
// Reading: `v` and `f` lines; `f a/b/c` forms, negative (relative) indices; polygons are
// fan-triangulated. Other statements (vt, vn, g, usemtl, ...) are ignored.
// Writing: `v` lines with full double precision and `f` lines; vertex fields are dropped.
#pragma once

#include "geometry/tri_mesh.h"

#include <string>
#include <string_view>

namespace hipfai::geometry::mesh_io {

// `name` prefixes every error message ("<name>: line 7: bad number 'x'").
TriMesh read_obj(const std::string& name, std::string_view text);
std::string write_obj(const TriMesh& mesh);

}  // namespace hipfai::geometry::mesh_io
