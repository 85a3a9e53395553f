// hipfai — cylindrical segmenting: exact collision detection for a mobile mesh rotating about a
// fixed axis (thesis §3.2, App. B-D). Striking motions; the depth is the curvilinear depth along
// the vertex's circle about the axis.
//
// Semantics. Fixed mesh F, mobile mesh M, rotation centre c, unit axis a (axis frame of
// arc_triangle.h). For each mobile vertex v (r, theta_v, z): the candidate fixed triangles are
// those of its ring cell (cylindrical_table.h); for each, the exact crossings of v's circle with
// the triangle (App. C, both roots, kept when inside the triangle: App. B exact variant). The
// crossing at the smallest angular distance |delta| (either direction) selects the triangle; the
// App. D test decides whether v is inside F. Each penetrating vertex gives
//   PenetrationPair{mobile_vertex, fixed_triangle, depth_mm = r * |delta|, angle_deg = |delta|},
// i.e. the rotation (either way) that brings v back onto F's surface.
//
// Why the nearest crossing decides. Follow v's circle from v to its nearest crossing V'. No other
// point of F's surface lies on that arc, so v and the points of the arc just before V' are on the
// same side of F. If F is closed and outward-oriented and the circle crosses the surface
// transversally at V', the side just before V' is "inside" exactly when the arc runs against the
// outward normal there (T.A < 0 in App. D). Assumptions, stated once:
//   - F is closed (watertight) and consistently outward-oriented;
//   - the nearest crossing is transversal (a circle that only grazes a ridge or a silhouette edge
//     at its nearest crossing may be misclassified; generic positions never do this).
// Open meshes (holes): nothing crashes and nothing is NaN; the verdict is the same local
// half-space test at the nearest crossing, so a circle that passes through a hole is judged by
// the next triangle it meets (possibly a far one). Results stay deterministic and equal to the
// oracle's, but "inside" has no global meaning for an open surface.
// Touching (arc distance <= touching_mm) is not penetration. Vertices on the axis (r = 0) do not
// move under the rotation, have no crossings, and are never reported. Zero-area triangles and
// triangles perpendicular to the axis are never crossed (arc_triangle.h).
//
// Two ways to query:
//   - cylindrical_segmenting(table, posed_mobile): one pass over the posed mobile vertices;
//   - CylindricalPoseCache (§3.2.3.2): pre-process the mobile mesh once per axis (all crossing
//     angles of every vertex's circle do not depend on the rotation angle), then query(angle_deg)
//     visits only the vertices that can penetrate at that angle. Between two consecutive
//     crossings of its circle a vertex can penetrate only if one of the two crossings faces that
//     way (penetrating_sides, arc_triangle.h), so each vertex has a few candidate arcs of pose
//     angle, widened by 1e-12 rad, known once per body pair; an AngularIntervalIndex finds the
//     arcs holding the query angle and only their vertices get the exact test (nearest crossing
//     + App. D), so the result is the same, pair for pair, as the pass over every tracked vertex
//     (query_every_vertex), in time that grows with the answer instead of with the mesh.
// The one-pass query finds each circle's nearest crossing through the table's angular index
// (CylindricalTable::nearest_crossing): the same answer as offering every candidate of the cell.
// Before that, a vertex in an outside region of its cell (CylindricalTable::outside_every_shell:
// between the cell's angular extents, outside every closed shell of F) is passed over: its
// nearest crossing, either way, is one it would enter through, so it cannot penetrate. That
// needs F to be made of closed, consistently oriented shells (otherwise there are no regions);
// it reaches the same verdict as the nearest crossing wherever that crossing is transversal, and
// the right one where it is not. And when the table keeps the clusters of the mobile mesh it was
// restricted to (CylindricalTable::mobile_clusters), the vertices go cluster by cluster: a
// cluster whose posed bounding ball cannot reach the fixed body (CylindricalTable::
// ball_may_touch) is passed over whole; VertexClusters and the pose do the same from the rest
// positions, without posing the vertices of a cluster passed over.
// Output pairs are sorted by mobile vertex. Work is split over `num_threads` threads.
#pragma once

#include "contact/angular_interval_index.h"
#include "contact/arc_triangle.h"
#include "contact/cylindrical_table.h"
#include "contact/penetration_result.h"
#include "contact/vertex_clusters.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <vector>

namespace hipfai::contact {

struct CylindricalQueryOptions {
  int num_threads = 0;                       // 0 = all hardware threads
  double touching_mm = kDefaultTouchingMm;   // arc distance under which a vertex only touches
  // CylindricalPoseCache only: build the arc index that makes query() output-sensitive. The range
  // finder reads the crossings and never queries a pose, so it turns this off; without the index
  // query() is query_every_vertex(). Not stored in cache files (a loaded cache has its index).
  bool pose_index = true;
  // (The speed-ups of the one-pass query are always on here; the benchmark and the tests switch
  // them off through contact/detail/ablation.h.)
};

// Posed mobile mesh (already rotated by the caller) against a table built for the same axis.
PenetrationResult cylindrical_segmenting(const CylindricalTable& table,
                                         const geometry::TriMesh& posed_mobile,
                                         const CylindricalQueryOptions& options = {});

// The same query with the mobile mesh at rest and its pose in the fixed frame: each vertex is
// posed (pose * v) as it is visited, so no posed copy of the mesh is made. Equal, pair for pair,
// to the query on the posed copy (the same arithmetic per vertex).
PenetrationResult cylindrical_segmenting(const CylindricalTable& table, const geometry::TriMesh& mobile,
                                         const Eigen::Isometry3d& pose,
                                         const CylindricalQueryOptions& options = {});

// The same query over the mobile mesh's vertex clusters (built once per body at rest) and its
// pose: a cluster whose posed bounding sphere cannot reach a non-empty ring cell within the fixed
// mesh's distance range (CylindricalTable::ball_may_touch) is passed over whole; the others'
// vertices are tested as above. Equal, pair for pair, to the query on the mesh the clusters were
// built from.
PenetrationResult cylindrical_segmenting(const CylindricalTable& table, const VertexClusters& mobile,
                                         const Eigen::Isometry3d& pose,
                                         const CylindricalQueryOptions& options = {});

// One-shot convenience: builds a table restricted to `posed_mobile`, then queries it.
PenetrationResult cylindrical_segmenting(const geometry::TriMesh& fixed,
                                         const geometry::TriMesh& posed_mobile,
                                         const Vec3& centre, const Vec3& axis,
                                         const CylindricalQueryOptions& options = {},
                                         const CylindricalTableOptions& table_options = {});

// Pre-processed mobile mesh for rotations about the table's axis. Self-contained: it copies what
// it needs from the table, so the table may be destroyed afterwards.
class CylindricalPoseCache {
 public:
  struct TrackedVertex {
    std::int32_t vertex = -1;   // index into the mobile mesh
    double r = 0.0;             // mm
    double z = 0.0;             // mm
    double theta0_rad = 0.0;    // angular position at pose 0
    std::size_t first = 0;      // its crossings are [first, last) in crossing_theta/triangle
    std::size_t last = 0;
  };

  CylindricalPoseCache() = default;
  // `mobile` at pose 0 (angle 0). The table must be built for the same axis.
  CylindricalPoseCache(const CylindricalTable& table, const geometry::TriMesh& mobile,
                       const CylindricalQueryOptions& options = {});

  QueryStatus status() const { return status_; }

  // Penetrating vertices when the mobile mesh is rotated by angle_deg about the axis
  // (right-hand rule). Same output as cylindrical_segmenting() on the posed mesh. Visits the
  // candidates of the arc index (|angle| up to 1e3 rad; beyond, where the rounding of the pose
  // angle outgrows the arcs' margin, it is query_every_vertex).
  PenetrationResult query(double angle_deg) const;
  // The same answer by the exact test of every tracked vertex: the reference the index is tested
  // against, and the ablation of the benchmark.
  PenetrationResult query_every_vertex(double angle_deg) const;
  // Candidate arcs in the index (for reports).
  std::size_t num_candidate_arcs() const { return index_.num_arcs(); }

  // The pre-processed data (used by the range finder): vertices whose circle crosses F.
  const std::vector<TrackedVertex>& tracked() const { return tracked_; }
  double crossing_theta_rad(std::size_t i) const { return crossing_theta_[i]; }
  std::int32_t crossing_triangle(std::size_t i) const { return crossing_triangle_[i]; }
  const Vec3& local_normal(std::int32_t t) const { return normals_[static_cast<std::size_t>(t)]; }
  std::size_t num_crossings() const { return crossing_theta_.size(); }
  double touching_mm() const { return options_.touching_mm; }

  friend class detail::CylindricalCacheAccess;

 private:
  // Fills index_ from tracked_ and the crossings (constructor, and after a cache is loaded).
  void build_index();
  // The exact test of one tracked vertex at a pose angle: true and `pair` filled if it penetrates.
  bool penetration_of(const TrackedVertex& vertex, double angle_rad, PenetrationPair& pair) const;
  // The exact test of tracked_[tracked_index(k)] for k in [0, count) on `threads` threads; the
  // pairs in the order of k.
  template <typename TrackedIndex>
  PenetrationResult penetrations(std::size_t count, int threads, double angle_rad, TrackedIndex tracked_index) const;
  // The answer without a pass (invalid cache, non-finite angle, no overlap), or nothing.
  std::optional<PenetrationResult> trivial_answer(double angle_deg) const;

  QueryStatus status_ = QueryStatus::kInvalidInput;
  std::string message_ = "pose cache not built";
  CylindricalQueryOptions options_;
  std::vector<TrackedVertex> tracked_;
  std::vector<double> crossing_theta_;
  std::vector<std::int32_t> crossing_triangle_;
  std::vector<Vec3> normals_;
  AngularIntervalIndex index_;  // arcs of pose angle where each tracked vertex may penetrate
};

}  // namespace hipfai::contact
