#include "contact/angular_interval_index.h"

#include "contact/arc_triangle.h"
#include "core/error.h"
#include "core/numbers.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hipfai::contact {
namespace {

using hipfai::kPi;
using hipfai::kTwoPi;

std::size_t bins_of_level(int levels, int level) { return std::size_t{1} << (levels - 1 - level); }

// Monotone in x (IEEE addition and division by a positive constant are), so lo <= x <= hi puts
// x's bin between lo's and hi's.
std::size_t bin_of(double x, std::size_t bins) {
  const double scaled = std::floor((x + kPi) / kTwoPi * static_cast<double>(bins));
  if (!(scaled > 0.0)) return 0;
  return std::min(bins - 1, static_cast<std::size_t>(scaled));
}

}  // namespace

AngularIntervalIndex::AngularIntervalIndex(const std::vector<AngularArc>& arcs, int levels)
    : levels_(levels), num_arcs_(arcs.size()) {
  if (levels < 1 || levels > 20) throw_error("angular interval index: ", levels, " levels; need 1..20");
  struct Piece {
    double lo, hi;
    std::int32_t id;
    int level;
  };
  std::vector<Piece> pieces;
  pieces.reserve(arcs.size());
  for (const AngularArc& arc : arcs) {
    if (!std::isfinite(arc.start_rad) || !std::isfinite(arc.length_rad) || arc.length_rad < 0.0) {
      throw_error("angular interval index: arc ", arc.id, " has start ", arc.start_rad, " and length ",
                  arc.length_rad, "; need a finite start and a finite length >= 0");
    }
    if (arc.length_rad >= kTwoPi) {
      full_circle_.push_back(arc.id);
      continue;
    }
    const double lo = wrap_angle(arc.start_rad);
    const double hi = lo + arc.length_rad;
    if (hi <= kPi) {
      pieces.push_back({lo, hi, arc.id, 0});
    } else {
      pieces.push_back({lo, kPi, arc.id, 0});
      pieces.push_back({-kPi, hi - kTwoPi, arc.id, 0});
    }
  }
  level_first_bin_.assign(static_cast<std::size_t>(levels) + 1, 0);
  for (int level = 0; level < levels; ++level) {
    level_first_bin_[static_cast<std::size_t>(level) + 1] =
        level_first_bin_[static_cast<std::size_t>(level)] + bins_of_level(levels, level);
  }
  const std::size_t total_bins = level_first_bin_.back();
  std::vector<std::size_t> counts(total_bins + 1, 0);
  const auto for_each_bin = [&](const Piece& piece, auto&& visit) {
    const std::size_t bins = bins_of_level(levels, piece.level);
    const std::size_t first = level_first_bin_[static_cast<std::size_t>(piece.level)];
    for (std::size_t b = bin_of(piece.lo, bins); b <= bin_of(piece.hi, bins); ++b) visit(first + b);
  };
  for (Piece& piece : pieces) {
    const double length = piece.hi - piece.lo;
    while (piece.level < levels - 1 &&
           kTwoPi / static_cast<double>(bins_of_level(levels, piece.level)) < length) {
      ++piece.level;
    }
    for_each_bin(piece, [&](std::size_t bin) { ++counts[bin + 1]; });
  }
  for (std::size_t b = 0; b < total_bins; ++b) counts[b + 1] += counts[b];
  offsets_ = counts;
  entries_.resize(offsets_.back());
  std::vector<std::size_t> fill(offsets_.begin(), offsets_.end() - 1);
  for (const Piece& piece : pieces) {
    for_each_bin(piece, [&](std::size_t bin) { entries_[fill[bin]++] = {piece.lo, piece.hi, piece.id}; });
  }
}

void AngularIntervalIndex::stab(double angle_rad, std::vector<std::int32_t>& ids) const {
  if (!std::isfinite(angle_rad) || levels_ == 0) return;
  ids.insert(ids.end(), full_circle_.begin(), full_circle_.end());
  const double angle = wrap_angle(angle_rad);
  for (int level = 0; level < levels_; ++level) {
    const std::size_t bin =
        level_first_bin_[static_cast<std::size_t>(level)] + bin_of(angle, bins_of_level(levels_, level));
    for (std::size_t k = offsets_[bin]; k < offsets_[bin + 1]; ++k) {
      const Entry& entry = entries_[k];
      if (entry.lo <= angle && angle <= entry.hi) ids.push_back(entry.id);
    }
  }
}

}  // namespace hipfai::contact
