// hipfai — a triangle mesh split into its connected parts.
//
// Two triangles are in one part when they share a vertex (through a chain of such triangles). A
// tissue surface may come in pieces: a synthesised labrum interrupted both at the acetabular notch
// and where the femoral neck passes under the rim is two swept solids in one mesh. Whatever works
// on one solid at a time (the FE volume mesher) takes the parts one by one.
#pragma once

#include "geometry/tri_mesh.h"

#include <vector>

namespace hipfai::geometry {

// The connected parts of `mesh`, ordered by their first triangle in `mesh`. Each keeps its
// vertices in their order in `mesh` (renumbered from 0), its triangles in theirs, and the vertex
// fields of one value per vertex; vertices no triangle uses belong to no part. A mesh of one part whose vertices are all
// used comes back unchanged; an empty mesh gives no parts.
std::vector<TriMesh> connected_parts(const TriMesh& mesh);

}  // namespace hipfai::geometry
