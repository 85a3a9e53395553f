#include "contact/radial_segmenting.h"

#include "contact/detail/ablation.h"
#include "contact/detail/radial_pose_state.h"
#include "contact/ray_triangle.h"
#include "core/error.h"
#include "core/parallel.h"

#include <algorithm>
#include <atomic>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

namespace hipfai::contact {

namespace {

// The adjacent crossing found so far for one vertex (see the crossing rule in the header).
struct Adjacent {
  bool found = false;
  double t = 0.0;
  int facing = 0;
  std::int32_t triangle = -1;
};

// Floating-point pre-filter of ray_triangle_crossing for the common case: most candidates of a
// cell miss the ray, and two of the edge functions e = d . (p x q) then have opposite signs. Each
// is evaluated here in plain floating point; its error is below ~6 x 3 ulp x the bound
// m_d m_p m_q of its six products (< 4e-15 of it), so a value beyond 1e-13 x that bound has the
// exact sign, and two such values of opposite signs prove the miss the exact test would find.
// Anything else (a hit, or a sign too close to call) goes to the exact, watertight test, so the
// answers are those of ray_triangle_crossing bit for bit; only the time changes.
// The same bound proves a clear hit: three values beyond it with one sign are the exact signs, so
// ray_triangle_crossing would find facing = that sign and only its tail remains
// (line_crossing_with_facing, same t bit for bit). Returns 0 for a clear miss, +-1 for a clear
// hit with that facing, 2 when the exact test must decide.
// The verdict from the three edge values and their bounds.
int filter_verdict(double e_ab, double e_bc, double e_ca, double bound_ab, double bound_bc, double bound_ca) {
  const int pos = (e_ab > bound_ab) + (e_bc > bound_bc) + (e_ca > bound_ca);
  const int neg = (e_ab < -bound_ab) + (e_bc < -bound_bc) + (e_ca < -bound_ca);
  if (pos > 0 && neg > 0) return 0;
  if (pos == 3) return 1;
  if (neg == 3) return -1;
  return 2;
}

int filter_crossing(const Vec3& d, double m_d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double m_a = max_abs_component(a), m_b = max_abs_component(b), m_c = max_abs_component(c);
  const double tolerance = 1e-13 * m_d;
  return filter_verdict(d.dot(a.cross(b)), d.dot(b.cross(c)), d.dot(c.cross(a)), tolerance * m_a * m_b,
                        tolerance * m_b * m_c, tolerance * m_c * m_a);
}

// The exact crossing of the ray along `direction` (|direction|_inf = m_d) with fixed triangle t,
// after the float pre-filter (hit, t and facing as ray_triangle_crossing; weights not needed).
RayCrossing crossing_of(const geometry::TriMesh& fixed, const Vec3& centre, const Vec3& direction,
                        double m_d, std::int32_t t) {
  const auto& tri = fixed.triangles[static_cast<std::size_t>(t)];
  const Vec3 a = fixed.vertices[static_cast<std::size_t>(tri[0])] - centre;
  const Vec3 b = fixed.vertices[static_cast<std::size_t>(tri[1])] - centre;
  const Vec3 c = fixed.vertices[static_cast<std::size_t>(tri[2])] - centre;
  const int verdict = filter_crossing(direction, m_d, a, b, c);
  if (verdict == 0) return {};
  if (verdict == 2) return ray_triangle_crossing(direction, a, b, c);
  return line_crossing_with_facing(direction, a, b, c, verdict);
}

// crossing_of with the triangle's pre-computed values (RadialSpans::TrianglePlanes, valid for the
// fixed coordinates the spans were computed for): the same filter on the same edge-function values
// (d . (a x b) with a x b computed once), the same tail of line_crossing_with_facing on the same
// N and det, and the exact test on the vertices when the filter cannot decide. Same answers bit
// for bit.
// `clear_hit` is set when the ray crosses with every edge function beyond its bound: it then runs
// strictly inside the triangle's cone (RadialSpans::separated).
RayCrossing crossing_with_planes(const geometry::TriMesh& fixed, const Vec3& centre, const Vec3& direction,
                                 double m_d, const RadialSpans::TrianglePlanes& planes, std::int32_t t, bool& clear_hit) {
  clear_hit = false;
  const int verdict = filter_verdict(direction.dot(planes.edge_ab), direction.dot(planes.edge_bc),
                                     direction.dot(planes.edge_ca), planes.bound_ab * m_d, planes.bound_bc * m_d,
                                     planes.bound_ca * m_d);
  if (verdict == 0) return {};
  if (verdict == 2) return crossing_of(fixed, centre, direction, m_d, t);
  const RayCrossing crossing = plane_crossing_with_facing(direction, planes.area_normal, planes.det, verdict);
  clear_hit = crossing.hit;
  return crossing;
}

// Offers one candidate triangle's crossing to the running choice.
void offer(const RayCrossing& crossing, RadialConfiguration configuration, std::int32_t t, Adjacent& adjacent) {
  if (!crossing.hit) return;
  if (configuration == RadialConfiguration::kMobileInsideFixed) {
    if (crossing.t > 1.0) return;
    const bool better = !adjacent.found || crossing.t > adjacent.t ||
                        (crossing.t == adjacent.t && t < adjacent.triangle);
    if (!better) return;
  } else {
    if (crossing.t < 1.0) return;
    const bool better = !adjacent.found || crossing.t < adjacent.t ||
                        (crossing.t == adjacent.t && t < adjacent.triangle);
    if (!better) return;
  }
  adjacent = {true, crossing.t, crossing.facing, t};
}

struct Crossing {
  double t;
  int facing;
  std::int32_t triangle;
};

// The kUnion rule over every crossing of the ray (gathered from the vertex's cells). Returns
// false when v is not inside the union.
bool resolve_union(const geometry::TriMesh& fixed, std::vector<Crossing>& crossings, bool inside_fixed,
                   double& t_out, std::int32_t& triangle_out) {
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& a, const Crossing& b) {
    return a.t != b.t ? a.t < b.t : a.triangle < b.triangle;
  });
  // The same triangle offered by several cells, and one hit split over the triangles around a
  // shared edge or vertex, count once.
  std::vector<Crossing> unique;
  for (const Crossing& c : crossings) {
    bool duplicate = false;
    for (auto it = unique.rbegin(); it != unique.rend() && it->t >= c.t * (1.0 - 1e-12); ++it) {
      if (it->triangle == c.triangle ||
          (it->facing == c.facing && geometry::triangles_share_a_vertex(fixed, it->triangle, c.triangle))) {
        duplicate = true;
        break;
      }
    }
    if (!duplicate) unique.push_back(c);
  }
  int winding = 0;  // solids containing v
  for (const Crossing& c : unique) {
    if (c.t == 1.0) return false;  // on the surface: touching, not penetrating
    if (c.t > 1.0) winding += c.facing;
  }
  if (winding <= 0) return false;
  // Walk away from v (towards O for kMobileInsideFixed, away from O otherwise) over the sorted
  // crossings; crossings at the same distance (the shared face of two touching solids: one exits,
  // the other enters) are passed together before the winding number is looked at.
  const int step = inside_fixed ? 1 : -1;  // winding change per unit facing when passing a crossing
  auto walk = [&](auto first, auto last) {
    for (auto it = first; it != last;) {
      if ((it->t - 1.0) * step > 0.0) {  // on v's other side
        ++it;
        continue;
      }
      auto group_end = it;
      std::int32_t lowest = it->triangle;
      bool facing_found = false;
      while (group_end != last && std::abs(group_end->t - it->t) <= 1e-12 * it->t) {
        winding += step * group_end->facing;
        if (group_end->facing == -step) {  // the boundary crossing faces back towards v
          lowest = facing_found ? std::min(lowest, group_end->triangle) : group_end->triangle;
          facing_found = true;
        }
        ++group_end;
      }
      if (winding == 0) {
        t_out = it->t;
        triangle_out = lowest;
        return true;
      }
      it = group_end;
    }
    return false;
  };
  if (inside_fixed) {
    if (walk(unique.rbegin(), unique.rend())) return true;
    t_out = 0.0;  // the union reaches O
    triangle_out = -1;
    return true;
  }
  if (walk(unique.begin(), unique.end())) return true;
  return false;  // cannot happen for closed solids; an open surface leaves v unresolved
}

// Which side of a radial span the crossing rule needs (radial_spans.h).
SpanCull span_side(const RadialQueryOptions& options) {
  const bool inside_fixed = options.configuration == RadialConfiguration::kMobileInsideFixed;
  // kAdjacent and kBeyond need a crossing on one side of v only; kUnion needs those beyond v.
  return options.rule != RadialCrossingRule::kUnion && inside_fixed ? SpanCull::kBelowLo : SpanCull::kAboveHi;
}

// What a query needs for every vertex, fixed for one query.
struct VertexQuery {
  VertexQuery(const RadialTable& table_in, const geometry::TriMesh& fixed_in, const RadialQueryOptions& options_in,
              bool use_spans_in)
      : table(table_in), fixed(fixed_in), options(options_in), spans(table_in.spans), use_spans(use_spans_in),
        inside_fixed(options_in.configuration == RadialConfiguration::kMobileInsideFixed),
        union_rule(options_in.rule == RadialCrossingRule::kUnion),
        beyond_rule(options_in.rule == RadialCrossingRule::kBeyond), side(span_side(options_in)),
        // Per-triangle skipping only where the rule looks at crossings on one side of v.
        skip_triangles(use_spans_in && options_in.rule != RadialCrossingRule::kUnion),
        cap_radius(options_in.neighbour_cells * table_in.grid.nominal_cell_angle_rad()),
        // The whole mesh's span and the cap, only where they can cull (a span from 0, or to
        // infinity on the side that counts, and no cap, never do).
        global_culls(use_spans_in && (side == SpanCull::kBelowLo ? spans.lo > 0.0 : spans.hi < RadialSpans::kInfinity)),
        cap_culls(use_spans_in && spans.cap_cos > -1.0) {}

  const RadialTable& table;
  const geometry::TriMesh& fixed;
  const RadialQueryOptions& options;
  const RadialSpans& spans;
  bool use_spans, inside_fixed, union_rule, beyond_rule;
  SpanCull side;
  bool skip_triangles;
  double cap_radius;
  bool global_culls, cap_culls;

  struct Scratch {
    std::vector<int> cap_cells;
    std::vector<Crossing> crossings;
  };

  // A vertex the culls that need no triangle keep, with what decide() needs.
  struct Kept {
    std::int32_t index = -1;
    int id = -1;  // packed cell (spans without neighbour cells), else -1
    int part = -1;  // the direction's part of the cell for its hint (cube mapping), else -1
    double r = 0.0;
    Vec3 direction = Vec3::Zero();
  };

  // The culls that need no triangle (inline, as most vertices end here): false when they decide
  // that the vertex does not penetrate, else `kept` is filled for decide().
  bool keep(std::int32_t index, const Vec3& position, Kept& kept) const {
    kept.index = index;
    kept.direction = position - table.centre;
    if (kept.direction.isZero(0.0)) return false;  // v == O: no ray
    kept.id = -1;
    kept.part = -1;
    kept.r = 0.0;
    if (!use_spans) return true;
    kept.r = kept.direction.norm();
    if (global_culls && outside_span(side, kept.r, spans.lo, spans.hi)) return false;
    if (cap_culls && outside_cap(spans, kept.direction, kept.r)) return false;
    if (options.neighbour_cells == 0) {
      kept.id = spans.cube.dimension > 0 ? spans.cube.cell(kept.direction, kept.part)
                                         : cell_of_direction(table.grid, kept.direction);
      const auto id = static_cast<std::size_t>(kept.id);
      if (side == SpanCull::kBelowLo ? kept.r < spans.cell_lo[id] * (1.0 - 1e-12) : kept.r > spans.cell_hi[id] * (1.0 + 1e-12)) return false;
    }
    return true;
  }

  // The slot of the entry a kept vertex tests first (RadialSpans, HINTS), or kNoHint.
  static int hinted_slot(const Kept& kept, const RadialSpans::Cell& cell) {
    return kept.part >= 0 ? cell.hint[static_cast<std::size_t>(kept.part)] : RadialSpans::kNoHint;
  }

  // Starts loading what decide() reads for a kept vertex, in the order of its dependent reads:
  // stage 0 the cell record, stage 1 its hinted (else first) entry (the record loaded by then),
  // stage 2 the triangle values of that entry, or of up to four first entries without a hint.
  void prefetch(const Kept& kept, int stage) const {
    if (kept.id < 0) return;
    const RadialSpans::Cell& cell = spans.cells[static_cast<std::size_t>(kept.id)];
    const int hint = hinted_slot(kept, cell);
    if (stage == 0) {
      __builtin_prefetch(&cell);
    } else if (stage == 1) {
      if (cell.wedge_end < cell.end) __builtin_prefetch(&spans.entries[cell.wedge_end]);
      if (hint != RadialSpans::kNoHint) __builtin_prefetch(&spans.entries[cell.wedge_end + static_cast<std::uint32_t>(hint)]);
    } else {
      // The triangle values (two cache lines each) of the entries the vertex will test first.
      auto load = [&](const RadialSpans::Entry& entry) {
        const auto* planes = reinterpret_cast<const char*>(&spans.planes[static_cast<std::size_t>(entry.triangle)]);
        __builtin_prefetch(planes);
        __builtin_prefetch(planes + 64);
      };
      if (hint != RadialSpans::kNoHint) {
        load(spans.entries[cell.wedge_end + static_cast<std::uint32_t>(hint)]);
        return;
      }
      for (std::uint32_t k = cell.wedge_end; k < cell.end && k < cell.wedge_end + 4; ++k) {
        const RadialSpans::Entry& entry = spans.entries[k];
        if (side == SpanCull::kBelowLo && outside_span(side, kept.r, entry.lo, entry.hi)) break;
        load(entry);
      }
    }
  }

  // The crossing rule for the mobile vertex `index` at `position`; false when it does not penetrate.
  bool penetrates(std::int32_t index, const Vec3& position, Scratch& scratch, PenetrationPair& out) const {
    Kept kept;
    return keep(index, position, kept) && decide(kept, scratch, out);
  }

  // The triangle tests for a vertex the culls kept.
  [[gnu::noinline]] bool decide(const Kept& kept, Scratch& scratch, PenetrationPair& out) const {
    const Vec3& direction = kept.direction;
    const double r = kept.r;
    const int id = kept.id;
    Adjacent adjacent;
    scratch.crossings.clear();
    const double m_d = max_abs_component(direction);
    bool clear_hit = false;
    auto offer_triangle = [&](std::int32_t t) {
      const RayCrossing crossing =
          use_spans ? crossing_with_planes(fixed, table.centre, direction, m_d, spans.planes[static_cast<std::size_t>(t)], t,
                                           clear_hit)
                    : crossing_of(fixed, table.centre, direction, m_d, t);
      if (union_rule || beyond_rule) {
        if (crossing.hit) scratch.crossings.push_back({crossing.t, crossing.facing, t});
      } else {
        offer(crossing, options.configuration, t, adjacent);
      }
    };
    auto visit = [&](const std::vector<std::int32_t>& candidates) {
      for (const std::int32_t t : candidates) {
        if (skip_triangles && outside_span(side, r, spans.triangle_lo[static_cast<std::size_t>(t)],
                                           spans.triangle_hi[static_cast<std::size_t>(t)])) {
          continue;
        }
        offer_triangle(t);
      }
    };
    if (options.neighbour_cells > 0) {
      scratch.cap_cells.clear();
      cells_of_cap(table.grid, direction, cap_radius, scratch.cap_cells);
      for (const int cap_cell : scratch.cap_cells) visit(table.cell(cap_cell));
    } else if (use_spans) {
      // The packed cells: one record per cell, entries contiguous with their spans inline.
      const RadialSpans::Cell& cell = spans.cells[static_cast<std::size_t>(id)];
      // Triangles whose cones are separated from one the ray clearly crosses are misses: skipped.
      // Entries come in ascending lo: on the kBelowLo side the first one beyond r ends the cell.
      std::uint32_t missed = 0;  // bit s: entry wedge_end + s is known to be missed
      const bool stop_at_lo = skip_triangles && side == SpanCull::kBelowLo;
      std::uint32_t first = cell.begin;
      if (cell.wedge_end > cell.begin) {
        // The leading triangles without a span are thin cones around one plane through O: a ray
        // clear of their wedge misses them all (radial_spans.h, FLAT WEDGES).
        const RadialSpans::FlatWedge& wedge = spans.wedges[cell.wedge];
        if (std::abs(direction.dot(wedge.normal)) > wedge.sin_bound * r) first = cell.wedge_end;
      }
      auto skipped = [&](const RadialSpans::Entry& entry) {
        return skip_triangles && outside_span(side, r, entry.lo, entry.hi);
      };
      // The hinted entry first (a clear hit there usually leaves nothing to test), then the others.
      const int hint = hinted_slot(kept, cell);
      if (hint != RadialSpans::kNoHint) {
        const RadialSpans::Entry& entry = spans.entries[cell.wedge_end + static_cast<std::uint32_t>(hint)];
        if (!skipped(entry)) {
          offer_triangle(entry.triangle);
          if (clear_hit) missed |= entry.separated;
          missed |= std::uint32_t{1} << hint;
        }
      }
      // Returns false when the entry ends the cell (the first beyond r on the kBelowLo side);
      // clear_hit tells whether it was tested and clearly crossed.
      auto consider = [&](const RadialSpans::Entry& entry) {
        clear_hit = false;
        if (stop_at_lo) {
          if (r < entry.lo * (1.0 - 1e-12)) return false;  // outside_span for this and every later entry
        } else if (skipped(entry)) {
          return true;
        }
        offer_triangle(entry.triangle);
        return true;
      };
      bool open = true;
      for (std::uint32_t k = first; k < cell.wedge_end && open; ++k) open = consider(spans.entries[k]);
      // The first 32 entries past the wedge by their bits (skipping those known to be missed), then
      // any beyond in order.
      const std::uint32_t past_wedge = cell.end - cell.wedge_end;
      std::uint32_t todo = open ? (past_wedge >= 32 ? ~std::uint32_t{0} : (std::uint32_t{1} << past_wedge) - 1) & ~missed : 0;
      while (todo != 0) {
        const RadialSpans::Entry& entry = spans.entries[cell.wedge_end + static_cast<std::uint32_t>(std::countr_zero(todo))];
        todo &= todo - 1;
        if (!consider(entry)) {
          open = false;
          break;
        }
        if (clear_hit) todo &= ~entry.separated;
      }
      for (std::uint32_t k = cell.wedge_end + 32; k < cell.end && open; ++k) open = consider(spans.entries[k]);
    } else {
      visit(table.cell(cell_of_direction(table.grid, direction)));
    }
    visit(table.always_candidates);
    return penetration_of(kept, scratch, adjacent, out);
  }

  // The pair the crossings offered give the vertex, by the configuration's rule; false when it
  // does not penetrate.
  bool penetration_of(const Kept& kept, Scratch& scratch, const Adjacent& adjacent, PenetrationPair& out) const {
    const std::int32_t index = kept.index;
    const Vec3& direction = kept.direction;
    if (union_rule) {
      double t_union = 0.0;
      std::int32_t triangle = -1;
      if (!resolve_union(fixed, scratch.crossings, inside_fixed, t_union, triangle)) return false;
      const double depth = (inside_fixed ? 1.0 - t_union : t_union - 1.0) * direction.norm();
      out = PenetrationPair{index, triangle, depth};
      return true;
    }
    if (beyond_rule) {
      // The crossing farthest from v on its side (ties: the lowest triangle index).
      const Crossing* chosen = nullptr;
      for (const Crossing& c : scratch.crossings) {
        if (inside_fixed ? !(c.t > 0.0 && c.t < 1.0) : !(c.t > 1.0)) continue;
        if (chosen == nullptr || (inside_fixed ? c.t < chosen->t : c.t > chosen->t) ||
            (c.t == chosen->t && c.triangle < chosen->triangle)) {
          chosen = &c;
        }
      }
      if (chosen == nullptr) return false;
      const double depth = (inside_fixed ? 1.0 - chosen->t : chosen->t - 1.0) * direction.norm();
      out = PenetrationPair{index, chosen->triangle, depth};
      return true;
    }
    if (!adjacent.found || adjacent.t == 1.0) return false;
    if (adjacent.facing != (inside_fixed ? -1 : 1)) return false;
    const double depth = (inside_fixed ? 1.0 - adjacent.t : adjacent.t - 1.0) * direction.norm();
    out = PenetrationPair{index, adjacent.triangle, depth};
    return true;
  }
};

std::string check_inputs(const RadialTable& table, const geometry::TriMesh& fixed,
                         const geometry::TriMesh& mobile, const RadialQueryOptions& options) {
  if (fixed.num_triangles() != table.num_triangles) {
    return "radial segmenting: fixed mesh has " + std::to_string(fixed.num_triangles()) +
           " triangles, the table was built for " + std::to_string(table.num_triangles);
  }
  if (options.num_threads < 1 || options.num_threads > 2) {
    return "radial segmenting: num_threads must be 1 or 2, got " +
           std::to_string(options.num_threads);
  }
  if (options.neighbour_cells < 0) return "radial segmenting: neighbour_cells must be >= 0";
  for (const auto& p : mobile.vertices) {
    if (!p.allFinite()) return "radial segmenting: mobile mesh has a non-finite vertex";
  }
  for (const auto& p : fixed.vertices) {
    if (!p.allFinite()) return "radial segmenting: fixed mesh has a non-finite vertex";
  }
  const auto num_fixed = static_cast<std::int32_t>(fixed.num_vertices());
  for (const auto& tri : fixed.triangles) {
    for (const auto index : tri) {
      if (index < 0 || index >= num_fixed) return "radial segmenting: fixed triangle index out of range";
    }
  }
  return {};
}

// Runs fill(block, scratch, hits) over blocks [0, blocks) taken dynamically by the workers (culled
// vertices cost almost nothing, so the work is uneven); each block appends its few hits to its own
// list, and the lists are joined in block order. No per-vertex output array is allocated (a query
// of 262 k vertices would otherwise zero 6 MiB per pose).
template <typename Fill>
std::vector<PenetrationPair> gather_blocks(std::size_t blocks, int threads, const Fill& fill) {
  std::vector<std::vector<PenetrationPair>> per_block(blocks);
  parallel_blocks(blocks, threads, 1, [&](std::size_t first_block, std::size_t last_block) {
    VertexQuery::Scratch scratch;
    for (std::size_t b = first_block; b < last_block; ++b) fill(b, scratch, per_block[b]);
  });
  std::size_t total = 0;
  for (const auto& hits : per_block) total += hits.size();
  std::vector<PenetrationPair> pairs;
  pairs.reserve(total);
  for (const auto& hits : per_block) pairs.insert(pairs.end(), hits.begin(), hits.end());
  return pairs;
}

// Stable LSD radix sort of pairs by mobile_vertex (all in [0, num_vertices)): 11-bit digits, as
// many passes as the indices need (two up to 4 M vertices); linear in the number of pairs.
void sort_by_vertex(std::vector<PenetrationPair>& pairs, std::size_t num_vertices) {
  constexpr int kBits = 11;
  constexpr std::size_t kRadix = std::size_t{1} << kBits;
  std::vector<PenetrationPair> buffer(pairs.size());
  for (int shift = 0; shift < 32 && (num_vertices - 1) >> shift != 0; shift += kBits) {
    std::array<std::size_t, kRadix + 1> start{};
    for (const PenetrationPair& p : pairs) ++start[((static_cast<std::uint32_t>(p.mobile_vertex) >> shift) & (kRadix - 1)) + 1];
    for (std::size_t d = 1; d <= kRadix; ++d) start[d] += start[d - 1];
    for (const PenetrationPair& p : pairs) buffer[start[(static_cast<std::uint32_t>(p.mobile_vertex) >> shift) & (kRadix - 1)]++] = p;
    pairs.swap(buffer);
  }
}

}  // namespace

const char* to_string(RadialConfiguration configuration) {
  return configuration == RadialConfiguration::kMobileInsideFixed ? "mobile_inside_fixed"
                                                                  : "fixed_inside_mobile";
}

const char* to_string(RadialCrossingRule rule) {
  switch (rule) {
    case RadialCrossingRule::kAdjacent: return "adjacent";
    case RadialCrossingRule::kUnion: return "union";
    case RadialCrossingRule::kBeyond: return "beyond";
  }
  return "unknown";
}

RadialConfiguration swapped(RadialConfiguration configuration) {
  return configuration == RadialConfiguration::kMobileInsideFixed
             ? RadialConfiguration::kFixedInsideMobile
             : RadialConfiguration::kMobileInsideFixed;
}

PenetrationResult radial_segmenting(const RadialTable& table, const geometry::TriMesh& fixed,
                                    const geometry::TriMesh& mobile,
                                    const RadialQueryOptions& options) {
  return detail::radial_segmenting(table, fixed, mobile, options, {});
}

PenetrationResult detail::radial_segmenting(const RadialTable& table, const geometry::TriMesh& fixed,
                                            const geometry::TriMesh& mobile, const RadialQueryOptions& options,
                                            const RadialAblation& ablation) {
  PenetrationResult result;
  result.message = check_inputs(table, fixed, mobile, options);
  if (!result.message.empty()) {
    result.status = QueryStatus::kInvalidInput;
    return result;
  }
  const bool use_spans = ablation.cull && radial_spans_valid(table.spans, fixed);
  const VertexQuery query(table, fixed, options, use_spans);
  constexpr std::size_t kBlock = 2048;
  const std::size_t count = mobile.num_vertices();
  result.pairs = gather_blocks((count + kBlock - 1) / kBlock, options.num_threads,
                               [&](std::size_t b, VertexQuery::Scratch& scratch, std::vector<PenetrationPair>& hits) {
                                 PenetrationPair pair;
                                 for (std::size_t v = b * kBlock, end = std::min(count, v + kBlock); v < end; ++v) {
                                   if (query.penetrates(static_cast<std::int32_t>(v), mobile.vertices[v], scratch, pair)) {
                                     hits.push_back(pair);
                                   }
                                 }
                               });
  return result;  // gathered in vertex order: already sorted
}

PenetrationResult radial_swap_roles(const geometry::TriMesh& fixed,
                                    const geometry::TriMesh& mobile, const Vec3& centre,
                                    const RadialTableOptions& table_options,
                                    const RadialQueryOptions& options) {
  const RadialTable table = build_radial_table(mobile, centre, table_options);
  RadialQueryOptions swapped_options = options;
  swapped_options.configuration = swapped(options.configuration);
  return radial_segmenting(table, mobile, fixed, swapped_options);
}

RadialPoseQuery::RadialPoseQuery(const RadialTable& table, const geometry::TriMesh& fixed,
                                 const geometry::TriMesh& mobile, const RadialQueryOptions& options)
    : state_(std::make_shared<const detail::RadialPoseState>(table, fixed, mobile, options)) {}

QueryStatus RadialPoseQuery::status() const { return state_->status(); }

const std::string& RadialPoseQuery::message() const { return state_->message(); }

std::size_t RadialPoseQuery::num_kept_vertices() const { return state_->num_kept_vertices(); }

PenetrationResult RadialPoseQuery::query(const Eigen::Isometry3d& pose) const { return state_->query(pose); }

PenetrationResult RadialPoseQuery::query_rotation(const Eigen::Matrix3d& rotation) const {
  return state_->query_rotation(rotation);
}

std::size_t RadialPoseQuery::num_tested_vertices(const Eigen::Isometry3d& pose) const {
  return state_->num_tested_vertices(pose);
}

}  // namespace hipfai::contact

namespace hipfai::contact::detail {

RadialPoseState::RadialPoseState(const RadialTable& table, const geometry::TriMesh& fixed,
                                 const geometry::TriMesh& mobile, const RadialQueryOptions& options)
    : table_(&table), fixed_(&fixed), options_(options) {
  message_ = check_inputs(table, fixed, mobile, options);
  if (!message_.empty()) return;
  status_ = QueryStatus::kOk;
  use_spans_ = radial_spans_valid(table.spans, fixed);
  // Buckets: the rest direction's cell on a coarse cube map (about kBucketVertices vertices per
  // cell over the sphere) and the rest distance in shells of kShellMm. Vertices are stored bucket by
  // bucket, coarse cell by coarse cell, and by the table's own cell inside a bucket: a rotation keeps
  // neighbouring directions together, so consecutive vertices read the same or adjacent cell
  // records and triangles (mesh order, after midpoint subdivision, jumps around).
  const std::size_t count = mobile.num_vertices();
  coarse_grid_ = make_radial_grid(RadialMapping::kCube,
                                  std::max<std::int64_t>(6, static_cast<std::int64_t>(count / kBucketVertices)));
  coarse_locator_ = make_cube_locator(coarse_grid_.dimension);
  const RadialGrid& coarse = coarse_grid_;
  struct Key {
    int coarse_cell;
    std::int64_t shell;
    int cell;
    std::int32_t vertex;
  };
  std::vector<Key> order(count);
  std::vector<double> distance(count);
  for (std::size_t v = 0; v < count; ++v) {
    const Vec3 direction = mobile.vertices[v] - table.centre;
    distance[v] = direction.norm();
    const bool at_centre = direction.isZero(0.0);
    order[v] = {at_centre ? -1 : cell_of_direction(coarse, direction),
                static_cast<std::int64_t>(std::floor(distance[v] / kShellMm)),
                at_centre ? -1 : cell_of_direction(table.grid, direction), static_cast<std::int32_t>(v)};
  }
  std::sort(order.begin(), order.end(), [](const Key& a, const Key& b) {
    if (a.coarse_cell != b.coarse_cell) return a.coarse_cell < b.coarse_cell;
    if (a.shell != b.shell) return a.shell < b.shell;
    return a.cell != b.cell ? a.cell < b.cell : a.vertex < b.vertex;
  });
  sorted_position_.reserve(count);
  sorted_index_.reserve(count);
  for (std::size_t k = 0; k < count;) {
    std::size_t end = k;
    while (end < count && order[end].coarse_cell == order[k].coarse_cell && order[end].shell == order[k].shell) ++end;
    Bucket bucket;
    bucket.begin = static_cast<std::uint32_t>(k);
    bucket.end = static_cast<std::uint32_t>(end);
    Vec3 sum = Vec3::Zero();
    bool has_centre = false;
    for (std::size_t m = k; m < end; ++m) {
      const auto v = static_cast<std::size_t>(order[m].vertex);
      sorted_position_.push_back(mobile.vertices[v]);
      sorted_index_.push_back(order[m].vertex);
      bucket.r_lo = std::min(bucket.r_lo, distance[v]);
      bucket.r_hi = std::max(bucket.r_hi, distance[v]);
      if (!(distance[v] > 0.0)) has_centre = true;
      else sum += (mobile.vertices[v] - table.centre) / distance[v];
    }
    // The members' cone of directions: around their mean direction, out to the widest of them
    // (plus 1e-9 rad for the rounding of these angles); a bucket holding O has none.
    if (!has_centre && sum.norm() > 0.0) {
      bucket.axis = sum.normalized();
      double widest = 0.0;
      for (std::size_t m = k; m < end; ++m) {
        const auto v = static_cast<std::size_t>(order[m].vertex);
        const Vec3 unit = (mobile.vertices[v] - table.centre) / distance[v];
        widest = std::max(widest, std::atan2(unit.cross(bucket.axis).norm(), unit.dot(bucket.axis)));
      }
      bucket.half_angle_rad = widest + 1e-9;
      bucket.cos_half_angle = std::cos(bucket.half_angle_rad);
      bucket.sin_half_angle = std::sin(bucket.half_angle_rad);
    }
    buckets_.push_back(bucket);
    k = end;
  }
  for (const Bucket& bucket : buckets_) largest_distance_ = std::max(largest_distance_, bucket.r_hi);
  if (use_spans_) build_distance_map();
  // Kept about O (a rotation without translation): the buckets whose rest distances the spans allow.
  for (const Bucket& bucket : buckets_) {
    if (!distance_culled(bucket, 0.0, 0.0)) num_kept_ += bucket.end - bucket.begin;
  }
}

// A fixed triangle whose cone is too wide to be filed under one coarse cell.
struct WideTriangle {
  Vec3 mean;
  double rho, lo, hi;
};

// The fixed triangles sorted for the distance map, by the cap of radius rho_t around their mean
// vertex direction that holds their cone (caps under 90 deg are convex).
struct FiledTriangles {
  // Per coarse cell, of the triangles with small caps (rho_t <= rho_limit) whose mean direction
  // is in the cell: the least lo and largest hi of their spans, and those without a span.
  std::vector<double> own_lo, own_hi;
  std::vector<std::vector<std::int32_t>> own_flat;
  double rho_max = 0.0;  // the largest of those caps
  std::vector<WideTriangle> wide;  // caps up to 1 rad: spread to every cell they reach
  // Of the triangles that count everywhere (a vertex at O, caps of 1 rad or more, the
  // always-checked ones): the least lo and largest hi.
  double global_lo = RadialSpans::kInfinity, global_hi = -RadialSpans::kInfinity;
};

namespace {

// Files the triangles of `fixed` (spans from `table`) under the coarse cells of `grid`: small caps
// under their mean direction's cell, wider ones to spread, the rest everywhere.
FiledTriangles file_triangles(const RadialTable& table, const geometry::TriMesh& fixed, const RadialGrid& grid) {
  const RadialSpans& spans = table.spans;
  const double rho_limit = 0.5 * grid.nominal_cell_angle_rad();
  FiledTriangles filed;
  filed.own_lo.assign(static_cast<std::size_t>(grid.num_cells()), RadialSpans::kInfinity);
  filed.own_hi.assign(filed.own_lo.size(), -RadialSpans::kInfinity);
  filed.own_flat.resize(filed.own_lo.size());
  for (std::size_t t = 0; t < fixed.num_triangles(); ++t) {
    const double lo = spans.triangle_lo[t], hi = spans.triangle_hi[t];
    if (!(lo <= hi)) continue;  // zero area: never crossed
    std::array<Vec3, 3> unit;
    bool at_centre = false;
    for (std::size_t k = 0; k < 3; ++k) {
      const Vec3 d = fixed.vertices[static_cast<std::size_t>(fixed.triangles[t][k])] - table.centre;
      const double length = d.norm();
      at_centre = at_centre || !(length > 0.0);
      unit[k] = at_centre ? Vec3::Zero() : Vec3(d / length);
    }
    const Vec3 sum = unit[0] + unit[1] + unit[2];
    if (!at_centre && sum.norm() > 0.0) {
      const Vec3 mean = sum.normalized();
      double rho = 0.0;
      for (const Vec3& u : unit) rho = std::max(rho, std::atan2(u.cross(mean).norm(), u.dot(mean)));
      rho += 1e-9;
      if (rho <= rho_limit) {
        const auto g = static_cast<std::size_t>(cell_of_direction(grid, mean));
        filed.rho_max = std::max(filed.rho_max, rho);
        if (lo == 0.0) {  // no span: kept for the cell's flat wedge
          filed.own_flat[g].push_back(static_cast<std::int32_t>(t));
          continue;
        }
        filed.own_lo[g] = std::min(filed.own_lo[g], lo);
        filed.own_hi[g] = std::max(filed.own_hi[g], hi);
        continue;
      }
      if (rho < 1.0) {
        filed.wide.push_back({mean, rho, lo, hi});
        continue;
      }
    }
    filed.global_lo = std::min(filed.global_lo, lo);
    filed.global_hi = std::max(filed.global_hi, hi);
  }
  for (const std::int32_t t : table.always_candidates) {
    filed.global_lo = std::min(filed.global_lo, spans.triangle_lo[static_cast<std::size_t>(t)]);
    filed.global_hi = std::max(filed.global_hi, spans.triangle_hi[static_cast<std::size_t>(t)]);
  }
  return filed;
}

// The angle from the centre direction of cube-map cell g to its farthest corner (cells are convex
// spherical quadrilaterals: the farthest point is a corner).
double farthest_corner_angle(const RadialGrid& grid, const RadialSpans::CubeLocator& locator, int g,
                             const Vec3& centre) {
  const int n = grid.dimension;
  const int i = g % n, j = (g / n) % n, face = g / (n * n), k = face / 2;
  double corner_angle = 0.0;
  for (const int ci : {i, i + 1}) {
    for (const int cj : {j, j + 1}) {
      Vec3 corner;  // the cube map's borders are the locator's
      corner[k] = face % 2 == 0 ? 1.0 : -1.0;
      corner[(k + 1) % 3] = locator.border[static_cast<std::size_t>(ci)];
      corner[(k + 2) % 3] = locator.border[static_cast<std::size_t>(cj)];
      corner.normalize();
      corner_angle = std::max(corner_angle, std::atan2(corner.cross(centre).norm(), corner.dot(centre)));
    }
  }
  return corner_angle;
}

}  // namespace

void RadialPoseState::build_distance_map() {
  const RadialGrid& grid = coarse_grid_;
  // The dilation: the widest bucket cone plus half a coarse cell for the translation of a pose.
  double widest = 0.0;
  for (const Bucket& bucket : buckets_) {
    if (bucket.half_angle_rad < 4.0) widest = std::max(widest, bucket.half_angle_rad);
  }
  map_dilation_rad_ = widest + 0.5 * grid.nominal_cell_angle_rad();
  // Triangles with small caps are filed under the coarse cell of their mean direction and spread
  // below; wider ones go straight to every cell their cap dilated reaches; those with a vertex at
  // O and the always-checked ones count everywhere.
  const FiledTriangles filed = file_triangles(*table_, *fixed_, grid);
  map_lo_.assign(filed.own_lo.size(), filed.global_lo);
  map_hi_.assign(filed.own_hi.size(), filed.global_hi);
  map_wedge_.assign(filed.own_lo.size(), MapWedge{});
  for (int g = 0; g < grid.num_cells(); ++g) fill_map_cell(g, filed);
  std::vector<int> near;
  for (const WideTriangle& triangle : filed.wide) {
    near.clear();
    cells_of_cap(grid, triangle.mean, triangle.rho + map_dilation_rad_ + 1e-6, near);
    for (const int g : near) {
      map_lo_[static_cast<std::size_t>(g)] = std::min(map_lo_[static_cast<std::size_t>(g)], triangle.lo);
      map_hi_[static_cast<std::size_t>(g)] = std::max(map_hi_[static_cast<std::size_t>(g)], triangle.hi);
    }
  }
}

// A triangle whose cone reaches within the dilation of cell g has its mean direction within
// rho_max + dilation of g, i.e. within the cap around g's centre of radius (g's farthest corner)
// + rho_max + dilation.
void RadialPoseState::fill_map_cell(int g, const FiledTriangles& filed) {
  const RadialGrid& grid = coarse_grid_;
  const auto cell = static_cast<std::size_t>(g);
  const Vec3 centre = cell_centre_direction(grid, g);
  const double corner_angle = farthest_corner_angle(grid, coarse_locator_, g, centre);
  std::vector<int> near;
  cells_of_cap(grid, centre, corner_angle + filed.rho_max + map_dilation_rad_ + 1e-6, near);
  std::vector<std::array<Vec3, 3>> flat;
  for (const int h : near) {
    map_lo_[cell] = std::min(map_lo_[cell], filed.own_lo[static_cast<std::size_t>(h)]);
    map_hi_[cell] = std::max(map_hi_[cell], filed.own_hi[static_cast<std::size_t>(h)]);
    for (const std::int32_t t : filed.own_flat[static_cast<std::size_t>(h)]) {
      flat.push_back(triangle_relative(*fixed_, static_cast<std::size_t>(t), table_->centre));
    }
  }
  if (flat.empty()) return;
  const RadialSpans::FlatWedge wedge = flat_wedge(flat);
  if (wedge.sin_bound < 0.5) {
    map_wedge_[cell] = {wedge.normal, std::asin(wedge.sin_bound) + 1e-9};
  } else {  // no thin wedge: their spans [0, inf] count
    map_lo_[cell] = std::min(map_lo_[cell], 0.0);
    map_hi_[cell] = RadialSpans::kInfinity;
  }
}

bool RadialPoseState::map_culled(const Bucket& bucket, const Vec3& axis, double shift_mm, double scale_mm) const {
  if (map_lo_.empty() || !(bucket.half_angle_rad < 4.0) || !(shift_mm < bucket.r_lo)) return false;
  // The posed directions lie within half_angle + asin(x) of axis, x = shift / r_lo; asin(x) <=
  // tan(asin(x)) = x / sqrt(1 - x^2) (x < 1 above), by far more than rounding except for x so small
  // that the difference is below 1e-20 rad, which the 1e-6 rad reach of the map's cells and the
  // 1e-9 margin of the wedge test cover.
  const double x = shift_mm / bucket.r_lo;
  const double cone_rad = bucket.half_angle_rad + x / std::sqrt(1.0 - x * x);
  if (!(cone_rad <= map_dilation_rad_)) return false;
  // The locator may differ from cell_of_direction within ~1e-15 rad of a border; the map's cells
  // reach 1e-6 rad further than the dilation, which covers it.
  const auto g = static_cast<std::size_t>(coarse_locator_.cell(axis));
  const double slack = shift_mm + 1e-9 * scale_mm;
  const bool beyond = span_side(options_) == SpanCull::kBelowLo ? bucket.r_hi + slack < map_lo_[g] * (1.0 - 1e-12)
                                                                 : bucket.r_lo - slack > map_hi_[g] * (1.0 + 1e-12);
  if (!beyond) return false;
  // The triangles without a span near g: every posed direction must stay out of their wedge, so
  // farther from its plane than the wedge's angle (then the exact test misses each of them).
  const MapWedge& wedge = map_wedge_[g];
  if (wedge.angle_rad < 0.0) return true;
  const double from_plane = std::asin(std::min(1.0, std::abs(axis.dot(wedge.normal)) / axis.norm()));
  return from_plane - cone_rad > wedge.angle_rad + 1e-9;
}

bool RadialPoseState::distance_culled(const Bucket& bucket, double shift_mm, double scale_mm) const {
  if (!use_spans_) return false;
  const RadialSpans& spans = table_->spans;
  // The full query culls a vertex whose computed |d| is outside the span (radial_spans.h); a
  // posed vertex's |d| is within shift_mm of its rest distance, up to rounding (1e-9 of the
  // coordinates' scale, far above it), so every vertex of such a bucket is culled at this pose.
  const double slack = shift_mm + 1e-9 * scale_mm;
  if (span_side(options_) == SpanCull::kBelowLo) return bucket.r_hi + slack < spans.lo * (1.0 - 1e-12);
  return bucket.r_lo - slack > spans.hi * (1.0 + 1e-12);
}

bool RadialPoseState::cap_culled(const Bucket& bucket, const Vec3& rest_cap_axis, const CapAngle& cap,
                                 double shift_mm) const {
  // Posed, a vertex's direction is R (v - c') with c' = pose^-1 O, |c' - O| = shift_mm: (v - c')
  // turns away from (v - O) by at most asin(shift / |v - O|), and (v - O) lies within the bucket's
  // cone. If even the nearest such direction is farther from the cap's axis (taken back to the rest
  // frame, R^T axis) than the cap's half-angle plus 1e-4 rad, d . axis < |d| cos(cap) by far more
  // than the rounding of the per-vertex test (radial_spans.h), so that test culls every vertex.
  // The angles add up to total = cap + 1e-4 + half_angle + asin(x), x = shift / r_lo; below pi
  // (checked with asin(x) <= pi x / 2) "angle > total" is "cos(angle) < cos(total)", and cos(total)
  // follows from the sines and cosines by the addition formulas (no inverse trigonometry per bucket).
  if (!use_spans_ || !(bucket.half_angle_rad < 4.0) || !(shift_mm < bucket.r_lo)) return false;
  const double x = shift_mm / bucket.r_lo;
  if (!(cap.angle_rad + bucket.half_angle_rad + 0.5 * std::numbers::pi * x < std::numbers::pi - 1e-3)) return false;
  const double cos_ab = cap.cos * bucket.cos_half_angle - cap.sin * bucket.sin_half_angle;
  const double sin_ab = cap.sin * bucket.cos_half_angle + cap.cos * bucket.sin_half_angle;
  const double cos_total = cos_ab * std::sqrt(1.0 - x * x) - sin_ab * x;
  return bucket.axis.dot(rest_cap_axis) < cos_total;
}

RadialPoseState::KeptBuckets RadialPoseState::kept_buckets(const Eigen::Isometry3d& pose) const {
  // |pose v - O| = |v - c'| with c' = pose^-1 O: the rest distance moves by at most |c' - O|.
  const Vec3& centre = table_->centre;
  const Vec3 moved_centre = pose.inverse(Eigen::Isometry) * centre;
  const double shift = (moved_centre - centre).norm();
  const double scale = largest_distance_ + 2.0 * centre.norm() + pose.translation().norm() + shift;
  const RadialSpans& spans = table_->spans;
  const bool has_cap = use_spans_ && spans.cap_cos > -1.0;
  const Vec3 rest_cap_axis = pose.linear().transpose() * spans.cap_axis;
  CapAngle cap;
  if (has_cap) {
    cap.angle_rad = std::acos(std::max(-1.0, std::min(1.0, spans.cap_cos))) + 1e-4;
    cap.cos = std::cos(cap.angle_rad);
    cap.sin = std::sin(cap.angle_rad);
  }
  // The buckets this pose keeps, cut into blocks of about kBlockVertices vertices for the workers.
  KeptBuckets kept;
  kept.block_start.push_back(0);
  std::size_t in_block = 0;
  for (std::size_t b = 0; b < buckets_.size(); ++b) {
    const Bucket& bucket = buckets_[b];
    if (distance_culled(bucket, shift, scale)) continue;
    if (has_cap && cap_culled(bucket, rest_cap_axis, cap, shift)) continue;
    if (map_culled(bucket, pose.linear() * bucket.axis, shift, scale)) continue;
    kept.buckets.push_back(static_cast<std::uint32_t>(b));
    kept.num_vertices += bucket.end - bucket.begin;
    in_block += bucket.end - bucket.begin;
    if (in_block >= kBlockVertices) {
      kept.block_start.push_back(kept.buckets.size());
      in_block = 0;
    }
  }
  if (kept.block_start.back() != kept.buckets.size()) kept.block_start.push_back(kept.buckets.size());
  return kept;
}

std::size_t RadialPoseState::num_tested_vertices(const Eigen::Isometry3d& pose) const {
  if (status_ != QueryStatus::kOk || !pose.matrix().allFinite()) return 0;
  return kept_buckets(pose).num_vertices;
}

PenetrationResult RadialPoseState::query(const Eigen::Isometry3d& pose) const {
  return run(pose, [&pose](const Vec3& v) -> Vec3 { return pose * v; });
}

PenetrationResult RadialPoseState::query_rotation(const Eigen::Matrix3d& rotation) const {
  const Vec3 centre = table_ != nullptr ? table_->centre : Vec3::Zero();
  const Eigen::Isometry3d pose = Eigen::Translation3d(centre) * Eigen::Isometry3d(rotation) * Eigen::Translation3d(-centre);
  return run(pose, [&rotation, &centre](const Vec3& v) -> Vec3 { return centre + rotation * (v - centre); });
}

template <typename Posing>
PenetrationResult RadialPoseState::run(const Eigen::Isometry3d& pose, const Posing& posing) const {
  PenetrationResult result;
  if (status_ != QueryStatus::kOk) {
    result.status = QueryStatus::kInvalidInput;
    result.message = message_.empty() ? "radial pose query: not built" : message_;
    return result;
  }
  if (!pose.matrix().allFinite()) {
    result.status = QueryStatus::kInvalidInput;
    result.message = "radial pose query: the pose is not finite";
    return result;
  }
  const KeptBuckets kept_buckets_of_pose = kept_buckets(pose);
  const std::vector<std::uint32_t>& kept = kept_buckets_of_pose.buckets;
  const std::vector<std::size_t>& block_start = kept_buckets_of_pose.block_start;
  std::atomic<bool> finite{true};
  const VertexQuery query(*table_, *fixed_, options_, use_spans_);
  result.pairs = gather_blocks(block_start.size() - 1, options_.num_threads,
                               [&](std::size_t block, VertexQuery::Scratch& scratch, std::vector<PenetrationPair>& hits) {
                                 // Two passes over batches of vertices: the culls first, starting the
                                 // loads of each kept vertex's cell, then the triangle tests, so the
                                 // loads of several vertices overlap (hits are sorted by vertex below).
                                 PenetrationPair pair;
                                 std::array<VertexQuery::Kept, 32> batch;
                                 std::size_t batched = 0;
                                 auto flush = [&] {
                                   for (std::size_t b = 0; b < batched; ++b) {
                                     if (b + 4 < batched) query.prefetch(batch[b + 4], 1);
                                     if (b + 2 < batched) query.prefetch(batch[b + 2], 2);
                                     if (query.decide(batch[b], scratch, pair)) hits.push_back(pair);
                                   }
                                   batched = 0;
                                 };
                                 for (std::size_t i = block_start[block]; i < block_start[block + 1]; ++i) {
                                   const Bucket& bucket = buckets_[kept[i]];
                                   for (std::uint32_t k = bucket.begin; k < bucket.end; ++k) {
                                     const Vec3 position = posing(sorted_position_[k]);
                                     if (!position.allFinite()) {
                                       finite = false;
                                       continue;
                                     }
                                     if (!query.keep(sorted_index_[k], position, batch[batched])) continue;
                                     query.prefetch(batch[batched], 0);
                                     if (++batched == batch.size()) flush();
                                   }
                                 }
                                 flush();
                               });
  if (!finite) {
    result.status = QueryStatus::kInvalidInput;
    result.message = "radial pose query: a posed mobile vertex is not finite";
    result.pairs.clear();
    return result;
  }
  sort_by_vertex(result.pairs, sorted_index_.size());
  return result;
}

}  // namespace hipfai::contact::detail
