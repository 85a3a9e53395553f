// The arc stabbing index against the definition (an arc [s, s + L] holds x when x - s, taken in
// [0, 2 pi), is at most L), on random arcs of every length, arcs crossing +-pi, empty and
// full-circle arcs, and angles exactly on arc ends; bad input.
#include "contact/angular_interval_index.h"
#include "contact/arc_triangle.h"
#include "core/error.h"
#include "core/numbers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace hipfai::contact {
namespace {

using hipfai::kPi;

bool holds(const AngularArc& arc, double x) {
  if (arc.length_rad >= 2.0 * kPi) return true;
  double d = wrap_angle(x - arc.start_rad);
  if (d < 0.0) d += 2.0 * kPi;
  return d <= arc.length_rad;
}

std::vector<std::int32_t> stabbed(const AngularIntervalIndex& index, double x) {
  std::vector<std::int32_t> ids;
  index.stab(x, ids);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

std::vector<std::int32_t> brute_force(const std::vector<AngularArc>& arcs, double x) {
  std::vector<std::int32_t> ids;
  for (const AngularArc& arc : arcs) {
    if (holds(arc, x)) ids.push_back(arc.id);
  }
  return ids;
}

TEST(AngularIntervalIndex, EqualsTheDefinitionOnRandomArcs) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const int levels : {1, 4, 13}) {
    std::vector<AngularArc> arcs;
    for (std::int32_t id = 0; id < 3000; ++id) {
      // Lengths over nine decades, some zero, some beyond the circle; starts over three turns.
      const double kind = u(rng);
      const double length = kind < 0.05 ? 0.0 : kind > 0.97 ? 2.0 * kPi + u(rng) : 7.0 * std::pow(10.0, -8.0 * u(rng));
      arcs.push_back({6.0 * kPi * (u(rng) - 0.5), length, id});
    }
    const AngularIntervalIndex index(arcs, levels);
    EXPECT_EQ(index.num_arcs(), arcs.size());
    std::size_t hits = 0;
    for (int q = 0; q < 4000; ++q) {
      const double x = 4.0 * kPi * (u(rng) - 0.5);
      const std::vector<std::int32_t> want = brute_force(arcs, x);
      ASSERT_EQ(stabbed(index, x), want) << "levels " << levels << ", angle " << x;
      hits += want.size();
    }
    EXPECT_GT(hits, 100000u);  // the arcs really overlap the queries
  }
}

TEST(AngularIntervalIndex, ArcEndsAndTheSeamAreInside) {
  // Closed arcs: both ends belong to them, and an arc across +-pi holds pi and angles just
  // above -pi.
  const std::vector<AngularArc> arcs = {
      {0.25, 0.5, 1}, {kPi - 0.1, 0.3, 2}, {-kPi, 0.2, 3}, {1.0, 0.0, 4}, {-3.0, 10.0, 5}};
  const AngularIntervalIndex index(arcs);
  EXPECT_EQ(stabbed(index, 0.25), (std::vector<std::int32_t>{1, 5}));
  EXPECT_EQ(stabbed(index, 0.25 + 0.5), (std::vector<std::int32_t>{1, 5}));
  EXPECT_EQ(stabbed(index, std::nextafter(0.75, 1.0)), (std::vector<std::int32_t>{5}));
  EXPECT_EQ(stabbed(index, kPi), (std::vector<std::int32_t>{2, 3, 5}));
  EXPECT_EQ(stabbed(index, -kPi + 0.15), (std::vector<std::int32_t>{2, 3, 5}));
  EXPECT_EQ(stabbed(index, 1.0), (std::vector<std::int32_t>{4, 5}));
  EXPECT_EQ(stabbed(index, 0.5 + 2.0 * kPi), (std::vector<std::int32_t>{1, 5}));
  EXPECT_EQ(stabbed(index, std::nan("")), (std::vector<std::int32_t>{}));
}

TEST(AngularIntervalIndex, RefusesBadArcs) {
  EXPECT_THROW(AngularIntervalIndex({{0.0, -1.0, 0}}), Error);
  EXPECT_THROW(AngularIntervalIndex({{std::nan(""), 1.0, 0}}), Error);
  EXPECT_THROW(AngularIntervalIndex({{0.0, INFINITY, 0}}), Error);
  EXPECT_THROW(AngularIntervalIndex({}, 0), Error);
  EXPECT_THROW(AngularIntervalIndex({}, 21), Error);
  EXPECT_NO_THROW(AngularIntervalIndex({}, 20));
}

}  // namespace
}  // namespace hipfai::contact
