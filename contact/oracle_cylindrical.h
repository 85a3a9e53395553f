// hipfai — exhaustive reference for cylindrical segmenting and the range finder.
//
// Every mobile vertex against EVERY fixed triangle: no table, no filters, no pre-processing,
// plain loops sharing only the primitives of arc_triangle.h (crossings, nearest crossing, App. D
// verdict). Same semantics as cylindrical_segmenting.h and range_finder.h, so their outputs must
// be equal; O(#V x #T), for tests and small meshes only.
#pragma once

#include "contact/arc_triangle.h"
#include "contact/penetration_result.h"
#include "contact/range_finder.h"
#include "geometry/tri_mesh.h"

namespace hipfai::contact {

// Penetrating vertices of the posed mobile mesh, depth along the arc about the axis.
PenetrationResult oracle_cylindrical(const geometry::TriMesh& fixed,
                                     const geometry::TriMesh& posed_mobile, const Vec3& centre,
                                     const Vec3& axis, double touching_mm = kDefaultTouchingMm);

// Range of motion by testing every vertex/triangle pair (both contact types when
// include_fixed_vertices).
RangeOfMotion oracle_range_of_motion(const geometry::TriMesh& fixed,
                                     const geometry::TriMesh& mobile, const Vec3& centre,
                                     const Vec3& axis, bool include_fixed_vertices = true,
                                     double touching_mm = kDefaultTouchingMm);

}  // namespace hipfai::contact
