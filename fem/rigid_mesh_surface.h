// hipfai — a rigid contact surface given as a closed triangle mesh (the femoral bone with its cam).
//
// The hip FE model (fem/hip_fe_model.h) lets the labrum and the acetabular cartilage touch the
// rigid femoral head-neck, whose shape is only known as a triangulated surface. The contact gap
// is measured along the normal at the closest point (closest-point projection, not
// radial rays), so this surface answers exact closest-point queries on the triangle mesh:
//   - a bounding-volume hierarchy over the triangles (median splits along the longest axis of
//     the centroid box) prunes the search; the answer is the exact nearest point of the mesh,
//     the same as a brute-force scan, not an approximation;
//   - the normal at the closest point points out of the body: on a face interior the face normal;
//     on an edge or a vertex the direction from the closest point to the query (signed with the
//     angle-weighted pseudo-normal of Baerentzen & Aanaes 2005 so that it points outward also for
//     a query inside the body), or the pseudo-normal itself when the query lies on the surface.
// The mesh must be closed and oriented outward (CCW seen from outside), like every TriMesh.
#pragma once

#include "fem/rigid_surface.h"
#include "geometry/tri_mesh.h"

#include <array>
#include <cstdint>
#include <vector>

namespace hipfai::fem {

// Which feature of a triangle a closest point lies on.
enum class TriangleFeature : std::uint8_t {
  kFace,     // interior of the triangle
  kEdge,     // on edge `index` (vertices index, index + 1 mod 3)
  kVertex,   // at vertex `index`
};

struct MeshClosestPoint {
  int triangle = -1;
  TriangleFeature feature = TriangleFeature::kFace;
  int index = 0;                          // edge or vertex of the triangle (0..2)
  geometry::Vec3 point_mm = geometry::Vec3::Zero();
  double distance_mm = 0.0;               // unsigned
  geometry::Vec3 normal = geometry::Vec3::UnitZ();  // unit, out of the body
  bool inside = false;                    // the query is inside the closed surface
};

// Closest point of triangle (a, b, c) to p, with the feature it lies on (exact regions of the
// Voronoi diagram of the triangle's features). Degenerate triangles resolve to an edge or vertex.
MeshClosestPoint closest_point_on_triangle(const geometry::Vec3& p, const geometry::Vec3& a,
                                           const geometry::Vec3& b, const geometry::Vec3& c);

class RigidMeshSurface final : public RigidSurface {
 public:
  // Copies what it needs from `mesh`. Throws hipfai::Error "<what>: ..." for an empty mesh, a
  // degenerate (zero-area) triangle, or an invalid mesh (geometry::validate_mesh).
  explicit RigidMeshSurface(const geometry::TriMesh& mesh, const std::string& what = "rigid mesh");

  SurfacePoint closest_point(const dealii::Point<3>& query_mm) const override;

  // The full answer (triangle, feature, inside/outside); closest_point() is built on it.
  MeshClosestPoint closest(const geometry::Vec3& query_mm) const;

  // Brute-force reference over all triangles (tests; O(triangles) per query).
  MeshClosestPoint closest_brute_force(const geometry::Vec3& query_mm) const;

  std::size_t n_triangles() const { return triangles_.size(); }

 private:
  struct Node {
    geometry::Vec3 box_min, box_max;
    int first = 0;   // leaf: range [first, first + count) of order_; inner: left child index
    int count = 0;   // 0 for an inner node (right child = left + 1 is not assumed: see right)
    int right = -1;  // inner: right child index
  };
  int build(int first, int count);
  // Fills in normal and inside for the closest point found on `hit.triangle`.
  void finish(const geometry::Vec3& query_mm, MeshClosestPoint& hit) const;

  std::vector<geometry::Vec3> vertices_;
  std::vector<geometry::Triangle> triangles_;
  std::vector<geometry::Vec3> face_normals_;
  std::vector<geometry::Vec3> vertex_normals_;                 // angle-weighted, unit
  std::vector<std::array<geometry::Vec3, 3>> edge_normals_;    // per triangle edge, unit
  std::vector<int> order_;                                     // triangle indices, leaf order
  std::vector<Node> nodes_;
  double on_surface_mm_ = 0.0;  // distances below this count as on the surface
};

}  // namespace hipfai::fem
