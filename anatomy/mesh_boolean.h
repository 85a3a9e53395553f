// hipfai — Boolean operations on closed triangle surfaces (union, intersection, difference), and
// the solid checks they need.
//
// Method: CGAL's corefinement (Polygon_mesh_processing::corefine_and_compute_boolean_operations)
// on Surface_mesh copies of the inputs, kernel Exact_predicates_inexact_constructions_kernel.
// Corefinement splits both surfaces along their intersection polyline (the intersection points
// are computed exactly and rounded to double once), then keeps, of each surface, the patches
// inside or outside the other. Every decision is an exact predicate, so the result is closed and
// manifold; only the rounding of the new vertices is inexact (below 1e-12 relative), which can in
// principle make a result self-intersect — the tests check it does not on the shapes we cut.
//
// Each input must bound a solid: closed (no boundary edge), manifold (every edge in exactly two
// triangles, every vertex a single fan), outward-oriented, free of degenerate triangles and of
// self-intersections. Anything else throws hipfai::Error "<name>: <what is wrong>" before CGAL is
// called (CGAL's own preconditions would otherwise abort or give garbage). Vertex fields are
// dropped: a cut surface has no meaningful value for them. All CGAL code lives in
// mesh_boolean.cpp (Debian's CGAL is header-only and slow to compile).
#pragma once

#include "geometry/tri_mesh.h"

#include <string>

namespace hipfai::anatomy {

// Which results a BooleanRequest asks for.
struct BooleanOutputs {
  bool union_of = false;      // a ∪ b
  bool intersection = false;  // a ∩ b
  bool difference = true;     // a − b
};

struct BooleanRequest {
  const geometry::TriMesh* a = nullptr;  // first solid (required)
  const geometry::TriMesh* b = nullptr;  // second solid (required)
  std::string a_name = "a";              // names the first solid in error messages
  std::string b_name = "b";              // names the second solid in error messages
  BooleanOutputs outputs;                // which results to compute (one corefinement for all)
};

struct BooleanResult {
  geometry::TriMesh union_of;      // a ∪ b, when asked for (empty otherwise)
  geometry::TriMesh intersection;  // a ∩ b, when asked for; empty when the solids are disjoint
  geometry::TriMesh difference;    // a − b, when asked for; empty when b contains a
};

// The asked-for Booleans of two solids (see the header comment for what a solid must be).
// Throws hipfai::Error naming the input at fault, or when CGAL reports a failure.
BooleanResult compute_booleans(const BooleanRequest& request);

// Shorthands of compute_booleans for one result.
geometry::TriMesh difference(const geometry::TriMesh& a, const geometry::TriMesh& b,
                             const std::string& a_name = "a", const std::string& b_name = "b");
geometry::TriMesh intersection(const geometry::TriMesh& a, const geometry::TriMesh& b,
                               const std::string& a_name = "a", const std::string& b_name = "b");
geometry::TriMesh union_of(const geometry::TriMesh& a, const geometry::TriMesh& b,
                           const std::string& a_name = "a", const std::string& b_name = "b");

// No boundary edge (every edge in at least two triangles). False for an empty mesh.
bool is_closed(const geometry::TriMesh& mesh);

// Edge-manifold (no edge in more than two triangles) and vertex-manifold (the triangles around
// every vertex form one fan). True for an empty mesh.
bool is_manifold(const geometry::TriMesh& mesh);

// Whether two triangles that are not neighbours intersect, or a triangle is degenerate (CGAL's
// self-intersection test; a non-manifold mesh is split at its non-manifold edges and vertices
// first, so triangles meeting there count as intersecting).
bool does_self_intersect(const geometry::TriMesh& mesh);

// Volume enclosed by a closed mesh, mm^3 (signed: negative when inward-oriented). Throws
// hipfai::Error when the mesh is not closed.
double volume(const geometry::TriMesh& mesh, const std::string& what = "mesh");

// Throws hipfai::Error "<what>: ..." unless the mesh bounds a solid (closed, manifold,
// outward-oriented, no degenerate triangle, no self-intersection).
void require_solid(const geometry::TriMesh& mesh, const std::string& what);

// A segmented bone can carry a few self-intersecting triangles (thin plates, the pubic symphysis)
// that make it no solid for the Booleans. repair_self_intersections removes and refills them
// locally (CGAL Polygon_mesh_processing::experimental::remove_self_intersections), leaving the rest
// of the surface as it was.
struct SelfIntersectionRepair {
  geometry::TriMesh mesh;          // the repaired surface (the input when nothing needed repair)
  std::size_t pairs_before = 0;    // self-intersecting triangle pairs found
  bool repaired = false;           // true when pairs_before > 0 and the result is a solid
  geometry::Vec3 where_mm = geometry::Vec3::Zero();  // mean of the intersecting triangles' centroids
};
// Throws hipfai::Error "<what>: ..." when the surface is not closed and manifold, or when the
// repair leaves self-intersections.
SelfIntersectionRepair repair_self_intersections(const geometry::TriMesh& mesh, const std::string& what);

}  // namespace hipfai::anatomy
