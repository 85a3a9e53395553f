// hipfai — optimized spatial hashing of Teschner, Heidelberger, Mueller, Pomeranets & Gross (2003),
// the uniform-grid peer of the thesis' methods, in two variants.
//
// The hash: space is cut into cubic cells of side `cell_size_mm` (default: the mean edge length,
// as Teschner et al. advise); cell (i, j, k) = floor(p / cell_size) goes to bucket
//   h = ((i * 73856093) xor (j * 19349663) xor (k * 83492791)) mod n
// with n a prime table size. Different cells may share a bucket (hash collisions): every
// candidate is confirmed by an exact test, so collisions cost time, never correctness. A primitive
// is entered in every cell its axis-aligned box (padded by 1e-9 of a cell) overlaps.
//
// Tetrahedral variant (as the thesis ran it): the FIXED solid is tetrahedralized (gmsh, from its
// closed surface: the boundary triangles of the tets are the input triangles), the tets are
// hashed once (pre-processing; the fixed object is rigid, so this is the cheaper order of
// Teschner's two passes), and per pose each mobile surface vertex looks up its cell and is tested
// against the candidate tets (barycentric signs, boundary inclusive so that shared inner faces
// leave no crack). It returns the penetrating vertices, without depth (the method has none).
//
// Surface variant: the fixed TRIANGLES are hashed. Two queries on it:
//   - radial_query: for each posed mobile vertex the cells along the segment between v and the
//     next surface crossing are walked (3D DDA, Amanatides & Woo 1987) towards O
//     (kMobileInsideFixed) or away from it (kFixedInsideMobile); candidates are tested with the
//     same watertight ray test and crossing rule as contact/radial_segmenting.h, and the walk stops
//     once the nearest crossing found lies before the current cell's exit. Exact radial depths.
//   - first_collision: any intersection between a posed mobile triangle and a fixed one (each
//     edge of one against the other triangle), stopping at the first (the thesis' Table 7 setup).
#pragma once

#include "contact/penetration_result.h"
#include "contact/radial_segmenting.h"
#include "geometry/tri_mesh.h"

#include <array>
#include <cstdint>
#include <vector>

namespace hipfai::bench {

struct SpatialHashOptions {
  double cell_size_mm = 0.0;   // 0 = mean edge length of the hashed mesh
  std::size_t table_size = 0;  // number of buckets; 0 = the first prime >= 2 x primitives
};

struct TetMesh {
  std::vector<Eigen::Vector3d> nodes;               // mm
  std::vector<std::array<std::int32_t, 4>> tets;    // node indices
};

// Tetrahedralizes the solid bounded by a closed, outward-oriented surface with gmsh (Delaunay),
// keeping the surface triangles as the boundary. Throws hipfai::Error when gmsh fails (e.g. a
// self-intersecting surface). Not thread-safe (gmsh has global state).
TetMesh tetrahedralize(const geometry::TriMesh& closed_surface);

// The hashed grid: buckets of primitive ids in compressed rows.
class SpatialHashGrid {
 public:
  SpatialHashGrid() = default;
  // `boxes` gives each primitive's axis-aligned box (min, max).
  SpatialHashGrid(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& boxes,
                  double cell_size_mm, std::size_t table_size);

  double cell_size_mm() const { return cell_; }
  std::size_t table_size() const { return table_size_; }
  std::array<long long, 3> cell_of(const Eigen::Vector3d& p) const;
  std::size_t bucket(long long i, long long j, long long k) const;
  // Primitive ids in a bucket (may include primitives of other cells with the same hash).
  const std::int32_t* begin(std::size_t bucket) const { return entries_.data() + start_[bucket]; }
  const std::int32_t* end(std::size_t bucket) const { return entries_.data() + start_[bucket + 1]; }
  std::size_t num_entries() const { return entries_.size(); }

 private:
  double cell_ = 1.0;
  std::size_t table_size_ = 1;
  std::vector<std::size_t> start_;
  std::vector<std::int32_t> entries_;
};

class TetSpatialHash {
 public:
  TetSpatialHash(TetMesh tets, const SpatialHashOptions& options = {});
  // Sorted indices of the posed mobile vertices inside a tetrahedron.
  std::vector<std::int32_t> penetrating_vertices(const geometry::TriMesh& posed_mobile,
                                                 int num_threads = 1) const;
  std::size_t num_tets() const { return mesh_.tets.size(); }

 private:
  TetMesh mesh_;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes_;
  SpatialHashGrid grid_;
};

class SurfaceSpatialHash {
 public:
  // Keeps a copy of the fixed mesh (its triangles are tested at query time).
  SurfaceSpatialHash(const geometry::TriMesh& fixed, const SpatialHashOptions& options = {});

  contact::PenetrationResult radial_query(const geometry::TriMesh& posed_mobile,
                                          const Eigen::Vector3d& centre,
                                          contact::RadialConfiguration configuration,
                                          int num_threads = 1) const;

  // True when some posed mobile triangle intersects some fixed triangle (coplanar overlaps are
  // not detected).
  bool first_collision(const geometry::TriMesh& posed_mobile) const;

 private:
  geometry::TriMesh fixed_;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes_;
  SpatialHashGrid grid_;
  Eigen::Vector3d box_min_, box_max_;
};

// Exact-predicate-free segment/triangle and triangle/triangle tests used above (double precision,
// via contact::ray_triangle_crossing), exposed for the tests.
bool segment_crosses_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                              const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                              const Eigen::Vector3d& c);
bool triangles_intersect(const std::array<Eigen::Vector3d, 3>& first,
                         const std::array<Eigen::Vector3d, 3>& second);

}  // namespace hipfai::bench
