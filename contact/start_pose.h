// hipfai — start-pose check: do the two bodies already intersect before any motion?
//
// Every motion query of hipfai (range finder, collide, the studies) starts from the meshes as
// given, and the range finder assumes that pose is collision-free: on bodies that already
// overlap it reports the rotation to the first surface crossing of any vertex, a small positive
// "range" that means nothing. check_start_pose() says whether, and how much, the two closed
// solids overlap at that pose, so callers can refuse or warn.
//
// What is counted (both meshes closed and outward-oriented, like every TriMesh query):
//   - vertices of each mesh INSIDE the other solid. Inside-ness is the winding number of the other
//     mesh along a ray, with radial segmenting's kUnion crossing rule (radial_segmenting.h; the
//     watertight ray-triangle test of ray_triangle.h, shared edges and vertices counted once):
//     the rays start at `centre` and run through each vertex, so a mesh that is a union of
//     touching closed parts is also read right. A vertex counts only if its exact Euclidean
//     distance to the other surface (nearest triangle, point_triangle_distance) exceeds
//     touching_mm: touching is not intersecting, and a vertex ON the other surface never counts.
//     Its depth is that distance. (A vertex exactly at `centre` has no ray and is not tested.)
//   - EDGES THROUGH THE OTHER SURFACE (check_edges): vertex containment misses overlaps where only
//     edges cross (two sharp rims interlocking, no vertex of either inside the other). Every
//     transversal intersection of two triangles ends where an edge of one crosses a triangle of
//     the other, so testing every edge of each mesh against the other's triangles finds every
//     such overlap; this is the triangle-triangle test (Möller 1997) by its edge-triangle half,
//     with the exact, watertight segment-triangle predicate of ray_triangle.h (edges through a
//     shared edge or vertex of the other mesh counted once, as in radial segmenting's kUnion
//     rule). Along each edge the crossings (entering / exiting by the outward normals) split it
//     into stretches inside and outside the other solid, starting from its first vertex's
//     inside-ness; an edge counts if the midpoint of one of its inside stretches lies deeper than
//     touching_mm (exact distance to the other surface), and that distance is its depth. An edge
//     lying in the other surface's plane never crosses it (touching). Candidates come from a
//     uniform grid of the other mesh's triangle bounding boxes (cell about two mean edges), so
//     the cost follows the edges actually near the other surface. The midpoint depth is a lower
//     bound of the stretch's deepest point (exact for a stretch through a slab, as in the tests).
//
// Cost: two radial tables (one per mesh, about one cell per triangle) and one pass over each
// mesh's vertices, plus the grid pass over the edges near the other surface; on the LHDL CT femur and pelvis
// (35k + 48k vertices) about 0.2 s on one core of a loaded machine (start_pose_test prints it).
//
// The check answers "do these solids overlap beyond touching_mm", not "are the meshes valid":
// an open or inward-oriented mesh gives counts without meaning (geometry/mesh_check.h first).
#pragma once

#include "contact/penetration_result.h"
#include "contact/ray_triangle.h"
#include "geometry/tri_mesh.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace hipfai::contact {

// Default touching tolerance of the command-line start-pose checks, mm: 1 um, above the rounding
// of single-precision coordinates of a CT frame (about 3e-5 mm at 500 mm) and far below any
// segmentation's resolution.
inline constexpr double kStartPoseTouchingMm = 1e-3;

struct StartPoseOptions {
  // A vertex, or an edge's inside stretch, within this distance of the other surface touches and
  // is not counted (mm, >= 0).
  double touching_mm = kStartPoseTouchingMm;
  // Origin of the inside-test rays (mm). Any point works; one inside the region where the bodies
  // meet (the hip joint centre) keeps the radial tables fine where it matters. Default: the centre
  // of the fixed mesh's bounding box.
  std::optional<Vec3> centre;
  // Also test the edges against the other surface (edge-only overlaps); off: vertices only.
  bool check_edges = true;
  // Threads of the vertex passes (radial segmenting runs on 1 or 2).
  int num_threads = 1;
};

struct StartPoseOverlap {
  QueryStatus status = QueryStatus::kOk;  // kInvalidInput: see message; the counts are then 0
  std::string message;                    // empty unless status == kInvalidInput

  std::size_t mobile_vertices_inside = 0;  // mobile vertices inside the fixed solid, deeper than touching_mm
  double mobile_deepest_mm = 0.0;          // largest distance of such a vertex to the fixed surface
  std::int32_t mobile_deepest_vertex = -1;  // its index in the mobile mesh, -1 if none
  std::size_t fixed_vertices_inside = 0;   // fixed vertices inside the mobile solid, deeper than touching_mm
  double fixed_deepest_mm = 0.0;           // largest distance of such a vertex to the mobile surface
  std::int32_t fixed_deepest_vertex = -1;  // its index in the fixed mesh, -1 if none
  // Edges of either mesh with a stretch inside the other solid deeper than touching_mm (an edge
  // from an inside vertex out through the surface included); 0 when check_edges is off.
  std::size_t mobile_edges_through = 0;  // mobile edges through the fixed surface
  std::size_t fixed_edges_through = 0;   // fixed edges through the mobile surface
  double edge_deepest_mm = 0.0;          // deepest inside-stretch midpoint of those edges
  double touching_mm = 0.0;                 // the tolerance applied

  // The bodies intersect: a vertex or an edge of one inside the other solid, beyond touching_mm.
  bool overlaps() const {
    return mobile_vertices_inside > 0 || fixed_vertices_inside > 0 || mobile_edges_through > 0 ||
           fixed_edges_through > 0;
  }
  // Deepest point found of either surface inside the other (vertices and edge midpoints), mm.
  double deepest_mm() const;
  // One clause for messages, e.g. "1234 mobile vertices inside the fixed mesh (deepest 2.31 mm),
  // 567 fixed vertices inside the mobile mesh (deepest 1.2 mm), 2345 edges through the other
  // surface (deepest 2.1 mm)".
  std::string summary() const;
};

// Overlap of `fixed` and `mobile` as given (the start pose). Returns kInvalidInput for an empty
// or invalid mesh, non-finite coordinates or a negative touching_mm; never throws for
// data-dependent reasons.
StartPoseOverlap check_start_pose(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                                  const StartPoseOptions& options = {});

}  // namespace hipfai::contact
