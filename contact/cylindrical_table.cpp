#include "contact/cylindrical_table.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <thread>

namespace hipfai::contact {
namespace {

// Relative widening of every bound: rounding in r_min / r / cell arithmetic is ~1e-16 relative,
// so 1e-9 of the table's extent is far above it and far below any mesh feature.
constexpr double kTablePad = 1e-9;

bool all_finite(const geometry::TriMesh& mesh) {
  for (const Vec3& p : mesh.vertices) {
    if (!p.allFinite()) return false;
  }
  const auto n = static_cast<std::int32_t>(mesh.vertices.size());
  for (const auto& tri : mesh.triangles) {
    for (std::int32_t v : tri) {
      if (v < 0 || v >= n) return false;
    }
  }
  return true;
}

}  // namespace

void CylindricalTable::refresh_geometry(const geometry::TriMesh& fixed) {
  local_vertices_.resize(fixed.vertices.size());
  for (std::size_t v = 0; v < fixed.vertices.size(); ++v) {
    local_vertices_[v] = frame_.to_local(fixed.vertices[v]);
  }
  triangles_ = fixed.triangles;
}

void CylindricalTable::refresh_triangle_normal(std::int32_t t) {
  const auto& tri = triangles_[static_cast<std::size_t>(t)];
  const Vec3 n = (local_vertex(tri[1]) - local_vertex(tri[0]))
                     .cross(local_vertex(tri[2]) - local_vertex(tri[0]));
  const double length = n.norm();
  local_normals_[static_cast<std::size_t>(t)] = length > 0.0 ? Vec3(n / length) : Vec3::Zero();
  refresh_triangle_plane(t);
}

void CylindricalTable::refresh_triangle_plane(std::int32_t t) {
  const auto& tri = triangles_[static_cast<std::size_t>(t)];
  planes_[static_cast<std::size_t>(t)] = crossing_plane(local_vertex(tri[0]), local_vertex(tri[1]), local_vertex(tri[2]));
}

void CylindricalTable::bin_triangle(std::int32_t t, bool allow_overflow) {
  const auto& tri = triangles_[static_cast<std::size_t>(t)];
  const Vec3& a = local_vertex(tri[0]);
  const Vec3& b = local_vertex(tri[1]);
  const Vec3& c = local_vertex(tri[2]);
  const CylindricalBounds bounds = triangle_cylindrical_bounds(a, b, c);
  CellRange& range = ranges_[static_cast<std::size_t>(t)];
  range = CellRange{};
  const double r_min = bounds.r_min - pad_, r_max = bounds.r_max + pad_;
  const double z_min = bounds.z_min - pad_, z_max = bounds.z_max + pad_;
  if (allow_overflow && (r_min < r_lo_ || r_max > r_hi_ || z_min < z_lo_ || z_max > z_hi_)) {
    range.overflow = true;
    overflow_.push_back(t);
  }
  if (num_r_ == 0 || num_z_ == 0) return;
  const long long r0 = std::max<long long>(cell_index(r_min, r_lo_, res_r_), 0);
  const long long r1 = std::min<long long>(cell_index(r_max, r_lo_, res_r_), num_r_ - 1);
  const long long z0 = std::max<long long>(cell_index(z_min, z_lo_, res_z_), 0);
  const long long z1 = std::min<long long>(cell_index(z_max, z_lo_, res_z_), num_z_ - 1);
  if (r1 < r0 || z1 < z0) return;  // entirely outside the grid (restricted table)
  range.r0 = r0;
  range.r1 = r1;
  range.z0 = z0;
  range.z1 = z1;
  for (long long iz = z0; iz <= z1; ++iz) {
    for (long long ir = r0; ir <= r1; ++ir) {
      cells_[static_cast<std::size_t>(iz * num_r_ + ir)].push_back(t);
    }
  }
}

void CylindricalTable::unbin_triangle(std::int32_t t) {
  CellRange& range = ranges_[static_cast<std::size_t>(t)];
  for (long long iz = range.z0; iz <= range.z1; ++iz) {
    for (long long ir = range.r0; ir <= range.r1; ++ir) {
      auto& list = cells_[static_cast<std::size_t>(iz * num_r_ + ir)];
      list.erase(std::remove(list.begin(), list.end(), t), list.end());
    }
  }
  if (range.overflow) overflow_.erase(std::remove(overflow_.begin(), overflow_.end(), t), overflow_.end());
  range = CellRange{};
}

CylindricalTable CylindricalTable::build(const geometry::TriMesh& fixed, const Vec3& centre,
                                         const Vec3& axis, const CylindricalTableOptions& options,
                                         const geometry::TriMesh* restrict_to_mobile) {
  CylindricalTable table;
  const AxisFrameResult frame = make_axis_frame(centre, axis);
  if (!frame.valid) {
    table.message_ = "rotation axis must be finite and non-zero, centre finite";
    return table;
  }
  if (fixed.empty() || !all_finite(fixed)) {
    table.message_ = "fixed mesh is empty, has a non-finite coordinate or an index out of range";
    return table;
  }
  if (restrict_to_mobile != nullptr &&
      (restrict_to_mobile->vertices.empty() || !all_finite(*restrict_to_mobile))) {
    table.message_ = "mobile mesh is empty, has a non-finite coordinate or an index out of range";
    return table;
  }
  if (!(options.resolution_r_mm >= 0.0) || !(options.resolution_z_mm >= 0.0) ||
      !std::isfinite(options.resolution_r_mm) || !std::isfinite(options.resolution_z_mm)) {
    table.message_ = "table resolution must be finite and >= 0";
    return table;
  }
  table.frame_ = frame.frame;
  table.status_ = QueryStatus::kOk;
  table.message_.clear();
  table.neighbour_cells_ = std::max(options.neighbour_cells, 0);
  table.refresh_geometry(fixed);
  RingExtent extent = table.measure_fixed();
  if (restrict_to_mobile != nullptr && !table.restrict_to(*restrict_to_mobile, extent)) {
    table.status_ = QueryStatus::kNoOverlap;
    table.num_r_ = table.num_z_ = 0;
    return table;
  }
  table.make_cells(extent, fixed, options);
  if (options.angular_index) {
    table.build_angular_index();
    if (restrict_to_mobile != nullptr) table.mobile_clusters_ = VertexClusters::build(*restrict_to_mobile);
  }
  return table;
}

CylindricalTable::RingExtent CylindricalTable::measure_fixed() {
  const std::size_t num_triangles = triangles_.size();
  local_normals_.resize(num_triangles);
  planes_.resize(num_triangles);
  ranges_.resize(num_triangles);
  RingExtent extent{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  double l_min = std::numeric_limits<double>::infinity(), l_max = 0.0;
  for (std::size_t t = 0; t < num_triangles; ++t) {
    refresh_triangle_normal(static_cast<std::int32_t>(t));
    const auto& tri = triangles_[t];
    const Vec3& a = local_vertex(tri[0]);
    const Vec3& b = local_vertex(tri[1]);
    const Vec3& c = local_vertex(tri[2]);
    const CylindricalBounds bounds = triangle_cylindrical_bounds(a, b, c);
    extent.r_lo = std::min(extent.r_lo, bounds.r_min);
    extent.r_hi = std::max(extent.r_hi, bounds.r_max);
    extent.z_lo = std::min(extent.z_lo, bounds.z_min);
    extent.z_hi = std::max(extent.z_hi, bounds.z_max);
    l_min = std::min(l_min, point_triangle_distance(Vec3::Zero(), a, b, c));
    l_max = std::max({l_max, a.norm(), b.norm(), c.norm()});
  }
  const double scale = std::max({1.0, extent.r_hi, std::abs(extent.z_lo), std::abs(extent.z_hi)});
  pad_ = kTablePad * scale;
  l_min_ = l_min - pad_;
  l_max_ = l_max + pad_;
  return extent;
}

bool CylindricalTable::restrict_to(const geometry::TriMesh& mobile, RingExtent& extent) const {
  // Eq. 2-3: intersect with the mobile ranges (rotation-invariant r, z, |x - c|).
  double mr_lo = std::numeric_limits<double>::infinity(), mr_hi = -mr_lo;
  double mz_lo = mr_lo, mz_hi = -mr_lo, ml_lo = mr_lo, ml_hi = 0.0;
  for (const Vec3& p : mobile.vertices) {
    const Vec3 local = frame_.to_local(p);
    const double r = std::hypot(local.x(), local.y());
    mr_lo = std::min(mr_lo, r);
    mr_hi = std::max(mr_hi, r);
    mz_lo = std::min(mz_lo, local.z());
    mz_hi = std::max(mz_hi, local.z());
    ml_lo = std::min(ml_lo, local.norm());
    ml_hi = std::max(ml_hi, local.norm());
  }
  extent.r_lo = std::max(extent.r_lo, mr_lo);
  extent.r_hi = std::min(extent.r_hi, mr_hi);
  extent.z_lo = std::max(extent.z_lo, mz_lo);
  extent.z_hi = std::min(extent.z_hi, mz_hi);
  return !(extent.r_lo > extent.r_hi + 2.0 * pad_ || extent.z_lo > extent.z_hi + 2.0 * pad_ || ml_lo > l_max_ ||
           ml_hi < l_min_);
}

void CylindricalTable::make_cells(const RingExtent& extent, const geometry::TriMesh& fixed,
                                  const CylindricalTableOptions& options) {
  r_lo_ = extent.r_lo - pad_;
  r_hi_ = extent.r_hi + pad_;
  z_lo_ = extent.z_lo - pad_;
  z_hi_ = extent.z_hi + pad_;
  const double edge = geometry::mean_edge_length(fixed);
  double res_r = options.resolution_r_mm > 0.0 ? options.resolution_r_mm : edge;
  double res_z = options.resolution_z_mm > 0.0 ? options.resolution_z_mm : edge;
  if (!(res_r > 0.0)) res_r = 1.0;
  if (!(res_z > 0.0)) res_z = 1.0;
  const auto count = [](double extent_mm, double res) {
    return static_cast<long long>(std::floor(extent_mm / res)) + 1;
  };
  const double r_extent = r_hi_ - r_lo_, z_extent = z_hi_ - z_lo_;
  const double max_cells = static_cast<double>(std::max<std::size_t>(options.max_cells, 1));
  while (static_cast<double>(count(r_extent, res_r)) * static_cast<double>(count(z_extent, res_z)) >
         max_cells) {
    res_r *= 2.0;
    res_z *= 2.0;
  }
  res_r_ = res_r;
  res_z_ = res_z;
  num_r_ = count(r_extent, res_r);
  num_z_ = count(z_extent, res_z);
  cells_.assign(static_cast<std::size_t>(num_r_ * num_z_), {});
  for (std::size_t t = 0; t < triangles_.size(); ++t) bin_triangle(static_cast<std::int32_t>(t), /*allow_overflow=*/false);
}

void CylindricalTable::build_angular_index() {
  const std::size_t num_cells = cells_.size();
  const auto down = [](double value) {
    float f = static_cast<float>(value);
    if (static_cast<double>(f) > value) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
  };
  const auto up = [](double value) {
    float f = static_cast<float>(value);
    if (static_cast<double>(f) < value) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
  };
  std::vector<AngularEntry> entries(triangles_.size());
  std::vector<double> widths(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    const Vec3& a = local_vertex(tri[0]);
    const Vec3& b = local_vertex(tri[1]);
    const Vec3& c = local_vertex(tri[2]);
    const AngularExtent extent = triangle_angular_extent(a, b, c);
    double lo = extent.lo;
    while (lo < -std::numbers::pi) lo += 2.0 * std::numbers::pi;
    while (lo >= std::numbers::pi) lo -= 2.0 * std::numbers::pi;
    const CylindricalBounds bounds = triangle_cylindrical_bounds(a, b, c);
    AngularEntry& entry = entries[t];
    entry.lo = lo;
    entry.r_min = down(bounds.r_min - pad_);
    entry.r_max = up(bounds.r_max + pad_);
    entry.z_min = down(bounds.z_min - pad_);
    entry.z_max = up(bounds.z_max + pad_);
    entry.triangle = static_cast<std::int32_t>(t);
    widths[t] = extent.all_angles() ? -1.0 : extent.width;
  }
  angular_begin_.assign(num_cells + 1, 0);
  all_begin_.assign(num_cells + 1, 0);
  angular_width_.assign(num_cells, 0.0);
  angular_entries_.clear();
  all_entries_.clear();
  for (std::size_t c = 0; c < num_cells; ++c) {
    const std::size_t first = angular_entries_.size();
    for (std::int32_t t : cells_[c]) {
      const auto ti = static_cast<std::size_t>(t);
      if (widths[ti] < 0.0) {
        all_entries_.push_back(entries[ti]);
      } else {
        angular_entries_.push_back(entries[ti]);
        angular_width_[c] = std::max(angular_width_[c], widths[ti]);
      }
    }
    std::sort(angular_entries_.begin() + static_cast<std::ptrdiff_t>(first), angular_entries_.end(),
              [](const AngularEntry& x, const AngularEntry& y) {
                return x.lo < y.lo || (x.lo == y.lo && x.triangle < y.triangle);
              });
    angular_begin_[c + 1] = static_cast<std::uint32_t>(angular_entries_.size());
    all_begin_[c + 1] = static_cast<std::uint32_t>(all_entries_.size());
  }
  occupied_prefix_.assign(static_cast<std::size_t>((num_z_ + 1) * (num_r_ + 1)), 0);
  const auto prefix = [&](long long iz, long long ir) -> std::uint32_t& {
    return occupied_prefix_[static_cast<std::size_t>(iz * (num_r_ + 1) + ir)];
  };
  for (long long iz = 0; iz < num_z_; ++iz) {
    for (long long ir = 0; ir < num_r_; ++ir) {
      const bool occupied = !cells_[static_cast<std::size_t>(iz * num_r_ + ir)].empty();
      prefix(iz + 1, ir + 1) = prefix(iz, ir + 1) + prefix(iz + 1, ir) - prefix(iz, ir) + (occupied ? 1u : 0u);
    }
  }
  build_outside_regions(widths);
}

bool CylindricalTable::has_candidates(double r, double z) const {
  if (neighbour_cells_ != 0) return true;
  const long long cell_r = cell_index(r, r_lo_, res_r_);
  const long long cell_z = cell_index(z, z_lo_, res_z_);
  if (cell_r < 0 || cell_r >= num_r_ || cell_z < 0 || cell_z >= num_z_) return !overflow_.empty();
  return !cells_[static_cast<std::size_t>(cell_z * num_r_ + cell_r)].empty();
}

bool CylindricalTable::ball_may_touch(const Vec3& local_centre, double radius_mm) const {
  if (neighbour_cells_ != 0 || occupied_prefix_.size() != static_cast<std::size_t>((num_z_ + 1) * (num_r_ + 1))) {
    return true;
  }
  const double distance = local_centre.norm();
  if (!(distance + radius_mm >= l_min_ && distance - radius_mm <= l_max_)) return false;
  const double r = std::hypot(local_centre.x(), local_centre.y());
  long long r0 = cell_index(r - radius_mm, r_lo_, res_r_), r1 = cell_index(r + radius_mm, r_lo_, res_r_);
  long long z0 = cell_index(local_centre.z() - radius_mm, z_lo_, res_z_);
  long long z1 = cell_index(local_centre.z() + radius_mm, z_lo_, res_z_);
  const bool leaves_grid = r0 < 0 || r1 >= num_r_ || z0 < 0 || z1 >= num_z_;
  if (leaves_grid && !overflow_.empty()) return true;
  r0 = std::max<long long>(r0, 0);
  z0 = std::max<long long>(z0, 0);
  r1 = std::min<long long>(r1, num_r_ - 1);
  z1 = std::min<long long>(z1, num_z_ - 1);
  if (r0 > r1 || z0 > z1) return false;
  const auto prefix = [&](long long iz, long long ir) {
    return static_cast<long long>(occupied_prefix_[static_cast<std::size_t>(iz * (num_r_ + 1) + ir)]);
  };
  return prefix(z1 + 1, r1 + 1) - prefix(z0, r1 + 1) - prefix(z1 + 1, r0) + prefix(z0, r0) > 0;
}

NearestCrossing CylindricalTable::nearest_crossing_of_every_candidate(double r, double z, double theta) const {
  NearestCrossing nearest;
  std::array<double, 2> angles{};
  for_each_candidate(r, z, [&](std::int32_t t) {
    const int n = crossings(t, r, z, angles);
    for (int i = 0; i < n; ++i) nearest.offer(theta, angles[static_cast<std::size_t>(i)], t);
  });
  return nearest;
}

NearestCrossing CylindricalTable::nearest_crossing(double r, double z, double theta) const {
  const long long cell_r = cell_index(r, r_lo_, res_r_);
  const long long cell_z = cell_index(z, z_lo_, res_z_);
  const bool outside = cell_r < 0 || cell_r >= num_r_ || cell_z < 0 || cell_z >= num_z_;
  if (outside || neighbour_cells_ != 0 || angular_begin_.size() != cells_.size() + 1) {
    return nearest_crossing_of_every_candidate(r, z, theta);
  }
  NearestCrossing nearest;
  std::array<double, 2> angles{};
  const auto offer = [&](std::int32_t t) {
    const int n = crossings(t, r, z, angles);
    for (int i = 0; i < n; ++i) nearest.offer(theta, angles[static_cast<std::size_t>(i)], t);
  };
  const auto c = static_cast<std::size_t>(cell_z * num_r_ + cell_r);
  for (std::size_t i = all_begin_[c]; i < all_begin_[c + 1]; ++i) {
    if (all_entries_[i].holds(r, z)) offer(all_entries_[i].triangle);
  }
  const std::size_t n = angular_begin_[c + 1] - angular_begin_[c];
  if (n == 0) return nearest;
  const AngularEntry* entry = angular_entries_.data() + angular_begin_[c];
  const double width = angular_width_[c];
  constexpr double two_pi = 2.0 * std::numbers::pi;
  // Forward: entries by increasing (lo - theta) mod 2 pi, from the first lo > theta; an extent
  // starting farther ahead than the nearest crossing holds none nearer that way, and none nearer
  // the other way while it also starts more than nearest + width behind (checked by the backward
  // walk, which meets the same entries from the other side). Backward: entries by increasing
  // (theta - lo) mod 2 pi; an extent starting more than nearest + width behind ends more than
  // nearest behind. Distances are monotone along each walk and the nearest only shrinks, so once a
  // walk stops, every entry beyond it stays out of reach; entries neither walk reached are at
  // angular distance > nearest everywhere in their extent (see nearest_crossing in the header).
  const std::size_t i0 = static_cast<std::size_t>(
      std::partition_point(entry, entry + n, [theta](const AngularEntry& e) { return e.lo <= theta; }) - entry);
  std::size_t forward = 0, backward = 0;
  bool forward_open = true, backward_open = true;
  while ((forward_open || backward_open) && forward + backward < n) {
    if (forward_open) {
      std::size_t j = i0 + forward;
      const bool wrapped = j >= n;
      if (wrapped) j -= n;
      const double distance = entry[j].lo - theta + (wrapped ? two_pi : 0.0);
      if (distance > nearest.abs_delta_rad) {
        forward_open = false;
      } else {
        if (entry[j].holds(r, z)) offer(entry[j].triangle);
        ++forward;
      }
    }
    if (backward_open && forward + backward < n) {
      const std::size_t k = backward + 1;
      const bool wrapped = k > i0;
      const std::size_t j = wrapped ? i0 + n - k : i0 - k;
      const double distance = theta - entry[j].lo + (wrapped ? two_pi : 0.0);
      if (distance > nearest.abs_delta_rad + width) {
        backward_open = false;
      } else {
        if (entry[j].holds(r, z)) offer(entry[j].triangle);
        ++backward;
      }
    }
  }
  return nearest;
}

void update_triangles(CylindricalTable& table, const geometry::TriMesh& fixed_now,
                      std::span<const std::int32_t> changed_triangles, TableUpdate mode) {
  if (table.status_ == QueryStatus::kInvalidInput) throw_error("update_triangles: the table is not valid");
  if (fixed_now.vertices.size() != table.local_vertices_.size() ||
      fixed_now.triangles.size() != table.triangles_.size() || !all_finite(fixed_now)) {
    throw_error("update_triangles: the deformed mesh must keep the vertex and triangle counts (",
                table.local_vertices_.size(), ", ", table.triangles_.size(),
                ") and finite coordinates");
  }
  const auto num_triangles = static_cast<std::int32_t>(table.triangles_.size());
  for (std::int32_t t : changed_triangles) {
    if (t < 0 || t >= num_triangles) {
      throw_error("update_triangles: triangle id ", t, " out of range [0, ", num_triangles, ")");
    }
  }
  table.refresh_geometry(fixed_now);
  for (std::int32_t t : changed_triangles) {
    table.refresh_triangle_normal(t);
    const auto& tri = table.triangles_[static_cast<std::size_t>(t)];
    const Vec3& a = table.local_vertex(tri[0]);
    const Vec3& b = table.local_vertex(tri[1]);
    const Vec3& c = table.local_vertex(tri[2]);
    // The L filter only widens, so it stays conservative.
    table.l_min_ = std::min(table.l_min_, point_triangle_distance(Vec3::Zero(), a, b, c) - table.pad_);
    table.l_max_ = std::max({table.l_max_, a.norm() + table.pad_, b.norm() + table.pad_,
                             c.norm() + table.pad_});
    if (mode == TableUpdate::kRebin) {
      table.unbin_triangle(t);
      table.bin_triangle(t, /*allow_overflow=*/true);
    }
  }
  if (!table.angular_begin_.empty()) table.build_angular_index();
  // A table that had no overlap may have one now, through the overflow list.
  if (table.status_ == QueryStatus::kNoOverlap && !table.overflow_.empty()) {
    table.status_ = QueryStatus::kOk;
  }
}

}  // namespace hipfai::contact
