#include "geometry/tri_mesh.h"

#include "core/error.h"
#include "core/hash.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace hipfai::geometry {

BoundingBox bounding_box(const TriMesh& mesh) {
  BoundingBox box;
  if (mesh.vertices.empty()) return box;
  box.min = box.max = mesh.vertices.front();
  for (const Vec3& p : mesh.vertices) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

Vec3 triangle_area_normal(const TriMesh& mesh, std::size_t t) {
  const Triangle& tri = mesh.triangles[t];
  const Vec3& a = mesh.vertices[tri[0]];
  return (mesh.vertices[tri[1]] - a).cross(mesh.vertices[tri[2]] - a);
}

Vec3 triangle_unit_normal(const TriMesh& mesh, std::size_t t) {
  const Vec3 n = triangle_area_normal(mesh, t);
  const double length = n.norm();
  return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
}

double triangle_area(const TriMesh& mesh, std::size_t t) {
  return 0.5 * triangle_area_normal(mesh, t).norm();
}

bool triangles_share_a_vertex(const TriMesh& mesh, std::int32_t a, std::int32_t b) {
  for (const auto i : mesh.triangles[static_cast<std::size_t>(a)]) {
    for (const auto j : mesh.triangles[static_cast<std::size_t>(b)]) {
      if (i == j) return true;
    }
  }
  return false;
}

double mean_edge_length(const TriMesh& mesh) {
  // Each undirected edge counted once, at its first appearance in triangle order (the order of
  // the sum, so the result does not depend on how duplicates are found). Duplicates are found by
  // buckets on the lower vertex, sorted per bucket: linear in the mesh, no hashing.
  const std::size_t num_half = 3 * mesh.triangles.size();
  const std::size_t num_vertices = mesh.vertices.size();
  std::vector<std::uint32_t> start(num_vertices + 1, 0);
  const auto ends = [&](std::size_t h) {
    const Triangle& tri = mesh.triangles[h / 3];
    const auto a = static_cast<std::uint32_t>(tri[h % 3]), b = static_cast<std::uint32_t>(tri[(h % 3 + 1) % 3]);
    return std::pair{std::min(a, b), std::max(a, b)};
  };
  for (std::size_t h = 0; h < num_half; ++h) ++start[ends(h).first + 1];
  for (std::size_t v = 0; v < num_vertices; ++v) start[v + 1] += start[v];
  std::vector<std::pair<std::uint32_t, std::uint32_t>> bucket(num_half);  // (upper vertex, half-edge)
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t h = 0; h < num_half; ++h) {
    const auto [lo, hi] = ends(h);
    bucket[fill[lo]++] = {hi, static_cast<std::uint32_t>(h)};
  }
  std::vector<std::uint8_t> first(num_half, 0);
  for (std::size_t v = 0; v < num_vertices; ++v) {
    const auto begin = bucket.begin() + start[v], end = bucket.begin() + start[v + 1];
    std::sort(begin, end);
    for (auto it = begin; it != end; ++it) {
      if (it == begin || it->first != (it - 1)->first) first[it->second] = 1;
    }
  }
  double total = 0.0;
  std::size_t count = 0;
  for (std::size_t h = 0; h < num_half; ++h) {
    if (!first[h]) continue;
    const Triangle& tri = mesh.triangles[h / 3];
    total += (mesh.vertices[static_cast<std::size_t>(tri[h % 3])] -
              mesh.vertices[static_cast<std::size_t>(tri[(h % 3 + 1) % 3])])
                 .norm();
    ++count;
  }
  return count ? total / static_cast<double>(count) : 0.0;
}

double surface_area(const TriMesh& mesh) {
  double area = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) area += triangle_area(mesh, t);
  return area;
}

double signed_volume(const TriMesh& mesh) {
  double six_volume = 0.0;
  for (const Triangle& tri : mesh.triangles) {
    six_volume += mesh.vertices[tri[0]].dot(mesh.vertices[tri[1]].cross(mesh.vertices[tri[2]]));
  }
  return six_volume / 6.0;
}

void apply_transform(TriMesh& mesh, const Eigen::Isometry3d& transform) {
  for (Vec3& p : mesh.vertices) p = transform * p;
}

void rotate_about_axis(TriMesh& mesh, const Vec3& centre, const Vec3& axis_unit,
                       double angle_rad) {
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(angle_rad, axis_unit).toRotationMatrix();
  for (Vec3& p : mesh.vertices) p = centre + rotation * (p - centre);
}

TriMesh merge_meshes(const std::vector<const TriMesh*>& parts) {
  TriMesh out;
  for (const TriMesh* part : parts) {
    const auto offset = static_cast<std::int32_t>(out.vertices.size());
    out.vertices.insert(out.vertices.end(), part->vertices.begin(), part->vertices.end());
    for (const Triangle& tri : part->triangles) {
      out.triangles.push_back({tri[0] + offset, tri[1] + offset, tri[2] + offset});
    }
  }
  if (parts.empty()) return out;
  for (const auto& field_of_first : parts.front()->vertex_fields) {
    const std::string& name = field_of_first.first;  // not a structured binding: lambdas capture it (clang 14)
    const bool everywhere = std::all_of(parts.begin(), parts.end(), [&](const TriMesh* part) {
      return part->vertex_fields.count(name) != 0;
    });
    if (!everywhere) continue;
    std::vector<double>& merged = out.vertex_fields[name];
    for (const TriMesh* part : parts) {
      const auto& field = part->vertex_fields.at(name);
      merged.insert(merged.end(), field.begin(), field.end());
    }
  }
  return out;
}

std::string mesh_hash(const TriMesh& mesh) {
  Hasher hasher;
  hasher.add(std::string_view(reinterpret_cast<const char*>(mesh.vertices.data()),
                              mesh.vertices.size() * sizeof(Vec3)));
  hasher.add(std::string_view(reinterpret_cast<const char*>(mesh.triangles.data()),
                              mesh.triangles.size() * sizeof(Triangle)));
  return hasher.hex();
}

void validate_mesh(const TriMesh& mesh, const std::string& what) {
  if (mesh.vertices.empty()) throw_error(what, ": mesh has no vertices");
  if (mesh.triangles.empty()) throw_error(what, ": mesh has no triangles");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) {
      throw_error(what, ": vertex ", i, " has a non-finite coordinate (NaN or Inf)");
    }
  }
  const auto n = static_cast<std::int64_t>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::int32_t index : mesh.triangles[t]) {
      if (index < 0 || index >= n) {
        throw_error(what, ": triangle ", t, " refers to vertex ", index, " but the mesh has ", n,
                    " vertices");
      }
    }
  }
  for (const auto& [name, values] : mesh.vertex_fields) {
    if (values.size() != mesh.vertices.size()) {
      throw_error(what, ": field '", name, "' has ", values.size(), " values for ", n,
                  " vertices");
    }
  }
}

}  // namespace hipfai::geometry
