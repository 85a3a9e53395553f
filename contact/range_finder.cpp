#include "contact/range_finder.h"

#include "contact/axis_reach.h"
#include "core/numbers.h"
#include "core/parallel.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <utility>

namespace hipfai::contact {
namespace {

using hipfai::kTwoPi;
using hipfai::kDegPerRad;
// Widening of the edges' angular extents: far above the rounding of atan2 and of the edge-edge
// roots (acos near +-1 loses about sqrt(ulp), ~1e-8 rad), far below any angle that matters.
constexpr double kAngularMarginRad = 1e-6;

struct DirectionBest {
  double angle_rad = kTwoPi;
  LimitingContact contact;
  void offer(double angle, const LimitingContact& candidate) {
    if (angle < angle_rad) {
      angle_rad = angle;
      contact = candidate;
    }
  }
};

// A vertex at (r, theta0) whose circle crosses `triangle` at `theta`: the rotation to reach it in
// each direction. Within touching_mm of it (a resting contact) it limits only the direction that
// enters the other solid, to 0.
void offer_crossing(double r, double theta0, double theta, const Vec3& normal, const LimitingContact& contact,
                    double touching_mm, DirectionBest& forward, DirectionBest& backward) {
  const double delta = wrap_angle(theta - theta0);
  if (r * std::abs(delta) <= touching_mm) {
    const double exit = crossing_exit_sign(theta, normal);
    if (exit < 0.0) forward.offer(0.0, contact);
    if (exit > 0.0) backward.offer(0.0, contact);
    return;
  }
  forward.offer(delta > 0.0 ? delta : delta + kTwoPi, contact);
  backward.offer(delta < 0.0 ? -delta : kTwoPi - delta, contact);
}

// The chunks' minima into the overall ones, in chunk order (a tie keeps the earlier chunk's).
void merge_chunks(const std::vector<DirectionBest>& chunk_forward, const std::vector<DirectionBest>& chunk_backward,
                  DirectionBest& forward, DirectionBest& backward) {
  for (std::size_t c = 0; c < chunk_forward.size(); ++c) {
    forward.offer(chunk_forward[c].angle_rad, chunk_forward[c].contact);
    backward.offer(chunk_backward[c].angle_rad, chunk_backward[c].contact);
  }
}

// Smallest anticlockwise ("forward") and clockwise ("backward") motion of the cached vertices
// before they meet a crossing; one pass over the stored crossings.
void scan(const CylindricalPoseCache& cache, ContactKind kind, int num_threads,
          DirectionBest& forward, DirectionBest& backward) {
  const auto& tracked = cache.tracked();
  const int threads = resolve_threads(num_threads);
  std::vector<DirectionBest> chunk_forward(static_cast<std::size_t>(threads));
  std::vector<DirectionBest> chunk_backward(static_cast<std::size_t>(threads));
  const double touching_mm = cache.touching_mm();
  parallel_chunks(tracked.size(), threads, [&](std::size_t begin, std::size_t end, int c) {
    DirectionBest& fwd = chunk_forward[static_cast<std::size_t>(c)];
    DirectionBest& bwd = chunk_backward[static_cast<std::size_t>(c)];
    for (std::size_t i = begin; i < end; ++i) {
      const auto& vertex = tracked[i];
      for (std::size_t k = vertex.first; k < vertex.last; ++k) {
        const std::int32_t triangle = cache.crossing_triangle(k);
        offer_crossing(vertex.r, vertex.theta0_rad, cache.crossing_theta_rad(k), cache.local_normal(triangle),
                       {kind, vertex.vertex, triangle}, touching_mm, fwd, bwd);
      }
    }
  });
  merge_chunks(chunk_forward, chunk_backward, forward, backward);
}

// ------------------------------------------------------------------ vertex passes from a table

// True unless every rotation that brings an angle `theta` into `extent` is at least as far as the
// running minima in both directions (then nothing of it can be offered: offers are strict). The
// rotation phi puts theta in the extent for phi in [start, start + width] (mod 2 pi).
bool may_beat(double theta, const AngularExtent& extent, const DirectionBest& forward, const DirectionBest& backward) {
  if (extent.width >= kTwoPi) return true;
  double start = extent.lo - theta;
  while (start < 0.0) start += kTwoPi;
  while (start >= kTwoPi) start -= kTwoPi;
  if (start + extent.width >= kTwoPi) return true;  // the set holds phi = 0
  return start < forward.angle_rad || kTwoPi - (start + extent.width) < backward.angle_rad;
}

// Every triangle's angular extent (arc_triangle.h).
std::vector<AngularExtent> triangle_extents(const CylindricalTable& table) {
  std::vector<AngularExtent> extents(table.num_triangles());
  for (std::size_t t = 0; t < extents.size(); ++t) {
    const auto& tri = table.triangle(static_cast<std::int32_t>(t));
    extents[t] = triangle_angular_extent(table.local_vertex(tri[0]), table.local_vertex(tri[1]),
                                         table.local_vertex(tri[2]));
  }
  return extents;
}

// The vertex pass of a pose cache built from `table` and `points` followed by scan(), without
// storing the crossings: the same candidates, crossings, order and offers, except that a candidate
// triangle whose angular extent cannot beat the running minima is not evaluated (it could offer
// nothing). Each chunk starts from the minima it is given.
void scan_table(const CylindricalTable& table, const geometry::TriMesh& points, ContactKind kind, double touching_mm,
                bool prune, int num_threads, DirectionBest& forward, DirectionBest& backward) {
  if (table.status() != QueryStatus::kOk) return;
  // Without pruning every extent is the whole turn, which may_beat never rejects.
  const std::vector<AngularExtent> extents =
      prune ? triangle_extents(table) : std::vector<AngularExtent>(table.num_triangles());
  const AxisFrame& frame = table.frame();
  const int threads = resolve_threads(num_threads);
  std::vector<DirectionBest> chunk_forward(static_cast<std::size_t>(threads), forward);
  std::vector<DirectionBest> chunk_backward(static_cast<std::size_t>(threads), backward);
  parallel_chunks(points.vertices.size(), threads, [&](std::size_t begin, std::size_t end, int c) {
    DirectionBest& fwd = chunk_forward[static_cast<std::size_t>(c)];
    DirectionBest& bwd = chunk_backward[static_cast<std::size_t>(c)];
    std::vector<std::pair<std::int32_t, double>> found;
    for (std::size_t v = begin; v < end; ++v) {
      const Vec3 local = frame.to_local(points.vertices[v]);
      if (!table.distance_may_touch(local.norm())) continue;
      const Cylindrical cyl = to_cylindrical(local);
      const auto beats = [&](std::int32_t t) { return may_beat(cyl.theta, extents[static_cast<std::size_t>(t)], fwd, bwd); };
      circle_crossings(table, cyl.r, cyl.z, beats, found);
      for (const auto& [triangle, theta] : found) {
        offer_crossing(cyl.r, cyl.theta, theta, table.local_normal(triangle),
                       {kind, static_cast<std::int32_t>(v), triangle}, touching_mm, fwd, bwd);
      }
    }
  });
  merge_chunks(chunk_forward, chunk_backward, forward, backward);
}

// ------------------------------------------------------------------ edge-edge contacts

// An edge in the axis frame with its extent in radius and height (both kept by the rotation),
// widened by a margin that absorbs the rounding of the extents.
struct LocalEdge {
  Vec3 p, d;  // start and direction (end - start), local coordinates
  double r_lo, r_hi, z_lo, z_hi;
  // Angular extent about the axis: theta in [theta_lo, theta_lo + theta_width] (width <= pi for a
  // segment off the axis; 2 pi, i.e. anything, when it passes within its length of the axis).
  double theta_lo, theta_width;
  std::array<std::int32_t, 2> ends;
};

std::vector<LocalEdge> local_edges(const geometry::TriMesh& mesh, const AxisFrame& frame) {
  // Unique undirected edges by buckets on the lower vertex (linear time; a global sort of all
  // 3 x #triangles keys dominated the finder on large meshes).
  const std::size_t num_vertices = mesh.vertices.size();
  std::vector<std::int32_t> start(num_vertices + 1, 0);
  auto for_each_edge = [&](auto&& fn) {
    for (const auto& tri : mesh.triangles) {
      for (std::size_t k = 0; k < 3; ++k) {
        const std::int32_t a = tri[k], b = tri[(k + 1) % 3];
        if (a != b) fn(std::min(a, b), std::max(a, b));
      }
    }
  };
  for_each_edge([&](std::int32_t a, std::int32_t) { ++start[static_cast<std::size_t>(a) + 1]; });
  for (std::size_t v = 0; v < num_vertices; ++v) start[v + 1] += start[v];
  std::vector<std::int32_t> upper(static_cast<std::size_t>(start[num_vertices]));
  std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
  for_each_edge([&](std::int32_t a, std::int32_t b) { upper[static_cast<std::size_t>(fill[static_cast<std::size_t>(a)]++)] = b; });
  std::vector<std::pair<std::int32_t, std::int32_t>> keys;
  keys.reserve(upper.size() / 2 + 1);
  for (std::size_t v = 0; v < num_vertices; ++v) {
    const auto first = upper.begin() + start[v], last = upper.begin() + start[v + 1];
    std::sort(first, last);
    for (auto it = first; it != last; ++it) {
      if (it == first || *it != *(it - 1)) keys.emplace_back(static_cast<std::int32_t>(v), *it);
    }
  }
  std::vector<LocalEdge> edges;
  edges.reserve(keys.size());
  for (const auto& [a, b] : keys) {
    const Vec3 p = frame.to_local(mesh.vertices[static_cast<std::size_t>(a)]);
    const Vec3 q = frame.to_local(mesh.vertices[static_cast<std::size_t>(b)]);
    const Vec3 d = q - p;
    // Radius along the segment: largest at an end, smallest at the point nearest the axis.
    const double dxy2 = d.x() * d.x() + d.y() * d.y();
    const double t = dxy2 > 0.0 ? std::clamp(-(p.x() * d.x() + p.y() * d.y()) / dxy2, 0.0, 1.0) : 0.0;
    const double margin = 1e-9 * (1.0 + p.norm() + q.norm());
    LocalEdge e;
    e.p = p;
    e.d = d;
    // sqrt(x^2 + y^2): coordinates are mm, far from over/underflow; rounding is within margin.
    const double nx = p.x() + t * d.x(), ny = p.y() + t * d.y();
    e.r_lo = std::sqrt(nx * nx + ny * ny) - margin;
    e.r_hi = std::sqrt(std::max(p.x() * p.x() + p.y() * p.y(), q.x() * q.x() + q.y() * q.y())) + margin;
    e.z_lo = std::min(p.z(), q.z()) - margin;
    e.z_hi = std::max(p.z(), q.z()) + margin;
    // Seen from the axis, a segment that does not pass through it sweeps the shorter arc between
    // its ends' angles. Widened by kAngularMarginRad for rounding (also of the roots below).
    const double theta_p = std::atan2(p.y(), p.x()), sweep = wrap_angle(std::atan2(q.y(), q.x()) - theta_p);
    if (e.r_lo > 0.0 && std::abs(sweep) < 0.9 * std::numbers::pi) {
      e.theta_lo = (sweep >= 0.0 ? theta_p : theta_p + sweep) - kAngularMarginRad;
      e.theta_width = std::abs(sweep) + 2.0 * kAngularMarginRad;
    } else {
      e.theta_lo = -std::numbers::pi;
      e.theta_width = kTwoPi;
    }
    e.ends = {a, b};
    edges.push_back(e);
  }
  return edges;
}

// The fixed edges binned on a grid over (r, z) (compressed rows: cell -> edge indices).
struct EdgeRingGrid {
  double r0 = 0.0, z0 = 0.0, cell = 1.0;
  int nr = 1, nz = 1;
  std::vector<std::int32_t> offsets, entries;
  int index(double value, double origin, int n) const {
    const double scaled = std::floor((value - origin) / cell);
    if (!(scaled >= 0.0)) return 0;
    return scaled >= n ? n - 1 : static_cast<int>(scaled);
  }
  int ir(double r) const { return index(r, r0, nr); }
  int iz(double z) const { return index(z, z0, nz); }
};

EdgeRingGrid bin_edges(const std::vector<LocalEdge>& edges) {
  EdgeRingGrid grid;
  if (edges.empty()) return grid;
  double r1 = edges[0].r_hi, z1 = edges[0].z_hi, length = 0.0;
  grid.r0 = edges[0].r_lo;
  grid.z0 = edges[0].z_lo;
  for (const auto& e : edges) {
    grid.r0 = std::min(grid.r0, e.r_lo);
    grid.z0 = std::min(grid.z0, e.z_lo);
    r1 = std::max(r1, e.r_hi);
    z1 = std::max(z1, e.z_hi);
    length += e.d.norm();
  }
  // Cells about an edge long (the thesis' advice for the ring table), at most 2048 a side.
  grid.cell = std::max({length / static_cast<double>(edges.size()), (r1 - grid.r0) / 2048.0,
                        (z1 - grid.z0) / 2048.0, 1e-9});
  grid.nr = static_cast<int>(std::floor((r1 - grid.r0) / grid.cell)) + 1;
  grid.nz = static_cast<int>(std::floor((z1 - grid.z0) / grid.cell)) + 1;
  const std::size_t cells = static_cast<std::size_t>(grid.nr) * static_cast<std::size_t>(grid.nz);
  grid.offsets.assign(cells + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::int32_t> fill;
    if (pass == 1) {
      for (std::size_t c = 0; c < cells; ++c) grid.offsets[c + 1] += grid.offsets[c];
      grid.entries.resize(static_cast<std::size_t>(grid.offsets[cells]));
      fill.assign(grid.offsets.begin(), grid.offsets.end() - 1);
    }
    for (std::size_t i = 0; i < edges.size(); ++i) {
      const auto& e = edges[i];
      for (int r = grid.ir(e.r_lo); r <= grid.ir(e.r_hi); ++r) {
        for (int z = grid.iz(e.z_lo); z <= grid.iz(e.z_hi); ++z) {
          const std::size_t c = static_cast<std::size_t>(r) * static_cast<std::size_t>(grid.nz) + static_cast<std::size_t>(z);
          if (pass == 0) {
            ++grid.offsets[c + 1];
          } else {
            grid.entries[static_cast<std::size_t>(fill[c]++)] = static_cast<std::int32_t>(i);
          }
        }
      }
    }
  }
  return grid;
}

// The roots of det[R(theta) P - Q, R(theta) D, E] = a cos + b sin + c (see the header) where the
// two segments meet, offered to the two directions' running minima.
void edge_pair(const LocalEdge& m, const Vec3& w, const LocalEdge& f, const Vec3& g,
               DirectionBest& forward, DirectionBest& backward) {
  const Vec3& d = m.d;
  const Vec3& e = f.d;
  const double a = (e.x() * w.x() + e.y() * w.y()) - (g.x() * d.x() + g.y() * d.y());
  const double b = (e.y() * w.x() - e.x() * w.y()) - (g.y() * d.x() - g.x() * d.y());
  const double c = e.z() * w.z() - g.z() * d.z();
  const double rho = std::hypot(a, b);
  // rho == 0: the coplanarity does not depend on theta (parallel edges, or both parallel to the
  // axis): any contact is an end point on the other edge, a vertex contact.
  const double scale = e.norm() * w.norm() + g.norm() * d.norm();
  if (!(rho > 1e-13 * scale) || std::abs(c) > rho) return;
  const double phi = std::atan2(b, a);
  const double beta = std::acos(std::clamp(-c / rho, -1.0, 1.0));
  for (const double root : {phi + beta, phi - beta}) {
    const double theta = wrap_angle(root);
    if (std::abs(theta) <= 1e-12) continue;  // touching at the start: see the header
    const double ahead = theta > 0.0 ? theta : theta + kTwoPi;
    const double behind = theta < 0.0 ? -theta : kTwoPi - theta;
    if (ahead >= forward.angle_rad && behind >= backward.angle_rad) continue;
    const double cs = std::cos(theta), sn = std::sin(theta);
    const Vec3 p(cs * m.p.x() - sn * m.p.y(), sn * m.p.x() + cs * m.p.y(), m.p.z());
    const Vec3 dr(cs * d.x() - sn * d.y(), sn * d.x() + cs * d.y(), d.z());
    // The coplanar lines' crossing: s dr - u e = f.p - p, solved in the least-squares sense.
    const Vec3 r = f.p - p;
    const double aa = dr.dot(dr), bb = dr.dot(e), cc = e.dot(e), d1 = dr.dot(r), e1 = e.dot(r);
    const double den = aa * cc - bb * bb;
    if (!(den > 1e-12 * aa * cc)) continue;  // (nearly) parallel: left to the vertex passes
    const double s = (d1 * cc - bb * e1) / den;
    const double u = (bb * d1 - aa * e1) / den;
    if (s < 0.0 || s > 1.0 || u < 0.0 || u > 1.0) continue;
    LimitingContact contact;
    contact.kind = ContactKind::kEdgeOnEdge;
    contact.mobile_edge = m.ends;
    contact.fixed_edge = f.ends;
    forward.offer(ahead, contact);
    backward.offer(behind, contact);
  }
}

// False when every rotation that brings the two edges' angular extents together is at least as
// far as the running minima in both directions: then no root of edge_pair can be offered (a
// contact point lies in both extents). The mobile edge turned by phi meets the fixed edge's extent
// for phi in [start, start + width] (mod 2 pi).
bool may_beat(const LocalEdge& m, const LocalEdge& f, const DirectionBest& forward, const DirectionBest& backward) {
  // The mobile edge's start angle must reach [f.lo - m.width, f.lo + f.width].
  return may_beat(m.theta_lo, {f.theta_lo - m.theta_width, m.theta_width + f.theta_width}, forward, backward);
}

// Every edge-edge first contact that beats the running minima `forward` / `backward`.
void scan_edges(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile, const AxisFrame& frame,
                bool prune, int num_threads, DirectionBest& forward, DirectionBest& backward) {
  const std::vector<LocalEdge> fixed_edges = local_edges(fixed, frame);
  const std::vector<LocalEdge> mobile_edges = local_edges(mobile, frame);
  if (fixed_edges.empty() || mobile_edges.empty()) return;
  const EdgeRingGrid grid = bin_edges(fixed_edges);
  std::vector<Vec3> g(fixed_edges.size());
  for (std::size_t i = 0; i < fixed_edges.size(); ++i) g[i] = fixed_edges[i].d.cross(fixed_edges[i].p);
  const int threads = resolve_threads(num_threads);
  std::vector<DirectionBest> chunk_forward(static_cast<std::size_t>(threads), forward);
  std::vector<DirectionBest> chunk_backward(static_cast<std::size_t>(threads), backward);
  parallel_chunks(mobile_edges.size(), threads, [&](std::size_t begin, std::size_t end, int chunk) {
    DirectionBest& fwd = chunk_forward[static_cast<std::size_t>(chunk)];
    DirectionBest& bwd = chunk_backward[static_cast<std::size_t>(chunk)];
    for (std::size_t i = begin; i < end; ++i) {
      const LocalEdge& m = mobile_edges[i];
      if (m.r_hi < grid.r0 || m.z_hi < grid.z0) continue;
      const Vec3 w = m.p.cross(m.d);
      const int r_first = grid.ir(m.r_lo), r_last = grid.ir(m.r_hi);
      const int z_first = grid.iz(m.z_lo), z_last = grid.iz(m.z_hi);
      for (int r = r_first; r <= r_last; ++r) {
        for (int z = z_first; z <= z_last; ++z) {
          const std::size_t c = static_cast<std::size_t>(r) * static_cast<std::size_t>(grid.nz) + static_cast<std::size_t>(z);
          for (auto k = grid.offsets[c]; k < grid.offsets[c + 1]; ++k) {
            const auto fi = static_cast<std::size_t>(grid.entries[static_cast<std::size_t>(k)]);
            const LocalEdge& f = fixed_edges[fi];
            if (f.r_hi < m.r_lo || f.r_lo > m.r_hi || f.z_hi < m.z_lo || f.z_lo > m.z_hi) continue;
            // Each pair once: in the cell of the lower corner of the two extents' overlap.
            if (std::max(r_first, grid.ir(f.r_lo)) != r || std::max(z_first, grid.iz(f.z_lo)) != z) continue;
            if (prune && !may_beat(m, f, fwd, bwd)) continue;
            edge_pair(m, w, f, g[fi], fwd, bwd);
          }
        }
      }
    }
  });
  merge_chunks(chunk_forward, chunk_backward, forward, backward);
}

RangeOfMotion to_range(const DirectionBest& anticlockwise, const DirectionBest& clockwise) {
  RangeOfMotion range;
  range.anticlockwise_deg = anticlockwise.angle_rad * kDegPerRad;
  range.clockwise_deg = clockwise.angle_rad * kDegPerRad;
  range.anticlockwise_limit = anticlockwise.contact;
  range.clockwise_limit = clockwise.contact;
  return range;
}

RangeOfMotion invalid_range(std::string message) {
  RangeOfMotion range;
  range.status = QueryStatus::kInvalidInput;
  range.message = std::move(message);
  return range;
}

}  // namespace

RangeOfMotion range_of_motion(const CylindricalPoseCache& mobile_on_fixed,
                              const CylindricalPoseCache* fixed_on_mobile, int num_threads) {
  if (mobile_on_fixed.status() == QueryStatus::kInvalidInput) {
    return invalid_range("range of motion: invalid pre-processed mobile mesh");
  }
  if (fixed_on_mobile != nullptr && fixed_on_mobile->status() == QueryStatus::kInvalidInput) {
    return invalid_range("range of motion: invalid pre-processed fixed mesh");
  }
  DirectionBest anticlockwise, clockwise;
  scan(mobile_on_fixed, ContactKind::kMobileVertexOnFixedTriangle, num_threads, anticlockwise,
       clockwise);
  if (fixed_on_mobile != nullptr) {
    // The mobile mesh turning anticlockwise moves the fixed vertices clockwise relative to it.
    scan(*fixed_on_mobile, ContactKind::kFixedVertexOnMobileTriangle, num_threads, clockwise,
         anticlockwise);
  }
  return to_range(anticlockwise, clockwise);
}

namespace {

bool finite_with_valid_indices(const geometry::TriMesh& mesh) {
  const auto n = static_cast<std::int32_t>(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) {
    if (!p.allFinite()) return false;
  }
  for (const auto& tri : mesh.triangles) {
    for (const std::int32_t v : tri) {
      if (v < 0 || v >= n) return false;
    }
  }
  return !mesh.vertices.empty() && !mesh.triangles.empty();
}

// Indices of the kept sub-meshes back to the input meshes'.
void to_input_indices(LimitingContact& contact, const AxisReach& reach) {
  const auto map = [](std::int32_t& index, const std::vector<std::int32_t>& original) {
    if (index >= 0) index = original[static_cast<std::size_t>(index)];
  };
  switch (contact.kind) {
    case ContactKind::kNone: break;
    case ContactKind::kMobileVertexOnFixedTriangle:
      map(contact.vertex, reach.mobile_vertices);
      map(contact.triangle, reach.fixed_triangles);
      break;
    case ContactKind::kFixedVertexOnMobileTriangle:
      map(contact.vertex, reach.fixed_vertices);
      map(contact.triangle, reach.mobile_triangles);
      break;
    case ContactKind::kEdgeOnEdge:
      for (auto& v : contact.mobile_edge) map(v, reach.mobile_vertices);
      for (auto& v : contact.fixed_edge) map(v, reach.fixed_vertices);
      break;
  }
}

}  // namespace

RangeOfMotion range_of_motion(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                              const Vec3& centre, const Vec3& axis,
                              const RangeOfMotionOptions& options) {
  if (options.cull_unreachable && make_axis_frame(centre, axis).valid && finite_with_valid_indices(fixed) &&
      finite_with_valid_indices(mobile)) {
    const AxisReach reach = reach_about_axis(fixed, mobile, centre, axis);
    if (reach.fixed.triangles.empty() && reach.mobile.triangles.empty()) {
      return to_range(DirectionBest{}, DirectionBest{});  // nothing can meet: free both ways
    }
    // (One side with nothing left but the other with triangles is left to the full meshes: only
    // isolated vertices could do that.)
    if (!reach.fixed.triangles.empty() && !reach.mobile.triangles.empty()) {
      RangeOfMotionOptions whole = options;
      whole.cull_unreachable = false;
      RangeOfMotion range = range_of_motion(reach.fixed, reach.mobile, centre, axis, whole);
      to_input_indices(range.anticlockwise_limit, reach);
      to_input_indices(range.clockwise_limit, reach);
      return range;
    }
  }
  CylindricalTableOptions table_options = options.table;
  table_options.angular_index = false;  // the vertex passes read every crossing
  const CylindricalTable fixed_table =
      CylindricalTable::build(fixed, centre, axis, table_options, &mobile);
  if (fixed_table.status() == QueryStatus::kInvalidInput) return invalid_range(fixed_table.message());
  // The vertex passes straight from the tables (what a pose cache per body would store, then
  // scan(), without storing it), then the edge-edge pass bounded by their ranges.
  DirectionBest anticlockwise, clockwise;
  const double touching_mm = options.query.touching_mm;
  const int threads = options.query.num_threads;
  const bool prune = options.angular_pruning;
  scan_table(fixed_table, mobile, ContactKind::kMobileVertexOnFixedTriangle, touching_mm, prune, threads, anticlockwise,
             clockwise);
  if (options.include_fixed_vertices) {
    const CylindricalTable mobile_table =
        CylindricalTable::build(mobile, centre, axis, table_options, &fixed);
    if (mobile_table.status() == QueryStatus::kInvalidInput) {
      return invalid_range(mobile_table.message());
    }
    // The mobile mesh turning anticlockwise moves the fixed vertices clockwise relative to it.
    scan_table(mobile_table, fixed, ContactKind::kFixedVertexOnMobileTriangle, touching_mm, prune, threads, clockwise,
               anticlockwise);
  }
  if (options.include_edge_edge) {
    // Same frame as the tables' (make_axis_frame of the same centre and axis).
    scan_edges(fixed, mobile, make_axis_frame(centre, axis).frame, prune, threads, anticlockwise, clockwise);
  }
  return to_range(anticlockwise, clockwise);
}

std::vector<AxisRangeOfMotion> range_of_motion_fan(const geometry::TriMesh& fixed,
                                                   const geometry::TriMesh& mobile,
                                                   const Vec3& centre, const Vec3& plane_normal,
                                                   int steps,
                                                   const RangeOfMotionOptions& options) {
  std::vector<AxisRangeOfMotion> fan;
  const AxisFrameResult plane = make_axis_frame(centre, plane_normal);
  if (!plane.valid || steps <= 0) {
    AxisRangeOfMotion bad;
    bad.range = invalid_range("fan: the plane normal must be non-zero and steps > 0");
    fan.push_back(bad);
    return fan;
  }
  for (int i = 0; i < steps; ++i) {
    AxisRangeOfMotion entry;
    entry.angle_deg = 180.0 * i / steps;
    const double angle = entry.angle_deg / kDegPerRad;
    entry.axis = std::cos(angle) * plane.frame.e1 + std::sin(angle) * plane.frame.e2;
    entry.range = range_of_motion(fixed, mobile, centre, entry.axis, options);
    fan.push_back(entry);
  }
  return fan;
}

std::vector<AxisRangeOfMotion> range_of_motion_sphere(const geometry::TriMesh& fixed,
                                                      const geometry::TriMesh& mobile,
                                                      const Vec3& centre, const Vec3& pole,
                                                      int polar_steps, int azimuth_steps,
                                                      const RangeOfMotionOptions& options) {
  std::vector<AxisRangeOfMotion> grid;
  const AxisFrameResult frame = make_axis_frame(centre, pole);
  if (!frame.valid || polar_steps <= 0 || azimuth_steps <= 0) {
    AxisRangeOfMotion bad;
    bad.range = invalid_range("sphere: the pole must be non-zero and steps > 0");
    grid.push_back(bad);
    return grid;
  }
  for (int i = 0; i <= polar_steps; ++i) {
    const double polar_deg = 90.0 * i / polar_steps;
    const int azimuths = i == 0 ? 1 : azimuth_steps;
    for (int j = 0; j < azimuths; ++j) {
      AxisRangeOfMotion entry;
      entry.angle_deg = polar_deg;
      entry.azimuth_deg = 360.0 * j / azimuth_steps;
      const double polar = polar_deg / kDegPerRad, azimuth = entry.azimuth_deg / kDegPerRad;
      entry.axis = std::cos(polar) * frame.frame.axis +
                   std::sin(polar) * (std::cos(azimuth) * frame.frame.e1 +
                                      std::sin(azimuth) * frame.frame.e2);
      entry.range = range_of_motion(fixed, mobile, centre, entry.axis, options);
      grid.push_back(entry);
    }
  }
  return grid;
}

}  // namespace hipfai::contact
