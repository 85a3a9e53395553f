// hipfai — the outside regions of the ring table (CylindricalTable::outside_every_shell).
#include "contact/cylindrical_table.h"

#include "core/numbers.h"
#include "geometry/mesh_check.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hipfai::contact {
namespace {

using hipfai::kTwoPi;
// A crossing whose tangent meets the triangle's plane at less than this (|sin| of the angle
// between the circle and the plane) does not settle a side: the circle may only graze there.
constexpr double kTransversal = 1e-6;
// Two crossings of one shell this close (rad) are one place on the circle: if they disagree on
// the side, the sample settles nothing.
constexpr double kSamePlaceRad = 1e-9;

// An angular interval [lo, hi] with lo in [-pi, pi) and hi - lo < 2 pi.
struct Interval {
  double lo, hi;
};

// The gaps between the union of the extents (sorted by lo), as open intervals (a, b) with
// a in [-pi, 3 pi) and b > a; none when the extents cover the whole circle.
std::vector<Interval> gaps_between(const std::vector<Interval>& extents) {
  std::vector<Interval> covered;
  for (const Interval& e : extents) {
    if (!covered.empty() && e.lo <= covered.back().hi) {
      covered.back().hi = std::max(covered.back().hi, e.hi);
    } else {
      covered.push_back(e);
    }
  }
  std::vector<Interval> gaps;
  if (covered.empty()) return gaps;
  // Only the last interval can reach beyond pi; what it covers past 2 pi covers the first gaps.
  const double wrapped_end = covered.back().hi - kTwoPi;
  for (std::size_t i = 0; i + 1 < covered.size(); ++i) {
    Interval gap{covered[i].hi, covered[i + 1].lo};
    gap.lo = std::max(gap.lo, wrapped_end);
    if (gap.lo < gap.hi) gaps.push_back(gap);
  }
  const Interval wrap{covered.back().hi, covered.front().lo + kTwoPi};
  if (wrap.lo < wrap.hi) gaps.push_back(wrap);
  return gaps;
}

// One crossing of a sample circle: its angle, shell and exit sign (crossing_exit_sign).
struct SampleCrossing {
  double theta;
  std::int32_t shell;
  double exit_sign;
};

enum class Side { kUnsettled, kOutside, kInside };

// The side of shell `shell` at angle theta of a sample circle, from its nearest crossings of that
// shell ahead (anticlockwise) and behind.
Side side_of(const std::vector<SampleCrossing>& crossings, std::int32_t shell, double theta) {
  const auto ahead_of = [theta](const SampleCrossing& c) {
    double d = c.theta - theta;
    while (d <= 0.0) d += kTwoPi;
    while (d > kTwoPi) d -= kTwoPi;
    return d;  // in (0, 2 pi]; behind is 2 pi - d
  };
  const SampleCrossing* ahead = nullptr;
  const SampleCrossing* behind = nullptr;
  for (const SampleCrossing& c : crossings) {
    if (c.shell != shell) continue;
    if (ahead == nullptr || ahead_of(c) < ahead_of(*ahead)) ahead = &c;
    if (behind == nullptr || ahead_of(c) > ahead_of(*behind)) behind = &c;
  }
  if (ahead == nullptr) return Side::kUnsettled;
  const double ahead_sign = ahead->exit_sign, behind_sign = behind->exit_sign;
  if (std::abs(ahead_sign) < kTransversal || std::abs(behind_sign) < kTransversal) return Side::kUnsettled;
  // A crossing of the shell at the same place with the other sign: the side is not settled here.
  for (const SampleCrossing& c : crossings) {
    if (c.shell != shell) continue;
    const double d = ahead_of(c);
    if ((d - ahead_of(*ahead) <= kSamePlaceRad && (c.exit_sign > 0.0) != (ahead_sign > 0.0)) ||
        (ahead_of(*behind) - d <= kSamePlaceRad && (c.exit_sign > 0.0) != (behind_sign > 0.0))) {
      return Side::kUnsettled;
    }
  }
  // Moving anticlockwise: out of the shell behind, into it ahead = outside between; the reverse =
  // inside. Anything else (a missed crossing) settles nothing.
  if (behind_sign > 0.0 && ahead_sign < 0.0) return Side::kOutside;
  if (behind_sign < 0.0 && ahead_sign > 0.0) return Side::kInside;
  return Side::kUnsettled;
}

}  // namespace

void CylindricalTable::build_outside_regions(const std::vector<double>& extent_widths) {
  const std::size_t num_cells = cells_.size();
  region_begin_.assign(num_cells + 1, 0);
  outside_regions_.clear();
  if (!shells_known_) {
    shell_ = geometry::closed_shell_labels(triangles_).value_or(std::vector<std::int32_t>{});
    shells_known_ = true;
  }
  if (shell_.empty()) return;

  std::vector<Interval> extents;
  std::vector<std::int32_t> shells;
  std::vector<SampleCrossing> crossings_of_sample;
  std::vector<Side> settled;  // per (gap, shell)
  std::array<double, 2> angles{};
  for (std::size_t c = 0; c < num_cells; ++c) {
    region_begin_[c] = static_cast<std::uint32_t>(outside_regions_.size());
    const std::uint32_t first = angular_begin_[c], last = angular_begin_[c + 1];
    if (first == last || all_begin_[c] != all_begin_[c + 1]) continue;
    extents.clear();
    shells.clear();
    for (std::uint32_t i = first; i < last; ++i) {
      const AngularEntry& e = angular_entries_[i];
      extents.push_back({e.lo, e.lo + extent_widths[static_cast<std::size_t>(e.triangle)]});
      shells.push_back(shell_[static_cast<std::size_t>(e.triangle)]);
    }
    const std::vector<Interval> gaps = gaps_between(extents);
    if (gaps.empty()) continue;
    std::sort(shells.begin(), shells.end());
    shells.erase(std::unique(shells.begin(), shells.end()), shells.end());
    settled.assign(gaps.size() * shells.size(), Side::kUnsettled);

    const auto iz = static_cast<long long>(c) / num_r_;
    const auto ir = static_cast<long long>(c) % num_r_;
    // Sample circles: the cell's centre, then four points halfway to its corners.
    static constexpr std::array<std::array<double, 2>, 5> kSamples{
        {{0.5, 0.5}, {0.25, 0.25}, {0.75, 0.25}, {0.25, 0.75}, {0.75, 0.75}}};
    for (const auto& [fr, fz] : kSamples) {
      const double r = r_lo_ + (static_cast<double>(ir) + fr) * res_r_;
      const double z = z_lo_ + (static_cast<double>(iz) + fz) * res_z_;
      if (!(r > 0.0)) continue;
      crossings_of_sample.clear();
      for (std::uint32_t i = first; i < last; ++i) {
        const AngularEntry& e = angular_entries_[i];
        if (!e.holds(r, z)) continue;
        const int n = crossings(e.triangle, r, z, angles);
        for (int k = 0; k < n; ++k) {
          const double theta = angles[static_cast<std::size_t>(k)];
          crossings_of_sample.push_back({theta, shell_[static_cast<std::size_t>(e.triangle)],
                                         crossing_exit_sign(theta, local_normal(e.triangle))});
        }
      }
      bool all_settled = true;
      for (std::size_t g = 0; g < gaps.size(); ++g) {
        const double middle = wrap_angle(0.5 * (gaps[g].lo + gaps[g].hi));
        for (std::size_t s = 0; s < shells.size(); ++s) {
          Side& side = settled[g * shells.size() + s];
          if (side == Side::kUnsettled) side = side_of(crossings_of_sample, shells[s], middle);
          all_settled = all_settled && side != Side::kUnsettled;
        }
      }
      if (all_settled) break;
    }
    const std::size_t cell_first = outside_regions_.size();
    for (std::size_t g = 0; g < gaps.size(); ++g) {
      const bool outside = std::all_of(settled.begin() + static_cast<std::ptrdiff_t>(g * shells.size()),
                                       settled.begin() + static_cast<std::ptrdiff_t>((g + 1) * shells.size()),
                                       [](Side side) { return side == Side::kOutside; });
      if (!outside) continue;
      // Into [-pi - 1, pi + 1]: shifted down by 2 pi when it starts beyond pi, split when across.
      Interval gap = gaps[g];
      if (gap.lo >= std::numbers::pi) {
        gap.lo -= kTwoPi;
        gap.hi -= kTwoPi;
      }
      if (gap.hi > std::numbers::pi) {
        outside_regions_.push_back({gap.lo, std::numbers::pi + 1.0});
        outside_regions_.push_back({-std::numbers::pi - 1.0, gap.hi - kTwoPi});
      } else {
        outside_regions_.push_back({gap.lo, gap.hi});
      }
    }
    std::sort(outside_regions_.begin() + static_cast<std::ptrdiff_t>(cell_first), outside_regions_.end(),
              [](const OutsideRegion& a, const OutsideRegion& b) { return a.lo < b.lo; });
  }
  region_begin_[num_cells] = static_cast<std::uint32_t>(outside_regions_.size());
}

std::span<const CylindricalTable::OutsideRegion> CylindricalTable::outside_regions(long long i_z,
                                                                                 long long i_r) const {
  if (region_begin_.size() != cells_.size() + 1 || i_z < 0 || i_z >= num_z_ || i_r < 0 || i_r >= num_r_) return {};
  const auto c = static_cast<std::size_t>(i_z * num_r_ + i_r);
  return {outside_regions_.data() + region_begin_[c], outside_regions_.data() + region_begin_[c + 1]};
}

bool CylindricalTable::outside_every_shell(double r, double z, double theta) const {
  if (neighbour_cells_ != 0 || region_begin_.size() != cells_.size() + 1) return false;
  const long long cell_r = cell_index(r, r_lo_, res_r_);
  const long long cell_z = cell_index(z, z_lo_, res_z_);
  if (cell_r < 0 || cell_r >= num_r_ || cell_z < 0 || cell_z >= num_z_) return false;
  const auto c = static_cast<std::size_t>(cell_z * num_r_ + cell_r);
  const OutsideRegion* begin = outside_regions_.data() + region_begin_[c];
  const OutsideRegion* end = outside_regions_.data() + region_begin_[c + 1];
  const OutsideRegion* after = std::partition_point(begin, end, [theta](const OutsideRegion& g) { return g.lo < theta; });
  return after != begin && theta < (after - 1)->hi;
}

}  // namespace hipfai::contact
