#include "geometry/primitive_meshes.h"

#include "core/error.h"

#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace hipfai::geometry {

TriMesh make_octasphere(const Vec3& centre, double radius_mm, int levels) {
  if (levels < 0 || levels > 10) throw_error("octasphere: levels must be in 0..10, got ", levels);
  TriMesh mesh;
  mesh.vertices = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0),
                   Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  mesh.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                    {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto split = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoint.find(key);
      if (found != midpoint.end()) return found->second;
      const int index = static_cast<int>(mesh.vertices.size());
      mesh.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]).normalized());
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<Triangle> refined;
    refined.reserve(mesh.triangles.size() * 4);
    for (const Triangle& t : mesh.triangles) {
      const int ab = split(t[0], t[1]), bc = split(t[1], t[2]), ca = split(t[2], t[0]);
      refined.push_back({t[0], ab, ca});
      refined.push_back({ab, t[1], bc});
      refined.push_back({ca, bc, t[2]});
      refined.push_back({ab, bc, ca});
    }
    mesh.triangles = std::move(refined);
  }
  for (Vec3& p : mesh.vertices) p = centre + radius_mm * p;
  return mesh;
}

TriMesh make_box(const Vec3& min, const Vec3& max, int divisions) {
  if (divisions < 1) throw_error("box: divisions must be at least 1, got ", divisions);
  TriMesh mesh;
  std::map<std::array<int, 3>, int> index_of;  // integer lattice coordinate -> vertex
  const int n = divisions;
  auto vertex = [&](int i, int j, int k) {
    const std::array<int, 3> key{i, j, k};
    const auto found = index_of.find(key);
    if (found != index_of.end()) return found->second;
    const Vec3 t(static_cast<double>(i) / n, static_cast<double>(j) / n,
                 static_cast<double>(k) / n);
    const int index = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back(min + (max - min).cwiseProduct(t));
    index_of.emplace(key, index);
    return index;
  };
  // Each face: fixed axis `a` at side s (0 or n); (u, v) span the two other axes, ordered so
  // that u x v points outward.
  for (int a = 0; a < 3; ++a) {
    for (int side = 0; side <= 1; ++side) {
      const int u_axis = (a + 1) % 3, v_axis = (a + 2) % 3;
      for (int u = 0; u < n; ++u) {
        for (int v = 0; v < n; ++v) {
          auto corner = [&](int du, int dv) {
            std::array<int, 3> c{};
            c[a] = side * n;
            c[u_axis] = u + du;
            c[v_axis] = v + dv;
            return vertex(c[0], c[1], c[2]);
          };
          const int p00 = corner(0, 0), p10 = corner(1, 0), p11 = corner(1, 1),
                    p01 = corner(0, 1);
          if (side == 1) {
            mesh.triangles.push_back({p00, p10, p11});
            mesh.triangles.push_back({p00, p11, p01});
          } else {
            mesh.triangles.push_back({p00, p11, p10});
            mesh.triangles.push_back({p00, p01, p11});
          }
        }
      }
    }
  }
  return mesh;
}

TriMesh make_torus(const Vec3& centre, double major_radius_mm, double minor_radius_mm,
                   int n_major, int n_minor) {
  if (n_major < 3 || n_minor < 3) throw_error("torus: needs at least 3 x 3 segments");
  TriMesh mesh;
  const double two_pi = 2.0 * std::numbers::pi;
  for (int i = 0; i < n_major; ++i) {
    const double u = two_pi * i / n_major;
    for (int j = 0; j < n_minor; ++j) {
      const double v = two_pi * j / n_minor;
      const double ring = major_radius_mm + minor_radius_mm * std::cos(v);
      mesh.vertices.push_back(centre + Vec3(ring * std::cos(u), ring * std::sin(u),
                                            minor_radius_mm * std::sin(v)));
    }
  }
  auto at = [&](int i, int j) { return (i % n_major) * n_minor + (j % n_minor); };
  for (int i = 0; i < n_major; ++i) {
    for (int j = 0; j < n_minor; ++j) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return mesh;
}

}  // namespace hipfai::geometry
