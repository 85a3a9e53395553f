#include "contact/axis_reach.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hipfai::contact {
namespace {

constexpr double kReachPad = 1e-9;

// A body in the axis frame: each vertex's (r, z) and each triangle's (r, z) box.
struct Body {
  std::vector<double> r, z;
  std::vector<CylindricalBounds> triangles;
};

Body body_in_frame(const geometry::TriMesh& mesh, const AxisFrame& frame) {
  Body body;
  std::vector<Vec3> local(mesh.vertices.size());
  body.r.resize(local.size());
  body.z.resize(local.size());
  for (std::size_t v = 0; v < local.size(); ++v) {
    local[v] = frame.to_local(mesh.vertices[v]);
    body.r[v] = std::hypot(local[v].x(), local[v].y());
    body.z[v] = local[v].z();
  }
  body.triangles.reserve(mesh.triangles.size());
  for (const auto& tri : mesh.triangles) {
    const CylindricalBounds b = triangle_cylindrical_bounds(local[static_cast<std::size_t>(tri[0])],
                                                            local[static_cast<std::size_t>(tri[1])],
                                                            local[static_cast<std::size_t>(tri[2])]);
    body.triangles.push_back(b);
  }
  return body;
}

// A grid over (r, z) and one body's marks on it, as 2D prefix sums.
class Footprint {
 public:
  Footprint(double r0, double z0, double cell, long long nr, long long nz)
      : r0_(r0), z0_(z0), cell_(cell), nr_(nr), nz_(nz) {}

  void mark(const Body& body, double pad) {
    std::vector<std::uint8_t> marked(static_cast<std::size_t>(nr_ * nz_), 0);
    const auto fill = [&](const CylindricalBounds& box) {
      const Cells c = cells(box, pad);
      for (long long z = c.z0; z <= c.z1; ++z) {
        std::fill(marked.begin() + z * nr_ + c.r0, marked.begin() + z * nr_ + c.r1 + 1, std::uint8_t{1});
      }
    };
    for (const CylindricalBounds& box : body.triangles) fill(box);
    for (std::size_t v = 0; v < body.r.size(); ++v) fill({body.r[v], body.r[v], body.z[v], body.z[v]});
    sums_.assign(static_cast<std::size_t>((nz_ + 1) * (nr_ + 1)), 0);
    for (long long z = 0; z < nz_; ++z) {
      for (long long r = 0; r < nr_; ++r) {
        sums_[at(z + 1, r + 1)] = marked[static_cast<std::size_t>(z * nr_ + r)] + sums_[at(z + 1, r)] +
                                  sums_[at(z, r + 1)] - sums_[at(z, r)];
      }
    }
  }

  // True when the box, widened by `pad`, overlaps a marked cell.
  bool reaches(const CylindricalBounds& box, double pad) const {
    const Cells c = cells(box, pad);
    return sums_[at(c.z1 + 1, c.r1 + 1)] + sums_[at(c.z0, c.r0)] - sums_[at(c.z0, c.r1 + 1)] -
               sums_[at(c.z1 + 1, c.r0)] > 0;
  }

 private:
  struct Cells {
    long long r0, r1, z0, z1;
  };
  // floor((value - origin) / cell), clamped to the grid (the grid covers both bodies, so the
  // clamp only absorbs the padding at its rim).
  long long index(double value, double origin, long long n) const {
    const double scaled = std::floor((value - origin) / cell_);
    if (!(scaled >= 0.0)) return 0;
    return scaled >= static_cast<double>(n - 1) ? n - 1 : static_cast<long long>(scaled);
  }
  Cells cells(const CylindricalBounds& box, double pad) const {
    return {index(box.r_min - pad, r0_, nr_), index(box.r_max + pad, r0_, nr_), index(box.z_min - pad, z0_, nz_),
            index(box.z_max + pad, z0_, nz_)};
  }
  std::size_t at(long long z, long long r) const { return static_cast<std::size_t>(z * (nr_ + 1) + r); }

  double r0_, z0_, cell_;
  long long nr_, nz_;
  std::vector<std::uint32_t> sums_;
};

// The parts of `mesh` (as `body`) that reach `other`'s footprint, compacted in order.
void keep_reaching(const geometry::TriMesh& mesh, const Body& body, const Footprint& other, double pad,
                   geometry::TriMesh& kept, std::vector<std::int32_t>& vertex_of, std::vector<std::int32_t>& triangle_of) {
  std::vector<std::uint8_t> keep_vertex(mesh.vertices.size(), 0);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    keep_vertex[v] = other.reaches({body.r[v], body.r[v], body.z[v], body.z[v]}, pad) ? 1 : 0;
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!other.reaches(body.triangles[t], pad)) continue;
    triangle_of.push_back(static_cast<std::int32_t>(t));
    for (const std::int32_t v : mesh.triangles[t]) keep_vertex[static_cast<std::size_t>(v)] = 1;
  }
  std::vector<std::int32_t> renumber(mesh.vertices.size(), -1);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!keep_vertex[v]) continue;
    renumber[v] = static_cast<std::int32_t>(vertex_of.size());
    vertex_of.push_back(static_cast<std::int32_t>(v));
    kept.vertices.push_back(mesh.vertices[v]);
  }
  kept.triangles.reserve(triangle_of.size());
  for (const std::int32_t t : triangle_of) {
    const auto& tri = mesh.triangles[static_cast<std::size_t>(t)];
    kept.triangles.push_back({renumber[static_cast<std::size_t>(tri[0])], renumber[static_cast<std::size_t>(tri[1])],
                              renumber[static_cast<std::size_t>(tri[2])]});
  }
}

// Mean length of the triangles' edges (each interior edge twice: the grid's scale, not a measure).
double mean_triangle_edge(const geometry::TriMesh& a, const geometry::TriMesh& b) {
  double total = 0.0;
  std::size_t count = 0;
  for (const auto* mesh : {&a, &b}) {
    for (const auto& tri : mesh->triangles) {
      for (std::size_t k = 0; k < 3; ++k) {
        total += (mesh->vertices[static_cast<std::size_t>(tri[k])] - mesh->vertices[static_cast<std::size_t>(tri[(k + 1) % 3])]).norm();
      }
      count += 3;
    }
  }
  return count > 0 ? total / static_cast<double>(count) : 0.0;
}

}  // namespace

AxisReach reach_about_axis(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile, const Vec3& centre,
                           const Vec3& axis) {
  const AxisFrame frame = make_axis_frame(centre, axis).frame;
  const Body fixed_body = body_in_frame(fixed, frame), mobile_body = body_in_frame(mobile, frame);
  double r_hi = 0.0, z_lo = std::numeric_limits<double>::infinity(), z_hi = -z_lo;
  for (const Body* body : {&fixed_body, &mobile_body}) {
    for (std::size_t v = 0; v < body->r.size(); ++v) {
      r_hi = std::max(r_hi, body->r[v]);
      z_lo = std::min(z_lo, body->z[v]);
      z_hi = std::max(z_hi, body->z[v]);
    }
  }
  AxisReach reach;
  if (!(z_lo <= z_hi)) return reach;  // no vertex at all
  const double pad = kReachPad * std::max({1.0, r_hi, std::abs(z_lo), std::abs(z_hi)});
  // The grid spans every widened box: r from 0 (no point is nearer the axis), z over all vertices.
  const double r0 = -2.0 * pad, z0 = z_lo - 2.0 * pad;
  const double r_extent = r_hi + 4.0 * pad, z_extent = z_hi - z_lo + 4.0 * pad;
  const double cell = std::max({mean_triangle_edge(fixed, mobile), r_extent / 2048.0, z_extent / 2048.0, 1e-9});
  const auto nr = static_cast<long long>(std::floor(r_extent / cell)) + 1;
  const auto nz = static_cast<long long>(std::floor(z_extent / cell)) + 1;
  Footprint fixed_footprint(r0, z0, cell, nr, nz), mobile_footprint(r0, z0, cell, nr, nz);
  fixed_footprint.mark(fixed_body, pad);
  mobile_footprint.mark(mobile_body, pad);
  keep_reaching(fixed, fixed_body, mobile_footprint, pad, reach.fixed, reach.fixed_vertices, reach.fixed_triangles);
  keep_reaching(mobile, mobile_body, fixed_footprint, pad, reach.mobile, reach.mobile_vertices, reach.mobile_triangles);
  return reach;
}

}  // namespace hipfai::contact
