// hipfai — a triangle mesh split into its connected parts (see mesh_parts.h).
#include "geometry/mesh_parts.h"

#include "core/disjoint_sets.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace hipfai::geometry {

std::vector<TriMesh> connected_parts(const TriMesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  DisjointSets sets(n);
  std::vector<char> used(n, 0);
  for (const Triangle& tri : mesh.triangles) {
    for (const std::int32_t v : tri) used[static_cast<std::size_t>(v)] = 1;
    sets.unite(static_cast<std::size_t>(tri[0]), static_cast<std::size_t>(tri[1]));
    sets.unite(static_cast<std::size_t>(tri[0]), static_cast<std::size_t>(tri[2]));
  }
  // Parts numbered in the order of their first triangle.
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::vector<std::size_t> part_of_root(n, kNone);
  std::vector<std::size_t> triangle_part(mesh.triangles.size());
  std::size_t parts = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::size_t root = sets.find(static_cast<std::size_t>(mesh.triangles[t][0]));
    if (part_of_root[root] == kNone) part_of_root[root] = parts++;
    triangle_part[t] = part_of_root[root];
  }
  const bool all_used = std::all_of(used.begin(), used.end(), [](char u) { return u != 0; });
  if (parts == 1 && all_used) return {mesh};

  std::vector<TriMesh> out(parts);
  std::vector<std::int32_t> renumbered(n, -1);
  for (std::size_t v = 0; v < n; ++v) {
    if (!used[v]) continue;
    TriMesh& part = out[part_of_root[sets.find(v)]];
    renumbered[v] = static_cast<std::int32_t>(part.vertices.size());
    part.vertices.push_back(mesh.vertices[v]);
    for (const auto& [name, values] : mesh.vertex_fields) {
      if (values.size() == n) part.vertex_fields[name].push_back(values[v]);
    }
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    out[triangle_part[t]].triangles.push_back({renumbered[static_cast<std::size_t>(tri[0])],
                                               renumbered[static_cast<std::size_t>(tri[1])],
                                               renumbered[static_cast<std::size_t>(tri[2])]});
  }
  return out;
}

}  // namespace hipfai::geometry
