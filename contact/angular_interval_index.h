// hipfai — which of a fixed set of closed arcs of the circle contain a given angle (a stabbing
// query), in time proportional to the answer rather than to the number of arcs.
//
// Used by the cylindrical pose cache (cylindrical_segmenting.h): a mobile vertex can penetrate
// only at pose angles inside a few arcs, known once per body pair, so a pose query looks up the
// arcs that hold its angle instead of visiting every vertex.
//
// Structure: a hierarchy of uniform bins over (-pi, pi]. Level l has 2^(levels-1-l) bins of width
// 2 pi / 2^(levels-1-l); an arc is stored at the lowest level whose bin is at least as wide as the
// arc, in the (at most two) bins it overlaps, so an arc at level l is longer than half a bin of
// level l - 1 and a bin's arcs lie within three of its widths: a query reads one bin per level and
// at least about a quarter of what it reads is a hit. Arcs crossing +-pi are stored as two pieces;
// arcs of length >= 2 pi hold every angle.
#pragma once

#include <cstdint>
#include <vector>

namespace hipfai::contact {

struct AngularArc {
  double start_rad = 0.0;   // any finite angle
  double length_rad = 0.0;  // >= 0; the arc is [start, start + length], closed
  std::int32_t id = 0;      // reported for every query angle the arc contains
};

class AngularIntervalIndex {
 public:
  AngularIntervalIndex() = default;
  // Throws hipfai::Error on a non-finite start, a negative or non-finite length, or levels
  // outside 1..20.
  explicit AngularIntervalIndex(const std::vector<AngularArc>& arcs, int levels = 13);

  // Appends to `ids` the id of every arc that contains angle_rad (taken modulo 2 pi). An id
  // appears once per arc piece holding the angle: arcs that share an id may repeat it (callers
  // that need each id once sort and deduplicate). Non-finite angles contain nothing.
  void stab(double angle_rad, std::vector<std::int32_t>& ids) const;

  std::size_t num_arcs() const { return num_arcs_; }

 private:
  struct Entry {
    double lo = 0.0, hi = 0.0;  // within [-pi, pi]
    std::int32_t id = 0;
  };
  int levels_ = 0;
  std::size_t num_arcs_ = 0;
  std::vector<std::size_t> level_first_bin_;  // bins of level l start at this index of offsets_
  std::vector<std::size_t> offsets_;          // CSR over every level's bins (one extra at the end)
  std::vector<Entry> entries_;
  std::vector<std::int32_t> full_circle_;     // arcs of length >= 2 pi
};

}  // namespace hipfai::contact
