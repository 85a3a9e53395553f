// Exact inside/outside and distance tools for closed triangle surfaces, shared by the geometry
// tests as independent references (they never read generator parameters).
#pragma once

#include "geometry/tri_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace hipfai::geometry::test_support {

// Inside test by ray parity: a ray along +X from the query crosses a closed surface an odd
// number of times iff the query is inside. Triangles are bucketed by their (y, z) bounding box
// on a 1 mm grid, so each query meets only the triangles over its (y, z) cell.
class InsideTester {
 public:
  explicit InsideTester(const TriMesh& mesh) : mesh_(mesh), box_(bounding_box(mesh)) {
    cells_y_ = static_cast<int>(std::ceil(box_.extent().y() / kCellMm)) + 1;
    cells_z_ = static_cast<int>(std::ceil(box_.extent().z() / kCellMm)) + 1;
    buckets_.resize(static_cast<std::size_t>(cells_y_ * cells_z_));
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      double y0 = 1e300, y1 = -1e300, z0 = 1e300, z1 = -1e300;
      for (auto v : mesh.triangles[t]) {
        const Vec3& p = mesh.vertices[static_cast<std::size_t>(v)];
        y0 = std::min(y0, p.y()); y1 = std::max(y1, p.y());
        z0 = std::min(z0, p.z()); z1 = std::max(z1, p.z());
      }
      for (int iy = cell(y0, box_.min.y()); iy <= cell(y1, box_.min.y()); ++iy) {
        for (int iz = cell(z0, box_.min.z()); iz <= cell(z1, box_.min.z()); ++iz) {
          buckets_[static_cast<std::size_t>(iy * cells_z_ + iz)].push_back(t);
        }
      }
    }
  }

  bool inside(const Vec3& query) const {
    if ((query.array() < box_.min.array()).any() || (query.array() > box_.max.array()).any()) return false;
    // A tiny irrational offset keeps the ray off shared edges and vertices.
    const Vec3 q = query + Vec3(0.0, 1.234567e-7, 7.654321e-8);
    const int iy = std::clamp(cell(q.y(), box_.min.y()), 0, cells_y_ - 1);
    const int iz = std::clamp(cell(q.z(), box_.min.z()), 0, cells_z_ - 1);
    int crossings = 0;
    for (std::size_t t : buckets_[static_cast<std::size_t>(iy * cells_z_ + iz)]) {
      const auto& tri = mesh_.triangles[t];
      const Vec3& a = mesh_.vertices[static_cast<std::size_t>(tri[0])];
      const Vec3& b = mesh_.vertices[static_cast<std::size_t>(tri[1])];
      const Vec3& c = mesh_.vertices[static_cast<std::size_t>(tri[2])];
      // Barycentric test of (q.y, q.z) in the triangle projected on the YZ plane.
      const double d = (b.y() - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (b.z() - a.z());
      if (d == 0.0) continue;
      const double u = ((q.y() - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (q.z() - a.z())) / d;
      const double v = ((b.y() - a.y()) * (q.z() - a.z()) - (q.y() - a.y()) * (b.z() - a.z())) / d;
      if (u < 0.0 || v < 0.0 || u + v > 1.0) continue;
      const double x = a.x() + u * (b.x() - a.x()) + v * (c.x() - a.x());
      if (x > q.x()) ++crossings;
    }
    return crossings % 2 == 1;
  }

 private:
  static constexpr double kCellMm = 1.0;
  static int cell(double value, double origin) { return static_cast<int>((value - origin) / kCellMm); }
  const TriMesh& mesh_;
  BoundingBox box_;
  int cells_y_ = 0;
  int cells_z_ = 0;
  std::vector<std::vector<std::size_t>> buckets_;
};

// Winding number of `mesh` around `q` (1 inside, 0 outside for a closed outward surface).
inline double winding_number(const TriMesh& mesh, const Vec3& q) {
  double solid_angle = 0.0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[static_cast<std::size_t>(t[0])] - q;
    const Vec3 b = mesh.vertices[static_cast<std::size_t>(t[1])] - q;
    const Vec3 c = mesh.vertices[static_cast<std::size_t>(t[2])] - q;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    solid_angle += 2.0 * std::atan2(numerator, denominator);
  }
  return solid_angle / (4.0 * std::numbers::pi);
}

// Exact distance from `p` to the triangle (a, b, c) (closest point by Voronoi regions, Ericson 2005).
inline double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  }
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

inline double distance_to_surface(const TriMesh& mesh, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Triangle& t : mesh.triangles) {
    best = std::min(best, point_triangle_distance(p, mesh.vertices[static_cast<std::size_t>(t[0])],
                                                  mesh.vertices[static_cast<std::size_t>(t[1])],
                                                  mesh.vertices[static_cast<std::size_t>(t[2])]));
  }
  return best;
}

// Longest edge of the mesh, for discretisation tolerances.
inline double longest_edge(const TriMesh& mesh) {
  double longest = 0.0;
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      longest = std::max(longest, (mesh.vertices[static_cast<std::size_t>(t[k])] -
                                   mesh.vertices[static_cast<std::size_t>(t[(k + 1) % 3])]).norm());
    }
  }
  return longest;
}

}  // namespace hipfai::geometry::test_support
