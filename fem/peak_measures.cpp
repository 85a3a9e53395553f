#include "fem/peak_measures.h"

#include "core/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace hipfai::fem {

namespace {

using GridCell = std::array<std::int64_t, 3>;

struct GridCellHash {
  std::size_t operator()(const GridCell& cell) const {
    // Distinct odd multipliers per axis, so that the neighbouring cells of one ball land in
    // different buckets (a plain sum of the indices would collide along diagonals).
    const std::uint64_t hash = static_cast<std::uint64_t>(cell[0]) * 0x9E3779B97F4A7C15ull ^
                               static_cast<std::uint64_t>(cell[1]) * 0xC2B2AE3D27D4EB4Full ^
                               static_cast<std::uint64_t>(cell[2]) * 0x165667B19E3779F9ull;
    return static_cast<std::size_t>(hash ^ (hash >> 29));
  }
};

void check_input(const std::vector<FieldSample>& samples, double radius_mm) {
  if (!std::isfinite(radius_mm) || radius_mm <= 0.0) {
    throw_error("ball-averaged peak: the radius must be finite and > 0 mm, got ", radius_mm);
  }
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const FieldSample& sample = samples[i];
    if (!sample.position_mm.allFinite()) {
      throw_error("ball-averaged peak: sample ", i, " has a non-finite position");
    }
    if (!std::isfinite(sample.value)) {
      throw_error("ball-averaged peak: sample ", i, " has a non-finite value (", sample.value, ")");
    }
    if (!std::isfinite(sample.weight) || sample.weight <= 0.0) {
      throw_error("ball-averaged peak: sample ", i, " has weight ", sample.weight,
                  " (must be finite and > 0)");
    }
  }
}

}  // namespace

std::vector<BallAverage> ball_averages(const std::vector<FieldSample>& samples, double radius_mm) {
  check_input(samples, radius_mm);
  const std::size_t n = samples.size();
  std::vector<BallAverage> averages(n);
  if (n == 0) return averages;

  // Cells a hair larger than r: a sample within r of the centre then lies in one of the 27 cells
  // around the centre's, even when rounding in the division puts a sample that is exactly r away
  // on the far side of a cell face.
  const double cell_mm = radius_mm * (1.0 + 1e-9);
  geometry::Vec3 lower = samples.front().position_mm, upper = lower;
  for (const FieldSample& sample : samples) {
    lower = lower.cwiseMin(sample.position_mm);
    upper = upper.cwiseMax(sample.position_mm);
  }
  // The 1e-9 margin above covers the rounding of (x - lower) / cell only while x / cell stays
  // below ~1e6 (double rounding 1.1e-16 per operation, a few operations); a radius a million
  // times smaller than the samples' spread is a unit mistake (m for mm), not a measurement.
  constexpr double kMaxCells = 1e6;
  if ((upper - lower).maxCoeff() / cell_mm > kMaxCells) {
    throw_error("ball-averaged peak: radius ", radius_mm,
                " mm is too small for samples spread over ", (upper - lower).maxCoeff(), " mm");
  }
  std::vector<GridCell> cell_of(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      cell_of[i][d] =
          static_cast<std::int64_t>(std::floor((samples[i].position_mm[d] - lower[d]) / cell_mm));
    }
  }
  // The samples' cells, counted into a dense grid (x slowest, z fastest) when it is not much
  // larger than the samples (the FE's fields: a few cells per sample), else hashed. Each cell
  // maps to its range of `order`, the samples sorted by cell (stable): the same order either way,
  // so the same sums.
  std::array<std::int64_t, 3> extent{};
  for (int d = 0; d < 3; ++d) extent[d] = static_cast<std::int64_t>(std::floor((upper[d] - lower[d]) / cell_mm)) + 1;
  const double cells = static_cast<double>(extent[0]) * static_cast<double>(extent[1]) * static_cast<double>(extent[2]);
  const bool dense = cells <= 16.0 * static_cast<double>(n) + 1e6;
  const auto dense_index = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::size_t>((x * extent[1] + y) * extent[2] + z);
  };
  std::vector<std::size_t> order(n);
  std::vector<std::size_t> start;  // dense: first index into `order` of each cell, and the end
  std::unordered_map<GridCell, std::pair<std::size_t, std::size_t>, GridCellHash> range_of;
  if (dense) {
    start.assign(static_cast<std::size_t>(cells) + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++start[dense_index(cell_of[i][0], cell_of[i][1], cell_of[i][2]) + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) order[next[dense_index(cell_of[i][0], cell_of[i][1], cell_of[i][2])]++] = i;
  } else {
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&cell_of](std::size_t a, std::size_t b) { return cell_of[a] < cell_of[b]; });
    range_of.reserve(n);
    for (std::size_t k = 0; k < n;) {
      std::size_t last = k + 1;
      while (last < n && cell_of[order[last]] == cell_of[order[k]]) ++last;
      range_of.emplace(cell_of[order[k]], std::make_pair(k, last));
      k = last;
    }
  }
  // The samples of the cells (x, y, z - 1 .. z + 1), in order: one range of the dense grid.
  const auto column = [&](std::int64_t x, std::int64_t y, std::int64_t z, std::size_t& first, std::size_t& last) {
    first = last = 0;
    if (x < 0 || y < 0 || x >= extent[0] || y >= extent[1]) return;
    const std::int64_t low = std::max<std::int64_t>(z - 1, 0), high = std::min<std::int64_t>(z + 1, extent[2] - 1);
    first = start[dense_index(x, y, low)];
    last = start[dense_index(x, y, high) + 1];
  };

  const double radius_squared = radius_mm * radius_mm;
  for (std::size_t i = 0; i < n; ++i) {
    const geometry::Vec3& centre = samples[i].position_mm;
    double weighted_sum = 0.0;
    BallAverage& ball = averages[i];
    const auto add_range = [&](std::size_t first, std::size_t last) {
      for (std::size_t k = first; k < last; ++k) {
        const FieldSample& other = samples[order[k]];
        if ((other.position_mm - centre).squaredNorm() > radius_squared) continue;
        weighted_sum += other.weight * other.value;
        ball.weight += other.weight;
        ++ball.samples;
      }
    };
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        if (dense) {
          std::size_t first = 0, last = 0;
          column(cell_of[i][0] + dx, cell_of[i][1] + dy, cell_of[i][2], first, last);
          add_range(first, last);
          continue;
        }
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto found = range_of.find({cell_of[i][0] + dx, cell_of[i][1] + dy, cell_of[i][2] + dz});
          if (found != range_of.end()) add_range(found->second.first, found->second.second);
        }
      }
    }
    // The centre is always in its own ball and every weight is > 0: no division by zero.
    ball.value = weighted_sum / ball.weight;
  }
  return averages;
}

BallPeak ball_averaged_peak(const std::vector<FieldSample>& samples, double radius_mm) {
  const std::vector<BallAverage> averages = ball_averages(samples, radius_mm);
  BallPeak peak;
  for (std::size_t i = 0; i < averages.size(); ++i) {
    if (peak.found && !(averages[i].value > peak.value)) continue;  // ties: the lowest index
    peak.found = true;
    peak.value = averages[i].value;
    peak.sample = i;
    peak.position_mm = samples[i].position_mm;
    peak.samples_in_ball = averages[i].samples;
    peak.ball_weight = averages[i].weight;
  }
  return peak;
}

}  // namespace hipfai::fem
