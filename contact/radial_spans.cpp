#include "contact/radial_spans.h"

#include "contact/radial_table.h"
#include "contact/ray_triangle.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace hipfai::contact {

using Vec3 = Eigen::Vector3d;

double distance_to_origin(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = -a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a.norm();
  const Vec3 bp = -b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return (a + d1 / (d1 - d3) * ab).norm();
  const Vec3 cp = -c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return (a + d2 / (d2 - d6) * ac).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b)).norm();
  }
  const double denominator = 1.0 / (va + vb + vc);
  return (a + ab * (vb * denominator) + ac * (vc * denominator)).norm();
}

RadialSpans::TrianglePlanes triangle_planes(const Vec3& a, const Vec3& b, const Vec3& c) {
  RadialSpans::TrianglePlanes planes;
  planes.edge_ab = a.cross(b);
  planes.edge_bc = b.cross(c);
  planes.edge_ca = c.cross(a);
  planes.area_normal = (b - a).cross(c - a);
  planes.det = a.dot(b.cross(c));
  const double m_a = max_abs_component(a), m_b = max_abs_component(b), m_c = max_abs_component(c);
  planes.bound_ab = 1e-13 * m_a * m_b;
  planes.bound_bc = 1e-13 * m_b * m_c;
  planes.bound_ca = 1e-13 * m_c * m_a;
  return planes;
}

void triangle_radial_span(const Vec3& a, const Vec3& b, const Vec3& c, double& lo, double& hi) {
  constexpr double kEps = 1.2e-16;  // unit roundoff, rounded up
  const double na = a.norm(), nb = b.norm(), nc = c.norm();
  const double far = std::max({na, nb, nc});
  const Vec3 normal = (b - a).cross(c - a);
  const double area2 = normal.norm();
  if (normal.x() == 0.0 && normal.y() == 0.0 && normal.z() == 0.0) {
    lo = RadialSpans::kInfinity;  // zero area: never crossed (ray_triangle_crossing), empty span
    hi = -RadialSpans::kInfinity;
    return;
  }
  lo = 0.0;
  hi = RadialSpans::kInfinity;
  if (!(area2 > 0.0) || !(far > 0.0)) return;
  const double shape = (b - a).norm() * (c - a).norm() / area2;
  // Plane distance from O, minus the rounding of a . N (so a lower bound of the true one): a plane
  // through O up to rounding gets no span (never culled by distance).
  const double h = (std::abs(a.dot(normal)) - 8.0 * kEps * na * area2 * (1.0 + shape)) / area2;
  if (!(h > 0.0)) return;
  const double error = 8.0 * kEps * shape * (far / h) + 8.0 * kEps * na * nb * nc / (h * area2);
  if (!(error < 1e-3)) return;
  const double nearest = distance_to_origin(a, b, c);
  lo = std::max(0.0, (nearest - 1e-14 * far) * (1.0 - error) * (1.0 - 1e-12));
  hi = far * (1.0 + error) * (1.0 + 1e-12);
}

namespace {

// The sign of det(a, b, c) = a . (b x c) when planes.det is beyond the bound on its rounding (the
// bound of the query's edge functions, same expression), else 0.
int certified_orientation(const RadialSpans::TrianglePlanes& planes, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double bound = 1e-13 * max_abs_component(a) * max_abs_component(b) * max_abs_component(c);
  return planes.det > bound ? 1 : (planes.det < -bound ? -1 : 0);
}

// Floats rounded outward, so the packed spans still contain the double ones.
float float_below(double value) {
  float f = static_cast<float>(value);
  if (static_cast<double>(f) > value) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

float float_above(double value) {
  float f = static_cast<float>(value);
  if (static_cast<double>(f) < value) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

}  // namespace

RadialSpans::FlatWedge flat_wedge(std::span<const std::array<Vec3, 3>> triangles) {
  RadialSpans::FlatWedge wedge;  // sin_bound 2: none
  if (triangles.empty()) return wedge;
  // The plane: normal to the direction the unit vertex directions spread least along.
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& triangle : triangles) {
    for (const Vec3& x : triangle) {
      const double r = x.norm();
      if (!(r > 0.0)) return wedge;  // a vertex at O: directions everywhere
      scatter += (x / r) * (x / r).transpose();
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  if (solver.info() != Eigen::Success) return wedge;
  const Vec3 n = solver.eigenvectors().col(0);
  // A ray y = sum w_i x_i (w_i >= 0) in a triangle's cone: |y . n| <= across sum w_i |x_i| with
  // across = max |x_i . n| / |x_i|, and |y| >= y . m >= cos_rho sum w_i |x_i| with m the unit mean of
  // the vertex directions and cos_rho = min x_i . m / |x_i| (> 1/2: a cone narrower than 60 deg,
  // convex, so a hit lies in it); so |y . n| / |y| <= across / cos_rho. The 1e-9 margin covers the
  // rounding here and in the query's |d . n| and |d| (~1e-15 relative).
  double bound = 0.0;
  for (const auto& triangle : triangles) {
    std::array<Vec3, 3> unit;
    Vec3 sum = Vec3::Zero();
    for (std::size_t k = 0; k < 3; ++k) {
      unit[k] = triangle[k] / triangle[k].norm();
      sum += unit[k];
    }
    if (!(sum.norm() > 0.0)) return wedge;
    const Vec3 mean = sum.normalized();
    double cos_rho = 1.0, across = 0.0;
    for (const Vec3& u : unit) {
      cos_rho = std::min(cos_rho, u.dot(mean));
      across = std::max(across, std::abs(u.dot(n)));
    }
    if (!(cos_rho > 0.5)) return wedge;
    bound = std::max(bound, across / cos_rho);
  }
  bound += 1e-9;
  if (!(bound < 0.5)) return wedge;
  wedge.normal = n;
  wedge.sin_bound = bound;
  return wedge;
}

namespace {

// Does the ray from O along d cross the triangle, in plain floating point (edge functions of one
// sign, t > 0)? Enough for a hint, which only orders the tests: ten times cheaper than the exact test.
bool roughly_crossed(const Vec3& d, const RadialSpans::TrianglePlanes& planes) {
  const double e_ab = d.dot(planes.edge_ab), e_bc = d.dot(planes.edge_bc), e_ca = d.dot(planes.edge_ca);
  const bool one_sign = (e_ab >= 0.0 && e_bc >= 0.0 && e_ca >= 0.0) || (e_ab <= 0.0 && e_bc <= 0.0 && e_ca <= 0.0);
  return one_sign && planes.det / d.dot(planes.area_normal) > 0.0;
}

// The hints of every cell of a cube-mapping table (RadialSpans, HINTS).
void compute_hints(RadialSpans& spans) {
  const RadialSpans::CubeLocator& cube = spans.cube;
  const int n = cube.dimension, side = RadialSpans::kHintSide;
  for (std::size_t id = 0; id < spans.cells.size(); ++id) {
    RadialSpans::Cell& cell = spans.cells[id];
    cell.hint.fill(RadialSpans::kNoHint);
    const std::uint32_t last = std::min(cell.end, cell.wedge_end + 32);
    if (cell.wedge_end >= last) continue;
    const int i = static_cast<int>(id) % n, j = (static_cast<int>(id) / n) % n, face = static_cast<int>(id) / (n * n);
    const int k = face / 2;
    for (int part_w = 0; part_w < side; ++part_w) {
      for (int part_u = 0; part_u < side; ++part_u) {
        Vec3 d;
        d[k] = face % 2 == 0 ? 1.0 : -1.0;
        const auto su = static_cast<std::size_t>(i * side + part_u), sw = static_cast<std::size_t>(j * side + part_w);
        d[(k + 1) % 3] = 0.5 * (cube.slice_border[su] + cube.slice_border[su + 1]);
        d[(k + 2) % 3] = 0.5 * (cube.slice_border[sw] + cube.slice_border[sw + 1]);
        for (std::uint32_t e = cell.wedge_end; e < last; ++e) {
          if (roughly_crossed(d, spans.planes[static_cast<std::size_t>(spans.entries[e].triangle)])) {
            cell.hint[static_cast<std::size_t>(part_w * side + part_u)] = static_cast<std::uint8_t>(e - cell.wedge_end);
            break;
          }
        }
      }
    }
  }
}

// Each triangle's span of distances from the centre and its planes through it; the spans' range.
void triangle_spans(RadialSpans& spans, const geometry::TriMesh& fixed, const Vec3& centre) {
  const std::size_t num_triangles = fixed.num_triangles();
  spans.triangle_lo.resize(num_triangles);
  spans.triangle_hi.resize(num_triangles);
  spans.planes.resize(num_triangles);
  for (std::size_t t = 0; t < num_triangles; ++t) {
    const auto [a, b, c] = triangle_relative(fixed, t, centre);
    triangle_radial_span(a, b, c, spans.triangle_lo[t], spans.triangle_hi[t]);
    spans.planes[t] = triangle_planes(a, b, c);
    spans.lo = std::min(spans.lo, spans.triangle_lo[t]);
    spans.hi = std::max(spans.hi, spans.triangle_hi[t]);
  }
}

// Appends the entries of table cell `id` in ascending lo (then index): a vertex at r on the
// kBelowLo side needs only the prefix of entries with lo <= r. Sets the cell's range, its span
// (with the always-checked triangles' [always_lo, always_hi]) and returns its triangles in
// that order.
std::vector<std::int32_t> list_cell_entries(RadialSpans& spans, const RadialTable& table, std::size_t id,
                                            double always_lo, double always_hi) {
  RadialSpans::Cell& cell = spans.cells[id];
  cell.begin = static_cast<std::uint32_t>(spans.entries.size());
  double cell_lo = always_lo, cell_hi = always_hi;
  std::vector<std::int32_t> listed = table.cells[id];
  // (float_below is monotone, so the stored float lo ascend too.)
  std::sort(listed.begin(), listed.end(), [&](std::int32_t x, std::int32_t y) {
    const double lo_x = spans.triangle_lo[static_cast<std::size_t>(x)], lo_y = spans.triangle_lo[static_cast<std::size_t>(y)];
    return lo_x != lo_y ? lo_x < lo_y : x < y;
  });
  for (const std::int32_t t : listed) {
    const double lo = spans.triangle_lo[static_cast<std::size_t>(t)], hi = spans.triangle_hi[static_cast<std::size_t>(t)];
    cell_lo = std::min(cell_lo, lo);
    cell_hi = std::max(cell_hi, hi);
    spans.entries.push_back({t, float_below(lo), float_above(hi), 0});
  }
  cell.end = static_cast<std::uint32_t>(spans.entries.size());
  spans.cell_lo[id] = float_below(cell_lo);
  spans.cell_hi[id] = float_above(cell_hi);
  return listed;
}

// The flat wedge of the cell's leading entries without a span (lo 0), when they fit in one.
void cell_flat_wedge(RadialSpans& spans, RadialSpans::Cell& cell, const std::vector<std::int32_t>& listed,
                     const geometry::TriMesh& fixed, const Vec3& centre) {
  cell.wedge_end = cell.begin;
  std::vector<std::array<Vec3, 3>> flat;
  for (std::size_t i = 0; i < listed.size() && spans.triangle_lo[static_cast<std::size_t>(listed[i])] == 0.0; ++i) {
    flat.push_back(triangle_relative(fixed, static_cast<std::size_t>(listed[i]), centre));
  }
  if (flat.empty()) return;
  const RadialSpans::FlatWedge wedge = flat_wedge(flat);
  if (wedge.sin_bound < 1.0) {
    cell.wedge_end = cell.begin + static_cast<std::uint32_t>(flat.size());
    cell.wedge = static_cast<std::uint32_t>(spans.wedges.size());
    spans.wedges.push_back(wedge);
  }
}

// Marks the separated pairs among the first 32 entries past the cell's wedge (both ways: a hinted
// entry is tested before the cell's others).
void mark_separated(RadialSpans& spans, const RadialSpans::Cell& cell, const ConeSeparation& separation) {
  const std::uint32_t base = cell.wedge_end, last = std::min(cell.end, base + 32);
  for (std::uint32_t i = base; i < last; ++i) {
    for (std::uint32_t j = i + 1; j < last; ++j) {
      if (!separation.separated(spans.entries[i].triangle, spans.entries[j].triangle)) continue;
      spans.entries[i].separated |= std::uint32_t{1} << (j - base);
      spans.entries[j].separated |= std::uint32_t{1} << (i - base);
    }
  }
}

// The cap: around the mean direction of the vertices used by triangles; every vertex's direction
// within it. Kept only when clearly narrower than a hemisphere (convex cone).
void compute_cap(RadialSpans& spans, const geometry::TriMesh& fixed, const Vec3& centre) {
  std::vector<std::uint8_t> used(fixed.num_vertices(), 0);
  for (const auto& tri : fixed.triangles) {
    for (const auto v : tri) used[static_cast<std::size_t>(v)] = 1;
  }
  Vec3 sum = Vec3::Zero();
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (!used[v]) continue;
    const Vec3 d = fixed.vertices[v] - centre;
    const double r = d.norm();
    if (!(r > 0.0)) return;  // a vertex at O: directions everywhere, no cap
    sum += d / r;
  }
  if (!(sum.norm() > 0.0)) return;
  const Vec3 axis = sum.normalized();
  double cos_angle = 1.0;
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (!used[v]) continue;
    const Vec3 d = fixed.vertices[v] - centre;
    cos_angle = std::min(cos_angle, d.dot(axis) / d.norm());
  }
  cos_angle -= 1e-12;  // rounding of the unit directions above
  if (cos_angle > std::cos(89.0 * 3.14159265358979323846 / 180.0)) {
    spans.cap_axis = axis;
    spans.cap_cos = cos_angle;
  }
}

}  // namespace

void compute_radial_spans(RadialTable& table, const geometry::TriMesh& fixed) {
  RadialSpans& spans = table.spans;
  spans = RadialSpans{};
  spans.vertices = fixed.vertices;
  triangle_spans(spans, fixed, table.centre);
  double always_lo = RadialSpans::kInfinity, always_hi = -RadialSpans::kInfinity;
  for (const std::int32_t t : table.always_candidates) {
    always_lo = std::min(always_lo, spans.triangle_lo[static_cast<std::size_t>(t)]);
    always_hi = std::max(always_hi, spans.triangle_hi[static_cast<std::size_t>(t)]);
  }
  const ConeSeparation separation(fixed, table.centre, spans.planes);
  spans.cells.resize(table.cells.size());
  spans.cell_lo.resize(table.cells.size());
  spans.cell_hi.resize(table.cells.size());
  spans.entries.clear();
  spans.entries.reserve(table.num_entries());
  for (std::size_t id = 0; id < table.cells.size(); ++id) {
    const std::vector<std::int32_t> listed = list_cell_entries(spans, table, id, always_lo, always_hi);
    cell_flat_wedge(spans, spans.cells[id], listed, fixed, table.centre);
    mark_separated(spans, spans.cells[id], separation);
  }
  if (table.grid.mapping == RadialMapping::kCube) {
    spans.cube = make_cube_locator(table.grid.dimension);
    compute_hints(spans);
  }
  compute_cap(spans, fixed, table.centre);
}

ConeSeparation::ConeSeparation(const geometry::TriMesh& mesh, const Vec3& centre,
                               std::span<const RadialSpans::TrianglePlanes> planes)
    : mesh_(&mesh), planes_(planes), relative_(mesh.num_vertices()), scale_(mesh.num_vertices()),
      orientation_(mesh.num_triangles()) {
  for (std::size_t v = 0; v < relative_.size(); ++v) {
    relative_[v] = mesh.vertices[v] - centre;
    scale_[v] = max_abs_component(relative_[v]);
  }
  for (std::size_t t = 0; t < orientation_.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    orientation_[t] = certified_orientation(planes[t], relative_[static_cast<std::size_t>(tri[0])],
                                            relative_[static_cast<std::size_t>(tri[1])], relative_[static_cast<std::size_t>(tri[2])]);
  }
}

bool ConeSeparation::edge_plane_separates(std::int32_t t, std::int32_t u) const {
  const auto& tri_t = mesh_->triangles[static_cast<std::size_t>(t)];
  const auto& tri_u = mesh_->triangles[static_cast<std::size_t>(u)];
  const RadialSpans::TrianglePlanes& planes = planes_[static_cast<std::size_t>(t)];
  const int s_t = orientation_[static_cast<std::size_t>(t)];
  const std::array<const Vec3*, 3> edges{&planes.edge_ab, &planes.edge_bc, &planes.edge_ca};
  for (std::size_t e = 0; e < 3; ++e) {
    const std::int32_t p = tri_t[e], q = tri_t[(e + 1) % 3];
    const double m_pq = scale_[static_cast<std::size_t>(p)] * scale_[static_cast<std::size_t>(q)];
    bool beyond = true;
    for (const std::int32_t w : tri_u) {
      if (w == p || w == q) continue;  // on the plane exactly
      const double value = relative_[static_cast<std::size_t>(w)].dot(*edges[e]);
      if (!(s_t * value < -1e-13 * scale_[static_cast<std::size_t>(w)] * m_pq)) {
        beyond = false;
        break;
      }
    }
    if (beyond) return true;
  }
  return false;
}

bool ConeSeparation::separated(std::int32_t t, std::int32_t u) const {
  if (orientation_[static_cast<std::size_t>(t)] == 0 || orientation_[static_cast<std::size_t>(u)] == 0) return false;
  return edge_plane_separates(t, u) || edge_plane_separates(u, t);
}

RadialSpans::CubeLocator make_cube_locator(int dimension) {
  RadialSpans::CubeLocator cube;
  const int n = dimension;
  cube.dimension = n;
  cube.border.resize(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) {
    cube.border[static_cast<std::size_t>(i)] = std::tan(i * (std::numbers::pi / 2.0) / n - std::numbers::pi / 4.0);
  }
  const int side = RadialSpans::kHintSide, slices = n * side;
  cube.slice_border.resize(static_cast<std::size_t>(slices) + 1);
  for (int m = 0; m <= slices; ++m) {
    const auto i = static_cast<std::size_t>(m / side);
    const int p = m % side;
    cube.slice_border[static_cast<std::size_t>(m)] =
        p == 0 ? cube.border[i] : cube.border[i] + (static_cast<double>(p) / side) * (cube.border[i + 1] - cube.border[i]);
  }
  const int bins = 2 * slices;
  cube.bins_per_unit = bins / 2.0;
  cube.start.resize(static_cast<std::size_t>(bins));
  int m = 0;
  for (int bin = 0; bin < bins; ++bin) {
    const double u = -1.0 + bin / cube.bins_per_unit;
    while (m + 1 < slices && u >= cube.slice_border[static_cast<std::size_t>(m + 1)]) ++m;
    cube.start[static_cast<std::size_t>(bin)] = m;
  }
  return cube;
}

bool radial_spans_valid(const RadialSpans& spans, const geometry::TriMesh& fixed) {
  if (spans.vertices.size() != fixed.vertices.size() || spans.triangle_lo.size() != fixed.num_triangles()) {
    return false;
  }
  return std::equal(spans.vertices.begin(), spans.vertices.end(), fixed.vertices.begin());
}

}  // namespace hipfai::contact
