// hipfai — quality and topology report of a triangle surface mesh.
//
// The collision and penetration methods assume a closed, outward-oriented, manifold surface
// (inside/outside and penetration depth are undefined otherwise), and segmented CT surfaces often
// break that assumption. check_mesh() says how, before a study runs on the mesh.
//
// Definitions (edges are undirected vertex pairs; a triangle with a repeated index contributes
// only its proper edges):
//   boundary edge       used by exactly one triangle; the mesh is closed iff there are none.
//   non-manifold edge   used by more than two triangles.
//   non-manifold vertex its triangles do not form a single fan (a disk, or a half-disk on the
//                       boundary): two cones touching at a tip, or a vertex on a non-manifold edge.
//   degenerate triangle a repeated vertex index, or zero area up to rounding (|AB x AC| at most
//                       16 machine epsilons of the longest edge squared, the rounding error of
//                       the cross product itself).
//   sliver              not degenerate, but with its smallest angle below 1e-3 rad.
//   duplicate triangle  a triangle with the same three vertices as an earlier one, in any order;
//                       the count is of the extra copies.
//   consistent          every interior edge (exactly two triangles) is traversed in opposite
//                       directions by its two triangles. Non-manifold edges are not judged here:
//                       they are reported on their own.
//   outward             closed, consistent and positive signed volume.
//   components          groups of triangles connected through shared vertices.
#pragma once

#include "geometry/tri_mesh.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace hipfai::geometry {

struct MeshReport {
  std::size_t num_vertices = 0;
  std::size_t num_triangles = 0;
  std::size_t unreferenced_vertices = 0;  // vertices no triangle uses
  BoundingBox bounds;
  double surface_area_mm2 = 0.0;
  double signed_volume_mm3 = 0.0;
  double mean_edge_length_mm = 0.0;
  std::size_t num_edges = 0;  // distinct undirected edges
  std::size_t boundary_edges = 0;
  std::size_t non_manifold_edges = 0;
  std::size_t non_manifold_vertices = 0;
  std::size_t degenerate_triangles = 0;
  std::size_t sliver_triangles = 0;
  std::size_t duplicate_triangles = 0;
  std::size_t inconsistent_edges = 0;  // interior edges traversed twice in the same direction
  std::size_t connected_components = 0;
  bool closed = false;
  bool orientation_consistent = false;
  bool outward = false;
  // Closed, manifold, consistently oriented and free of degenerate or duplicate triangles: the
  // surfaces every hipfai method is specified for.
  bool watertight_manifold = false;
};

// Minimum angle below which a non-degenerate triangle counts as a sliver, radians.
inline constexpr double kSliverAngleRad = 1e-3;

// Report on `mesh`. Indices must be in range (see validate_mesh); an empty mesh gives zeros.
MeshReport check_mesh(const TriMesh& mesh);

// The closed shells of a surface: when every edge is used by exactly two triangles that traverse it
// in opposite directions (and no triangle repeats an index), each group of triangles connected
// through shared edges is a closed, consistently oriented surface and bounds a region of space;
// the result labels every triangle with its group, 0 .. count - 1 in order of first appearance.
// nullopt for any other surface (a boundary edge, a non-manifold or inconsistent edge). Shells may
// touch at a vertex and may intersect each other: each is judged on its own.
std::optional<std::vector<std::int32_t>> closed_shell_labels(std::span<const Triangle> triangles);

}  // namespace hipfai::geometry
