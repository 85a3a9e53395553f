#include "contact/radial_segmenting.h"

#include "contact/ray_triangle.h"
#include "core/error.h"
#include "core/parallel.h"

#include <algorithm>
#include <atomic>
#include <array>
#include <cmath>
#include <limits>

namespace hipfai::contact {

namespace {

// The adjacent crossing found so far for one vertex (see the crossing rule in the header).
struct Adjacent {
  bool found = false;
  double t = 0.0;
  int facing = 0;
  std::int32_t triangle = -1;
};

double max_abs(const Vec3& v) {
  return std::max({std::abs(v.x()), std::abs(v.y()), std::abs(v.z())});
}

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
int filter_crossing(const Vec3& d, double m_d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double m_a = max_abs(a), m_b = max_abs(b), m_c = max_abs(c);
  const double e_ab = d.dot(a.cross(b)), e_bc = d.dot(b.cross(c)), e_ca = d.dot(c.cross(a));
  const double tolerance = 1e-13 * m_d;
  const double bound_ab = tolerance * m_a * m_b, bound_bc = tolerance * m_b * m_c,
               bound_ca = tolerance * m_c * m_a;
  const int pos = (e_ab > bound_ab) + (e_bc > bound_bc) + (e_ca > bound_ca);
  const int neg = (e_ab < -bound_ab) + (e_bc < -bound_bc) + (e_ca < -bound_ca);
  if (pos > 0 && neg > 0) return 0;
  if (pos == 3) return 1;
  if (neg == 3) return -1;
  return 2;
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

// Offers one candidate triangle to the running choice.
void offer(const geometry::TriMesh& fixed, const Vec3& centre, const Vec3& direction, double m_d,
           RadialConfiguration configuration, std::int32_t t, Adjacent& adjacent) {
  const RayCrossing crossing = crossing_of(fixed, centre, direction, m_d, t);
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

bool share_a_vertex(const geometry::TriMesh& mesh, std::int32_t a, std::int32_t b) {
  for (auto i : mesh.triangles[static_cast<std::size_t>(a)]) {
    for (auto j : mesh.triangles[static_cast<std::size_t>(b)]) {
      if (i == j) return true;
    }
  }
  return false;
}

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
          (it->facing == c.facing && share_a_vertex(fixed, it->triangle, c.triangle))) {
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
        cap_radius(options_in.neighbour_cells * table_in.grid.nominal_cell_angle_rad()) {}

  const RadialTable& table;
  const geometry::TriMesh& fixed;
  const RadialQueryOptions& options;
  const RadialSpans& spans;
  bool use_spans, inside_fixed, union_rule, beyond_rule;
  SpanCull side;
  bool skip_triangles;
  double cap_radius;

  struct Scratch {
    std::vector<int> cap_cells;
    std::vector<Crossing> crossings;
  };

  // The crossing rule for the mobile vertex `index` at `position`; false when it does not penetrate.
  bool penetrates(std::int32_t index, const Vec3& position, Scratch& scratch, PenetrationPair& out) const {
    const Vec3 direction = position - table.centre;
    if (direction.isZero(0.0)) return false;  // v == O: no ray
    double r = 0.0;
    if (use_spans) {
      r = direction.norm();
      if (outside_span(side, r, spans.lo, spans.hi) || outside_cap(spans, direction, r)) return false;
    }
    Adjacent adjacent;
    scratch.crossings.clear();
    const double m_d = max_abs(direction);
    auto offer_triangle = [&](std::int32_t t) {
      if (union_rule || beyond_rule) {
        const RayCrossing crossing = crossing_of(fixed, table.centre, direction, m_d, t);
        if (crossing.hit) scratch.crossings.push_back({crossing.t, crossing.facing, t});
      } else {
        offer(fixed, table.centre, direction, m_d, options.configuration, t, adjacent);
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
      for (const int id : scratch.cap_cells) visit(table.cell(id));
    } else if (use_spans) {
      // The packed cells: one record per cell, entries contiguous with their spans inline.
      const int id = spans.cube.dimension > 0 ? spans.cube.cell(direction) : cell_of_direction(table.grid, direction);
      const RadialSpans::Cell& cell = spans.cells[static_cast<std::size_t>(id)];
      if (outside_span(side, r, cell.lo, cell.hi)) return false;
      for (std::uint32_t k = cell.begin; k < cell.end; ++k) {
        const RadialSpans::Entry& entry = spans.entries[k];
        if (skip_triangles && outside_span(side, r, entry.lo, entry.hi)) continue;
        offer_triangle(entry.triangle);
      }
    } else {
      visit(table.cell(cell_of_direction(table.grid, direction)));
    }
    visit(table.always_candidates);
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

void query_range(const VertexQuery& query, const geometry::TriMesh& mobile, std::size_t begin, std::size_t end,
                 std::vector<PenetrationPair>& slots, std::vector<std::uint8_t>& hits) {
  VertexQuery::Scratch scratch;
  for (std::size_t v = begin; v < end; ++v) {
    if (query.penetrates(static_cast<std::int32_t>(v), mobile.vertices[v], scratch, slots[v])) hits[v] = 1;
  }
}

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
  PenetrationResult result;
  result.message = check_inputs(table, fixed, mobile, options);
  if (!result.message.empty()) {
    result.status = QueryStatus::kInvalidInput;
    return result;
  }
  const std::size_t count = mobile.num_vertices();
  std::vector<PenetrationPair> slots(count);
  std::vector<std::uint8_t> hits(count, 0);
  const bool use_spans = options.cull && radial_spans_valid(table.spans, fixed);
  // Each block writes its own slots: no sharing, and the output order is fixed afterwards. Blocks
  // are taken dynamically: culled vertices cost almost nothing, so the work is uneven.
  const VertexQuery query(table, fixed, options, use_spans);
  parallel_blocks(count, options.num_threads, 2048, [&](std::size_t begin, std::size_t end) {
    query_range(query, mobile, begin, end, slots, hits);
  });
  for (std::size_t v = 0; v < count; ++v) {
    if (hits[v]) result.pairs.push_back(slots[v]);
  }
  return result;  // built in vertex order: already sorted
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

}  // namespace hipfai::contact

namespace hipfai::contact {

RadialPoseQuery::RadialPoseQuery(const RadialTable& table, const geometry::TriMesh& fixed,
                                 const geometry::TriMesh& mobile, const RadialQueryOptions& options)
    : table_(&table), fixed_(&fixed), options_(options) {
  message_ = check_inputs(table, fixed, mobile, options);
  if (!message_.empty()) return;
  status_ = QueryStatus::kOk;
  use_spans_ = options.cull && radial_spans_valid(table.spans, fixed);
  // Sorted by distance in shells of kShellMm, then by the table cell of the rest direction: a pose
  // keeps a contiguous run of shells (found by bisection) and walks its vertices cell by cell. A
  // rotation keeps neighbouring directions together, so consecutive vertices read the same or
  // adjacent cell records and triangles (mesh order, after midpoint subdivision, jumps around).
  struct Key {
    std::int64_t shell;
    int cell;
    std::int32_t vertex;
    double distance;
  };
  std::vector<Key> order(mobile.num_vertices());
  for (std::size_t v = 0; v < order.size(); ++v) {
    const Vec3 direction = mobile.vertices[v] - table.centre;
    const double distance = direction.norm();
    const int cell = direction.isZero(0.0) ? -1 : cell_of_direction(table.grid, direction);
    order[v] = {static_cast<std::int64_t>(std::floor(distance / kShellMm)), cell, static_cast<std::int32_t>(v), distance};
  }
  std::sort(order.begin(), order.end(), [](const Key& a, const Key& b) {
    if (a.shell != b.shell) return a.shell < b.shell;
    return a.cell != b.cell ? a.cell < b.cell : a.vertex < b.vertex;
  });
  sorted_distance_.reserve(order.size());
  sorted_position_.reserve(order.size());
  sorted_index_.reserve(order.size());
  for (const Key& key : order) {
    sorted_distance_.push_back(key.distance);
    sorted_position_.push_back(mobile.vertices[static_cast<std::size_t>(key.vertex)]);
    sorted_index_.push_back(key.vertex);
  }
  // Largest distance up to k and smallest from k on: both non-decreasing in k, so the kept run is
  // found by bisection, exactly (no reliance on the shells' rounding).
  prefix_max_.resize(order.size());
  suffix_min_.resize(order.size());
  double running = -1.0;
  for (std::size_t k = 0; k < order.size(); ++k) prefix_max_[k] = running = std::max(running, sorted_distance_[k]);
  running = std::numeric_limits<double>::infinity();
  for (std::size_t k = order.size(); k-- > 0;) suffix_min_[k] = running = std::min(running, sorted_distance_[k]);
  const auto [first, last] = kept_range(0.0, 0.0);
  kept_index_.assign(sorted_index_.begin() + static_cast<std::ptrdiff_t>(first),
                     sorted_index_.begin() + static_cast<std::ptrdiff_t>(last));
}

std::pair<std::size_t, std::size_t> RadialPoseQuery::kept_range(double shift_mm, double scale_mm) const {
  const std::size_t count = sorted_distance_.size();
  if (!use_spans_) return {0, count};
  const RadialSpans& spans = table_->spans;
  // The full query culls a vertex whose computed |d| is outside the span (radial_spans.h); a
  // posed vertex's |d| is within shift_mm of its rest distance, up to rounding (1e-9 of the
  // coordinates' scale, far above it), so these are culled at this pose.
  const double slack = shift_mm + 1e-9 * scale_mm;
  // Vertices before `first` (after `last`) all have rest distances beyond the bound; the kept run
  // may hold a few more of them around its ends, which the query's own span test culls exactly.
  if (span_side(options_) == SpanCull::kBelowLo) {
    const double below = spans.lo * (1.0 - 1e-12) - slack;  // r + slack < lo (1 - 1e-12): culled
    const auto first = std::lower_bound(prefix_max_.begin(), prefix_max_.end(), below);
    return {static_cast<std::size_t>(first - prefix_max_.begin()), count};
  }
  const double above = spans.hi * (1.0 + 1e-12) + slack;  // r - slack > hi (1 + 1e-12): culled
  const auto last = std::upper_bound(suffix_min_.begin(), suffix_min_.end(), above);
  return {0, static_cast<std::size_t>(last - suffix_min_.begin())};
}

PenetrationResult RadialPoseQuery::query(const Eigen::Isometry3d& pose) const {
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
  // |pose v - O| = |v - c'| with c' = pose^-1 O: the rest distance moves by at most |c' - O|.
  const Vec3& centre = table_->centre;
  const Vec3 moved_centre = pose.inverse(Eigen::Isometry) * centre;
  const double shift = (moved_centre - centre).norm();
  const double largest = sorted_distance_.empty() ? 0.0 : sorted_distance_.back();
  const double scale = largest + 2.0 * centre.norm() + pose.translation().norm() + shift;
  const auto [first, last] = kept_range(shift, scale);
  const std::size_t count = last - first;
  std::vector<PenetrationPair> slots(count);
  std::vector<std::uint8_t> hits(count, 0);
  std::atomic<bool> finite{true};
  const VertexQuery query(*table_, *fixed_, options_, use_spans_);
  parallel_blocks(count, options_.num_threads, 2048, [&](std::size_t begin, std::size_t end) {
    VertexQuery::Scratch scratch;
    for (std::size_t k = begin; k < end; ++k) {
      const Vec3 position = pose * sorted_position_[first + k];
      if (!position.allFinite()) {
        finite = false;
        continue;
      }
      if (query.penetrates(sorted_index_[first + k], position, scratch, slots[k])) hits[k] = 1;
    }
  });
  if (!finite) {
    result.status = QueryStatus::kInvalidInput;
    result.message = "radial pose query: a posed mobile vertex is not finite";
    return result;
  }
  for (std::size_t k = 0; k < count; ++k) {
    if (hits[k]) result.pairs.push_back(slots[k]);
  }
  std::sort(result.pairs.begin(), result.pairs.end(),
            [](const PenetrationPair& a, const PenetrationPair& b) { return a.mobile_vertex < b.mobile_vertex; });
  return result;
}

}  // namespace hipfai::contact
