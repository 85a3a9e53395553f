// hipfai — VTK XML PolyData (.vtp) (geometry/mesh_io.h dispatches here by extension).
//
// Reading, through expat (geometry/xml_tree.h): one Piece; Points, Polys (connectivity/offsets)
// and Strips; scalar PointData arrays become vertex fields. DataArrays ascii or inline base64
// binary with a UInt32 or UInt64 header, either byte order. Compressed files and appended data
// are rejected with a message saying so; malformed XML with expat's line, column and reason.
// Writing: Float64 points and fields, Int64 connectivity, ascii or inline base64 binary.
#pragma once

#include "geometry/tri_mesh.h"

#include <string>
#include <string_view>

namespace hipfai::geometry::mesh_io {

// `name` prefixes every error message ("<name>: malformed XML at line 3, column 7: ...").
TriMesh read_vtp(const std::string& name, std::string_view xml);
std::string write_vtp(const TriMesh& mesh, bool ascii);

}  // namespace hipfai::geometry::mesh_io
