// hipfai — exhaustive oracle for radial penetration (the reference radial segmenting is tested
// against).
//
// Every mobile vertex against every fixed triangle, with the crossing rules documented in
// radial_segmenting.h (kAdjacent: adjacent crossing, normals decide, ties to the lowest triangle
// index, on-surface and v == O do not penetrate; kUnion; kBeyond). Plain loops: it shares only the ray_triangle.h
// primitive with the method under test, no table and no mapping. O(#V x #T).
#pragma once

#include "contact/penetration_result.h"
#include "contact/radial_segmenting.h"
#include "geometry/tri_mesh.h"

namespace hipfai::contact {

PenetrationResult oracle_radial(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                                const Vec3& centre, RadialConfiguration configuration,
                                RadialCrossingRule rule = RadialCrossingRule::kAdjacent);

}  // namespace hipfai::contact
