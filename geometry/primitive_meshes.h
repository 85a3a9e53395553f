// hipfai — closed, outward-oriented primitive surfaces for tests, benchmarks and examples.
#pragma once

#include "geometry/tri_mesh.h"

namespace hipfai::geometry {

// Sphere from a regular octahedron whose faces are split into 4 `levels` times, vertices pushed
// to the sphere. Vertex counts 6, 18, 66, 258, 1 026, 4 098, 16 386, 65 538, 262 146 for
// levels 0..8 — the sphere sizes of thesis Table 2 (levels 2..8).
TriMesh make_octasphere(const Vec3& centre, double radius_mm, int levels);

// Axis-aligned box [min, max] whose every face is an n x n grid of quads split in two triangles.
TriMesh make_box(const Vec3& min, const Vec3& max, int divisions);

// Torus about the z axis through `centre`: major radius R, minor radius r, n_major x n_minor quads.
TriMesh make_torus(const Vec3& centre, double major_radius_mm, double minor_radius_mm,
                   int n_major, int n_minor);

}  // namespace hipfai::geometry
