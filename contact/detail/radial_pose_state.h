// hipfai — the private state of contact::RadialPoseQuery (radial_segmenting.h): the mobile
// vertices in buckets of rest direction and distance, and the distance map that drops whole
// buckets at a pose. Internal: included by radial_segmenting.cpp only; the class comment of
// RadialPoseQuery states what the buckets and the map guarantee.
#pragma once

#include "contact/radial_segmenting.h"
#include "contact/radial_spans.h"
#include "contact/radial_table.h"

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace hipfai::contact::detail {

struct FiledTriangles;  // the fixed triangles sorted for the distance map (radial_segmenting.cpp)

class RadialPoseState {
 public:
  RadialPoseState(const RadialTable& table, const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                  const RadialQueryOptions& options);
  QueryStatus status() const { return status_; }
  const std::string& message() const { return message_; }
  std::size_t num_kept_vertices() const { return num_kept_; }
  PenetrationResult query(const Eigen::Isometry3d& pose) const;
  PenetrationResult query_rotation(const Eigen::Matrix3d& rotation) const;
  std::size_t num_tested_vertices(const Eigen::Isometry3d& pose) const;

 private:
  // A run of stored vertices sharing a coarse rest direction and a shell of rest distance.
  struct Bucket {
    std::uint32_t begin = 0, end = 0;  // [begin, end) of sorted_position_ / sorted_index_
    double r_lo = std::numeric_limits<double>::infinity(), r_hi = 0.0;  // rest distances from O
    Vec3 axis = Vec3::UnitZ();  // unit mean rest direction
    double half_angle_rad = 8.0;  // every member's direction within this of axis (8: no cone)
    double cos_half_angle = -1.0, sin_half_angle = 0.0;  // of half_angle_rad
  };
  // The buckets a pose keeps, in blocks of about kBlockVertices vertices (block b: buckets
  // [block_start[b], block_start[b + 1]) of `buckets`).
  struct KeptBuckets {
    std::vector<std::uint32_t> buckets;
    std::vector<std::size_t> block_start;
    std::size_t num_vertices = 0;
  };
  KeptBuckets kept_buckets(const Eigen::Isometry3d& pose) const;
  // The query at `pose` (for the culls), each kept vertex posed by posing(v).
  template <typename Posing>
  PenetrationResult run(const Eigen::Isometry3d& pose, const Posing& posing) const;
  // Is every vertex of the bucket culled by the spans' distance test, its distance moved by <= shift_mm?
  bool distance_culled(const Bucket& bucket, double shift_mm, double scale_mm) const;
  // The spans' cap half-angle + 1e-4 rad, with its cosine and sine.
  struct CapAngle {
    double angle_rad = 0.0, cos = 1.0, sin = 0.0;
  };
  // Is every vertex of the bucket culled by the spans of the triangles its posed directions can
  // meet (the bucket's coarse cell of the distance map, see map_lo_)? `axis` is the bucket's
  // posed axis R axis, shift_mm and scale_mm as for distance_culled.
  bool map_culled(const Bucket& bucket, const Vec3& axis, double shift_mm, double scale_mm) const;
  void build_distance_map();
  // Cell g of the distance map from the filed triangles near it (its flat wedge, or their spans).
  void fill_map_cell(int g, const FiledTriangles& filed);
  // Is every vertex of the bucket outside the spans' cap (radial_spans.h) at a pose whose rotation
  // takes rest_cap_axis to the cap's axis and whose centre moves by shift_mm?
  bool cap_culled(const Bucket& bucket, const Vec3& rest_cap_axis, const CapAngle& cap, double shift_mm) const;

  const RadialTable* table_ = nullptr;
  const geometry::TriMesh* fixed_ = nullptr;
  RadialQueryOptions options_;
  QueryStatus status_ = QueryStatus::kInvalidInput;
  std::string message_;
  bool use_spans_ = false;
  static constexpr double kShellMm = 0.5;
  static constexpr std::size_t kBucketVertices = 32;  // mean vertices per coarse direction cell
  static constexpr std::size_t kBlockVertices = 2048;  // vertices per unit of parallel work
  std::vector<Bucket> buckets_;
  std::vector<Vec3> sorted_position_;
  std::vector<std::int32_t> sorted_index_;
  // THE DISTANCE MAP (radial spans for whole buckets, so a culled bucket is never posed): on the
  // buckets' coarse cube grid, map_lo_[g] (map_hi_[g]) is the least lo (largest hi) of every fixed
  // triangle whose cone reaches within map_dilation_rad_ of coarse cell g, and of the
  // always-checked ones. A bucket whose posed directions all lie within map_dilation_rad_ of its
  // posed axis (its half-angle plus asin(shift / r_lo)) meets only such triangles, so when its
  // distances are beyond that span on the rule's side every one of its vertices is decided as the
  // per-vertex test decides it (no qualifying crossing). The dilation is a speed trade only: a
  // wider one covers larger translations with looser spans; the answers never change.
  // Triangles without a span (planes through O up to rounding, the socket's rim faces) would make
  // those spans [0, inf] near the rim; where the ones within the dilation of cell g fit in a thin
  // flat wedge (radial_spans.h, FLAT WEDGES), map_wedge_[g] holds it and they are left out of
  // map_lo_ / map_hi_: a bucket whose posed cone stays clear of the wedge cannot meet them.
  struct MapWedge {
    Vec3 normal = Vec3::Zero();
    double angle_rad = -1.0;  // asin of the wedge's sin_bound; < 0: no wedge at this cell
  };
  RadialGrid coarse_grid_;
  RadialSpans::CubeLocator coarse_locator_;  // the coarse grid's cells without atan
  double map_dilation_rad_ = 0.0;
  std::vector<double> map_lo_, map_hi_;  // per coarse cell; empty: no map
  std::vector<MapWedge> map_wedge_;       // per coarse cell
  std::size_t num_kept_ = 0;  // vertices kept at a pose about O (for num_kept_vertices)
  double largest_distance_ = 0.0;  // largest rest distance from O
};

}  // namespace hipfai::contact::detail
