// hipfai — the ring table of cylindrical segmenting (thesis §3.2.2.2, Eq. 2-4, App. A).
//
// Space around the rotation axis is cut into rings: cell (i_z, i_r) holds every point whose
// cylindrical coordinates (axis frame of arc_triangle.h) satisfy
//   i_r = floor((r - r_lo) / res_r),  i_z = floor((z - z_lo) / res_z).
// A rotation about the axis keeps r and z, so a mobile vertex can only meet the fixed triangles
// stored in its own cell. Each fixed triangle is stored in every cell its exact cylindrical
// bounding volume [r_min, r_max] x [z_min, z_max] covers (r_min is the exact axis-to-triangle
// distance of App. A), widened by a relative 1e-9 of the table's extent so that rounding can never
// put a vertex that lies on a cell border, or exactly on the bound, outside the triangle's cells.
// Since the cell index is a monotone function of r (and z), r_min <= r <= r_max implies the
// vertex's cell is among the triangle's cells: no candidate is ever missed.
//
// Search intervals (Eq. 2-3): the table spans the fixed mesh's r and z ranges, intersected with a
// mobile mesh's ranges when one is given (then the table is valid only for vertices of that
// mobile mesh, in any pose about this axis). The rotation-invariant distance |x - c| (L in the
// thesis) gives a second filter: a mobile vertex whose distance to the centre lies outside the
// fixed mesh's [min, max] distance to the centre cannot touch it in any pose.
//
// Resolution defaults to the fixed mesh's mean edge length (both r and z), coarsened if the grid
// would exceed `max_cells`.
//
// Deformation (§3.2.3): update_triangles() re-bins only the triangles that changed; a triangle
// that moved beyond the grid is also kept in an overflow list that vertices outside the grid
// check, so an updated table answers exactly like a fresh one. Alternatively keep the bins and
// refresh only the geometry (TableUpdate::kGeometryOnly), and search +-k neighbour cells: exact
// while every vertex of the fixed mesh moved by at most k * min(res_r, res_z) since its triangles
// were binned (the bounds are 1-Lipschitz in the vertex positions).
//
// A built table is immutable under queries: const member functions are thread-safe.
#pragma once

#include "contact/arc_triangle.h"
#include "contact/penetration_result.h"
#include "contact/vertex_clusters.h"
#include "geometry/tri_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::contact {

namespace detail {
// Binary save/load of the cylindrical artefacts (cylindrical_cache_io.h): reads and restores the
// private state of CylindricalTable and CylindricalPoseCache.
class CylindricalCacheAccess;
}  // namespace detail

struct CylindricalTableOptions {
  double resolution_r_mm = 0.0;     // ring width; 0 = mean edge length of the fixed mesh
  double resolution_z_mm = 0.0;     // ring height; 0 = mean edge length of the fixed mesh
  int neighbour_cells = 0;          // queries also search +-k cells in r and z
  std::size_t max_cells = 1u << 22; // the resolution is coarsened to stay below this
  // Build the angular index of nearest_crossing() (the one-pass query's walk). The pose cache and
  // the range finder read every crossing and never walk, so they leave it out (nearest_crossing
  // then offers every candidate: the same answer). A loaded table always has it.
  bool angular_index = true;
};

enum class TableUpdate {
  kRebin,         // refresh geometry and re-bin the changed triangles (exact for any motion)
  kGeometryOnly,  // refresh geometry, keep the bins: use with neighbour_cells (see above)
};

class CylindricalTable {
 public:
  CylindricalTable() = default;

  // Builds the table of `fixed` for rotations about `axis` through `centre`. With
  // `restrict_to_mobile`, the grid covers only the ranges that mobile mesh can reach, and (with
  // the angular index) the table keeps that mesh's vertex clusters (mobile_clusters()).
  // Invalid input (zero axis, non-finite data, empty mesh) gives status() == kInvalidInput;
  // disjoint ranges give kNoOverlap (an empty table that finds no candidates).
  static CylindricalTable build(const geometry::TriMesh& fixed, const Vec3& centre,
                                const Vec3& axis, const CylindricalTableOptions& options = {},
                                const geometry::TriMesh* restrict_to_mobile = nullptr);

  QueryStatus status() const { return status_; }
  const std::string& message() const { return message_; }
  const AxisFrame& frame() const { return frame_; }

  // False when a point at this distance from the centre can meet no fixed triangle in any pose.
  bool distance_may_touch(double distance_to_centre_mm) const {
    return distance_to_centre_mm >= l_min_ && distance_to_centre_mm <= l_max_;
  }

  // Calls fn(triangle) for every candidate triangle of the circle (r, z). A triangle may be
  // offered more than once when neighbour_cells > 0.
  template <typename Fn>
  void for_each_candidate(double r, double z, Fn&& fn) const {
    const long long cell_r = cell_index(r, r_lo_, res_r_);
    const long long cell_z = cell_index(z, z_lo_, res_z_);
    const bool outside = cell_r < 0 || cell_r >= num_r_ || cell_z < 0 || cell_z >= num_z_;
    if (outside) {
      for (std::int32_t t : overflow_) fn(t);
    }
    if (num_r_ == 0 || num_z_ == 0) return;
    const long long k = neighbour_cells_;
    const long long r0 = std::max<long long>(cell_r - k, 0);
    const long long r1 = std::min<long long>(cell_r + k, num_r_ - 1);
    const long long z0 = std::max<long long>(cell_z - k, 0);
    const long long z1 = std::min<long long>(cell_z + k, num_z_ - 1);
    for (long long iz = z0; iz <= z1; ++iz) {
      for (long long ir = r0; ir <= r1; ++ir) {
        for (std::int32_t t : cells_[static_cast<std::size_t>(iz * num_r_ + ir)]) fn(t);
      }
    }
  }

  // False only when for_each_candidate(r, z) offers nothing (an empty cell inside the grid, or a
  // circle outside the grid with no overflow triangles): such a circle crosses nothing.
  bool has_candidates(double r, double z) const;
  // False only when no point of the ball (centre in the axis frame, radius in mm) can pass both
  // distance_may_touch and has_candidates: the ball's distance range misses [L_min, L_max], or the
  // cells its (r, z) ranges cover are all empty (counted with a prefix sum of the occupied cells)
  // and, where they leave the grid, there are no overflow triangles. The caller widens the radius
  // by the rounding of the positions it compares. Always true without the angular index or with
  // neighbour cells.
  bool ball_may_touch(const Vec3& local_centre, double radius_mm) const;

  // The nearest crossing of the circle (r, z) from the angle theta, by NearestCrossing's rule over
  // every crossing of every triangle for_each_candidate offers: the same triangle and angle as
  // offering them all. With neighbour_cells == 0 and the circle inside the grid, the cell's
  // triangles are visited in order of their angular extents (triangle_angular_extent), outwards
  // from theta both ways, and the walk stops where no further extent can hold a crossing as near
  // as the nearest found (ties included): usually a few of the cell's triangles are evaluated.
  NearestCrossing nearest_crossing(double r, double z, double theta) const;
  // The same by offering every candidate of for_each_candidate (the walk's reference and fallback).
  NearestCrossing nearest_crossing_of_every_candidate(double r, double z, double theta) const;

  // True when the point (r, z, theta) lies in an outside region of its ring cell: a range of
  // angles between the cell's angular extents (so no fixed surface passes through the cell there)
  // that was found, at build, to lie outside every closed shell of the fixed mesh (each shell on
  // its own: geometry::closed_shell_labels). From such a point the first surface its circle meets,
  // either way, is one it enters, so its nearest crossing can only say "outside" (for a crossing
  // that is transversal; see cylindrical_segmenting.h): the one-pass query skips its walk.
  // How a region is classified: the surface-free region (the cell's (r, z) box times the angles)
  // is connected, so it is on one side of each shell; a sample circle of the cell through it
  // settles the side when its nearest crossings of that shell, ahead and behind, are an entry
  // and an exit with transversal tangents (a missed or grazing crossing breaks that pattern and
  // leaves the region unclassified). Regions inside a shell, unsettled ones, cells with an
  // all-angle triangle and meshes that are not closed shells have none: then this is false.
  bool outside_every_shell(double r, double z, double theta) const;
  // An outside region: the open interval of angles (lo, hi), within [-pi - 1, pi + 1] (a region
  // across +-pi is stored as two whose outer ends lie beyond +-pi).
  struct OutsideRegion {
    double lo = 0.0, hi = 0.0;
  };
  // The vertex clusters of the mobile mesh the table was restricted to (empty otherwise, and for
  // a loaded table). The one-pass query on a mesh with as many vertices tests them cluster by
  // cluster: the ball about each cluster's bounding box, as posed, first (ball_may_touch). Only the
  // grouping of vertex indices is used, never the rest positions, so any mesh is answered exactly;
  // one that moved rigidly from the rest mesh keeps the clusters compact.
  const VertexClusters& mobile_clusters() const { return mobile_clusters_; }

  // Outside regions of the index, and those of cell (i_z, i_r) sorted by lo (reports and tests).
  std::size_t num_outside_regions() const { return outside_regions_.size(); }
  std::span<const OutsideRegion> outside_regions(long long i_z, long long i_r) const;

  // circle_triangle_crossings of the circle (r, z) with triangle t, with the triangle's plane
  // computed once at build (the same crossings, bit for bit).
  int crossings(std::int32_t t, double r, double z, std::array<double, 2>& angles_rad) const {
    const auto& tri = triangles_[static_cast<std::size_t>(t)];
    return circle_triangle_crossings(r, z, local_vertex(tri[0]), local_vertex(tri[1]), local_vertex(tri[2]),
                                     planes_[static_cast<std::size_t>(t)], angles_rad);
  }

  const Vec3& local_vertex(std::int32_t v) const { return local_vertices_[static_cast<std::size_t>(v)]; }
  const geometry::Triangle& triangle(std::int32_t t) const { return triangles_[static_cast<std::size_t>(t)]; }
  const Vec3& local_normal(std::int32_t t) const { return local_normals_[static_cast<std::size_t>(t)]; }
  std::size_t num_triangles() const { return triangles_.size(); }
  std::size_t num_vertices() const { return local_vertices_.size(); }

  // Grid description (for reports and tests).
  long long num_r_cells() const { return num_r_; }
  long long num_z_cells() const { return num_z_; }
  double resolution_r_mm() const { return res_r_; }
  double resolution_z_mm() const { return res_z_; }
  double r_lo_mm() const { return r_lo_; }
  double z_lo_mm() const { return z_lo_; }
  int neighbour_cells() const { return neighbour_cells_; }
  void set_neighbour_cells(int k) { neighbour_cells_ = k < 0 ? 0 : k; }
  std::size_t num_overflow_triangles() const { return overflow_.size(); }
  // Triangle ids stored in cell (i_z, i_r), for tests.
  const std::vector<std::int32_t>& cell(long long i_z, long long i_r) const {
    return cells_[static_cast<std::size_t>(i_z * num_r_ + i_r)];
  }

  friend void update_triangles(CylindricalTable& table, const geometry::TriMesh& fixed_now,
                               std::span<const std::int32_t> changed_triangles,
                               TableUpdate mode);
  friend class detail::CylindricalCacheAccess;

 private:
  struct CellRange {
    long long r0 = 0, r1 = -1, z0 = 0, z1 = -1;  // empty when r1 < r0
    bool overflow = false;
  };

  static long long cell_index(double value, double lo, double resolution) {
    const double cell = std::floor((value - lo) / resolution);
    if (!(cell > -1e15)) return -1;  // also NaN
    if (cell > 1e15) return static_cast<long long>(1e15);
    return static_cast<long long>(cell);
  }
  // The (r, z) ranges a table covers, in its axis frame (mm).
  struct RingExtent {
    double r_lo, r_hi, z_lo, z_hi;
  };
  // build()'s steps: the fixed triangles' normals, exact cylindrical bounds (App. A) and distances
  // to the centre (sets pad_, l_min_, l_max_); the intersection with a mobile mesh's ranges
  // (Eq. 2-3; false: they do not overlap); the cells over the extent, padded.
  RingExtent measure_fixed();
  bool restrict_to(const geometry::TriMesh& mobile, RingExtent& extent) const;
  void make_cells(const RingExtent& extent, const geometry::TriMesh& fixed, const CylindricalTableOptions& options);
  void refresh_geometry(const geometry::TriMesh& fixed);
  void refresh_triangle_normal(std::int32_t t);  // also its plane
  void refresh_triangle_plane(std::int32_t t);
  void bin_triangle(std::int32_t t, bool allow_overflow);
  void unbin_triangle(std::int32_t t);
  // Rebuilds the angular index from the cells and the current geometry (derived data: after
  // build(), update_triangles() and loading a saved table), and its outside regions.
  void build_angular_index();
  // The outside regions of every cell (outside_every_shell), from the sorted angular entries and
  // each triangle's extent width.
  void build_outside_regions(const std::vector<double>& extent_widths);

  QueryStatus status_ = QueryStatus::kInvalidInput;
  std::string message_ = "table not built";
  AxisFrame frame_;
  std::vector<Vec3> local_vertices_;
  std::vector<geometry::Triangle> triangles_;
  std::vector<Vec3> local_normals_;  // unit outward normals in the axis frame (zero if degenerate)
  std::vector<CrossingPlane> planes_;  // per triangle, for crossings() (derived from the vertices)
  std::vector<CellRange> ranges_;
  std::vector<std::vector<std::int32_t>> cells_;  // num_z_ x num_r_, row-major in z
  std::vector<std::int32_t> overflow_;
  // The angular index of nearest_crossing(): cell c's triangles with a bounded angular extent,
  // sorted by the extent's start (in [-pi, pi)), are entries [angular_begin_[c],
  // angular_begin_[c + 1]) of angular_entries_, the widest of their extents is angular_width_[c];
  // its all-angle triangles are [all_begin_[c], all_begin_[c + 1]) of all_entries_.
  // Each entry also carries the triangle's padded (r, z) bounds (those it was binned with),
  // rounded outwards to float: a circle outside them crosses the triangle nowhere, so the walk
  // skips it without the crossing test.
  struct AngularEntry {
    double lo = 0.0;
    float r_min = 0.0f, r_max = 0.0f, z_min = 0.0f, z_max = 0.0f;
    std::int32_t triangle = -1;
    bool holds(double r, double z) const { return r >= r_min && r <= r_max && z >= z_min && z <= z_max; }
  };
  std::vector<std::uint32_t> angular_begin_;
  std::vector<AngularEntry> angular_entries_;
  std::vector<double> angular_width_;
  std::vector<std::uint32_t> all_begin_;
  std::vector<AngularEntry> all_entries_;
  // Outside regions: cell c's are [region_begin_[c], region_begin_[c + 1]) of outside_regions_,
  // sorted by lo. shell_ labels each triangle with its closed shell (empty when the fixed mesh is
  // not made of closed shells); shells_known_ once computed (the topology never changes after
  // build).
  // occupied_prefix_[(i_z) * (num_r_ + 1) + i_r]: occupied cells with z index < i_z and r index
  // < i_r (built with the angular index, for ball_may_touch).
  std::vector<std::uint32_t> occupied_prefix_;
  std::vector<std::uint32_t> region_begin_;
  std::vector<OutsideRegion> outside_regions_;
  std::vector<std::int32_t> shell_;
  bool shells_known_ = false;
  VertexClusters mobile_clusters_;
  double r_lo_ = 0.0, r_hi_ = 0.0, z_lo_ = 0.0, z_hi_ = 0.0;
  double res_r_ = 1.0, res_z_ = 1.0;
  double pad_ = 0.0;
  double l_min_ = 0.0, l_max_ = -1.0;
  long long num_r_ = 0, num_z_ = 0;
  int neighbour_cells_ = 0;
};

// Refreshes the table after the fixed mesh deformed (same vertex and triangle counts; throws
// hipfai::Error otherwise). `changed_triangles` must list every triangle with a moved vertex.
void update_triangles(CylindricalTable& table, const geometry::TriMesh& fixed_now,
                      std::span<const std::int32_t> changed_triangles,
                      TableUpdate mode = TableUpdate::kRebin);

// The crossings (triangle, angle) of the circle (r, z) with the table's candidate triangles for
// which keep(triangle) holds, into `found` (cleared first), sorted and each once
// (neighbour_cells > 0 offers a triangle several times).
template <typename Keep>
void circle_crossings(const CylindricalTable& table, double r, double z, Keep&& keep,
                      std::vector<std::pair<std::int32_t, double>>& found) {
  found.clear();
  std::array<double, 2> angles{};
  table.for_each_candidate(r, z, [&](std::int32_t t) {
    if (!keep(t)) return;
    const int n = table.crossings(t, r, z, angles);
    for (int i = 0; i < n; ++i) found.emplace_back(t, angles[static_cast<std::size_t>(i)]);
  });
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
}

}  // namespace hipfai::contact
