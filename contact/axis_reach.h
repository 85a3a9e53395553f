// hipfai — what of two bodies can ever meet when one turns about an axis (found once per body
// pair): rotation about the axis keeps every point's (r, z), its distance from the axis
// and its height along it. Two points can meet at some angle only if they share (r, z); so a
// triangle, edge or vertex of one body whose (r, z) extent lies where the other body has nothing
// takes part in no contact at any angle, and every pass of the range finder (tables, pose caches,
// edge-edge pairs) can run on what is left.
//
// The footprint of a body is a bitmap over a grid in (r, z) (cells about a mean edge long): a cell
// is marked when the (r, z) box of one of the body's triangles (exact, App. A:
// triangle_cylindrical_bounds) or one of its vertices overlaps it, every box widened by 1e-9 of the
// bodies' extent (rounding of r is ~1e-16 relative). A triangle of the other body is kept when its
// widened box overlaps a marked cell (2D prefix sums: four reads), a vertex when its widened point
// does or when a kept triangle uses it. Cell indices come from floor(), monotone, so a point inside
// two boxes lies in a cell that both boxes overlap: whatever can meet is kept, on every border.
#pragma once

#include "contact/arc_triangle.h"
#include "geometry/tri_mesh.h"

#include <cstdint>
#include <vector>

namespace hipfai::contact {

struct AxisReach {
  // The kept parts as meshes (vertices renumbered, order kept), and the original index of every
  // kept vertex and triangle.
  geometry::TriMesh fixed, mobile;
  std::vector<std::int32_t> fixed_vertices, fixed_triangles;
  std::vector<std::int32_t> mobile_vertices, mobile_triangles;
};

// Both meshes must be finite with valid indices and `axis` non-zero (the range finder checks
// first); an empty part means nothing of that body can meet the other.
AxisReach reach_about_axis(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile, const Vec3& centre,
                           const Vec3& axis);

}  // namespace hipfai::contact
