// hipfai — a surface split along a sphere: every edge that crosses the sphere gets a vertex on it.
//
// The split mesh is the same surface (each new vertex lies on its edge, each triangle is cut into
// three that tile it, winding kept), sampled also where it crosses |x - c| = radius. A per-vertex
// quantity whose largest values lie on that crossing curve (the curvilinear depth of a femur's
// striking region, which begins at the articular sphere plus the contact tolerance) is then
// sampled on the curve itself instead of at whichever vertices happen to lie near it.
#pragma once

#include "geometry/tri_mesh.h"

namespace hipfai::geometry {

struct SphereSplit {
  TriMesh mesh;                  // the input's vertices first (same indices), then the new ones
  std::size_t num_original = 0;  // vertices [0, num_original) are the input's
};

// A vertex is inside when |v - centre| <= radius. An edge with one vertex inside and one outside
// gets the point where the segment meets the sphere (computed from the segment's quadratic; one
// root lies on the segment), shared by both triangles of the edge. Vertex fields are not carried.
SphereSplit split_at_sphere(const TriMesh& mesh, const Vec3& centre, double radius);

}  // namespace hipfai::geometry
