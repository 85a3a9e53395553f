// hipfai — Stanford PLY (geometry/mesh_io.h dispatches here by extension).
//
// Reading: ascii, binary_little_endian, binary_big_endian; any numeric vertex property type;
// x, y, z are the position and every other scalar vertex property becomes a vertex field; faces
// as a list property `vertex_indices` (or `vertex_index`) with any integer count type; polygons
// fan-triangulated; other elements are skipped. Element counts are checked against the body's
// size before anything is allocated.
// Writing: ascii or binary_little_endian, double coordinates and one double property per
// vertex field (a field name must be one PLY word, not x, y or z).
#pragma once

#include "geometry/tri_mesh.h"

#include <string>
#include <string_view>

namespace hipfai::geometry::mesh_io {

// `name` prefixes every error message ("<name>: PLY header line 3: unknown format 'x'").
TriMesh read_ply(const std::string& name, std::string_view bytes);
std::string write_ply(const std::string& name, const TriMesh& mesh, bool ascii);

}  // namespace hipfai::geometry::mesh_io
