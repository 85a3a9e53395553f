#include "contact/radial_segmenting.h"

#include "contact/ray_triangle.h"
#include "core/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <thread>

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
bool clearly_missed(const Vec3& d, double m_d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double m_a = max_abs(a), m_b = max_abs(b), m_c = max_abs(c);
  const double e_ab = d.dot(a.cross(b)), e_bc = d.dot(b.cross(c)), e_ca = d.dot(c.cross(a));
  const double tolerance = 1e-13 * m_d;
  const double bound_ab = tolerance * m_a * m_b, bound_bc = tolerance * m_b * m_c,
               bound_ca = tolerance * m_c * m_a;
  const bool pos = e_ab > bound_ab || e_bc > bound_bc || e_ca > bound_ca;
  const bool neg = e_ab < -bound_ab || e_bc < -bound_bc || e_ca < -bound_ca;
  return pos && neg;
}

// The exact crossing of the ray along `direction` (|direction|_inf = m_d) with fixed triangle t,
// after the float pre-filter.
RayCrossing crossing_of(const geometry::TriMesh& fixed, const Vec3& centre, const Vec3& direction,
                        double m_d, std::int32_t t) {
  const auto& tri = fixed.triangles[static_cast<std::size_t>(t)];
  const Vec3 a = fixed.vertices[static_cast<std::size_t>(tri[0])] - centre;
  const Vec3 b = fixed.vertices[static_cast<std::size_t>(tri[1])] - centre;
  const Vec3 c = fixed.vertices[static_cast<std::size_t>(tri[2])] - centre;
  if (clearly_missed(direction, m_d, a, b, c)) return {};
  return ray_triangle_crossing(direction, a, b, c);
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

void query_range(const RadialTable& table, const geometry::TriMesh& fixed,
                 const geometry::TriMesh& mobile, const RadialQueryOptions& options,
                 std::size_t begin, std::size_t end, std::vector<PenetrationPair>& slots,
                 std::vector<std::uint8_t>& hits) {
  const bool inside_fixed = options.configuration == RadialConfiguration::kMobileInsideFixed;
  const double cap_radius = options.neighbour_cells * table.grid.nominal_cell_angle_rad();
  std::vector<int> cap_cells;
  const bool union_rule = options.rule == RadialCrossingRule::kUnion;
  std::vector<Crossing> crossings;
  for (std::size_t v = begin; v < end; ++v) {
    const Vec3 direction = mobile.vertices[v] - table.centre;
    if (direction.isZero(0.0)) continue;  // v == O: no ray
    Adjacent adjacent;
    crossings.clear();
    const double m_d = max_abs(direction);
    auto visit = [&](const std::vector<std::int32_t>& candidates) {
      for (const std::int32_t t : candidates) {
        if (union_rule) {
          const RayCrossing crossing = crossing_of(fixed, table.centre, direction, m_d, t);
          if (crossing.hit) crossings.push_back({crossing.t, crossing.facing, t});
        } else {
          offer(fixed, table.centre, direction, m_d, options.configuration, t, adjacent);
        }
      }
    };
    if (options.neighbour_cells > 0) {
      cap_cells.clear();
      cells_of_cap(table.grid, direction, cap_radius, cap_cells);
      for (const int id : cap_cells) visit(table.cell(id));
    } else {
      visit(table.cell(cell_of_direction(table.grid, direction)));
    }
    visit(table.always_candidates);
    if (union_rule) {
      double t_union = 0.0;
      std::int32_t triangle = -1;
      if (!resolve_union(fixed, crossings, inside_fixed, t_union, triangle)) continue;
      const double depth = (inside_fixed ? 1.0 - t_union : t_union - 1.0) * direction.norm();
      slots[v] = PenetrationPair{static_cast<std::int32_t>(v), triangle, depth};
      hits[v] = 1;
      continue;
    }
    if (!adjacent.found || adjacent.t == 1.0) continue;
    if (adjacent.facing != (inside_fixed ? -1 : 1)) continue;
    const double depth = (inside_fixed ? 1.0 - adjacent.t : adjacent.t - 1.0) * direction.norm();
    slots[v] = PenetrationPair{static_cast<std::int32_t>(v), adjacent.triangle, depth};
    hits[v] = 1;
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
  if (options.num_threads == 2 && count > 1) {
    // Each thread writes its own slots: no sharing, and the output order is fixed afterwards.
    const std::size_t half = count / 2;
    std::thread worker([&] { query_range(table, fixed, mobile, options, 0, half, slots, hits); });
    query_range(table, fixed, mobile, options, half, count, slots, hits);
    worker.join();
  } else {
    query_range(table, fixed, mobile, options, 0, count, slots, hits);
  }
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
