#include "geometry/sphere_split.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace hipfai::geometry {

namespace {

// Parameter t in [0, 1] where a + t (b - a) meets the sphere, a inside and b outside or the
// reverse. f(t) = |a - c + t d|^2 - r^2 is convex with f(0) and f(1) of opposite sign (or f(0) = 0),
// so exactly one root lies in [0, 1]: the larger root when a is inside, the smaller otherwise.
double crossing_parameter(const Vec3& a, const Vec3& b, const Vec3& centre, double radius, bool a_inside) {
  const Vec3 d = b - a;
  const Vec3 m = a - centre;
  const double qa = d.squaredNorm();
  const double qb = m.dot(d);  // half the linear coefficient
  const double qc = m.squaredNorm() - radius * radius;
  const double disc = std::max(qb * qb - qa * qc, 0.0);
  const double root = std::sqrt(disc);
  // Cancellation-free pair of roots: q = -(qb + sign(qb) root), t1 = q / qa, t2 = qc / q.
  const double q = -(qb + std::copysign(root, qb));
  double t1 = q / qa;
  double t2 = q != 0.0 ? qc / q : t1;
  if (t1 > t2) std::swap(t1, t2);
  const double t = a_inside ? t2 : t1;
  return std::clamp(t, 0.0, 1.0);
}

}  // namespace

SphereSplit split_at_sphere(const TriMesh& mesh, const Vec3& centre, double radius) {
  SphereSplit split;
  split.num_original = mesh.num_vertices();
  split.mesh.vertices = mesh.vertices;
  std::vector<char> inside(mesh.num_vertices());
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) inside[v] = (mesh.vertices[v] - centre).norm() <= radius;
  std::unordered_map<std::uint64_t, std::int32_t> on_edge;
  auto crossing = [&](std::int32_t a, std::int32_t b) {
    const auto lo = static_cast<std::uint64_t>(std::min(a, b));
    const auto hi = static_cast<std::uint64_t>(std::max(a, b));
    const auto [it, inserted] = on_edge.try_emplace((lo << 32) | hi, 0);
    if (inserted) {
      // From the lower index, so both triangles of the edge compute the same point.
      const Vec3& p = mesh.vertices[lo];
      const Vec3& q = mesh.vertices[hi];
      const double t = crossing_parameter(p, q, centre, radius, inside[lo] != 0);
      split.mesh.vertices.push_back(p + t * (q - p));
      it->second = static_cast<std::int32_t>(split.mesh.vertices.size() - 1);
    }
    return it->second;
  };
  split.mesh.triangles.reserve(mesh.num_triangles());
  for (const auto& tri : mesh.triangles) {
    const bool i0 = inside[static_cast<std::size_t>(tri[0])] != 0;
    const bool i1 = inside[static_cast<std::size_t>(tri[1])] != 0;
    const bool i2 = inside[static_cast<std::size_t>(tri[2])] != 0;
    if (i0 == i1 && i1 == i2) {
      split.mesh.triangles.push_back(tri);
      continue;
    }
    // The lone vertex L (its class differs from the other two), then A and B in winding order.
    const int lone = (i0 != i1 && i0 != i2) ? 0 : (i1 != i0 && i1 != i2) ? 1 : 2;
    const std::int32_t l = tri[lone];
    const std::int32_t a = tri[(lone + 1) % 3];
    const std::int32_t b = tri[(lone + 2) % 3];
    const std::int32_t p = crossing(l, a);
    const std::int32_t q = crossing(l, b);
    split.mesh.triangles.push_back({l, p, q});
    split.mesh.triangles.push_back({p, a, b});
    split.mesh.triangles.push_back({p, b, q});
  }
  return split;
}

}  // namespace hipfai::geometry
