#include "geometry/mesh_check.h"

#include "core/disjoint_sets.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace hipfai::geometry {
namespace {

struct EdgeUse {
  std::uint64_t key;  // (min << 32) | max of the two vertex indices
  bool forward;       // traversed from the smaller index to the larger
};

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

bool has_repeated_index(const Triangle& tri) {
  return tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2];
}

// Angle at corner p between the edges to q and r, radians, in [0, pi].
double corner_angle(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 u = q - p;
  const Vec3 v = r - p;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

void count_edges(const TriMesh& mesh, MeshReport& report) {
  std::vector<EdgeUse> uses;
  uses.reserve(3 * mesh.triangles.size());
  for (const Triangle& tri : mesh.triangles) {
    const bool repeated = has_repeated_index(tri);
    std::uint64_t emitted[3];
    int emitted_count = 0;
    for (int e = 0; e < 3; ++e) {
      const auto a = static_cast<std::uint32_t>(tri[e]);
      const auto b = static_cast<std::uint32_t>(tri[(e + 1) % 3]);
      if (a == b) continue;
      const std::uint64_t key = edge_key(a, b);
      // (a, b, a) names the edge a-b twice; it is one edge of one (degenerate) triangle.
      if (repeated && std::find(emitted, emitted + emitted_count, key) != emitted + emitted_count) {
        continue;
      }
      emitted[emitted_count++] = key;
      uses.push_back({key, a < b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) { return x.key < y.key; });
  double total_length = 0.0;
  for (std::size_t begin = 0; begin < uses.size();) {
    std::size_t end = begin + 1;
    while (end < uses.size() && uses[end].key == uses[begin].key) ++end;
    const std::size_t count = end - begin;
    ++report.num_edges;
    const auto a = static_cast<std::size_t>(uses[begin].key >> 32);
    const auto b = static_cast<std::size_t>(uses[begin].key & 0xffffffffu);
    total_length += (mesh.vertices[a] - mesh.vertices[b]).norm();
    if (count == 1) {
      ++report.boundary_edges;
    } else if (count == 2) {
      if (uses[begin].forward == uses[begin + 1].forward) ++report.inconsistent_edges;
    } else {
      ++report.non_manifold_edges;
    }
    begin = end;
  }
  report.mean_edge_length_mm =
      report.num_edges ? total_length / static_cast<double>(report.num_edges) : 0.0;
}

void count_triangle_quality(const TriMesh& mesh, MeshReport& report) {
  constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    if (has_repeated_index(tri)) {
      ++report.degenerate_triangles;
      continue;
    }
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(tri[0])];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(tri[1])];
    const Vec3& c = mesh.vertices[static_cast<std::size_t>(tri[2])];
    const double longest_squared =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    const double twice_area = (b - a).cross(c - a).norm();
    if (twice_area <= 16.0 * kEpsilon * longest_squared) {
      ++report.degenerate_triangles;
      continue;
    }
    const double min_angle =
        std::min({corner_angle(a, b, c), corner_angle(b, c, a), corner_angle(c, a, b)});
    if (min_angle < kSliverAngleRad) ++report.sliver_triangles;
  }

  std::vector<Triangle> sorted = mesh.triangles;
  for (Triangle& tri : sorted) std::sort(tri.begin(), tri.end());
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t t = 1; t < sorted.size(); ++t) {
    if (sorted[t] == sorted[t - 1]) ++report.duplicate_triangles;
  }
}

void count_components(const TriMesh& mesh, MeshReport& report) {
  DisjointSets sets(mesh.vertices.size());
  std::vector<bool> referenced(mesh.vertices.size(), false);
  for (const Triangle& tri : mesh.triangles) {
    for (const std::int32_t index : tri) referenced[static_cast<std::size_t>(index)] = true;
    sets.unite(static_cast<std::size_t>(tri[0]), static_cast<std::size_t>(tri[1]));
    sets.unite(static_cast<std::size_t>(tri[1]), static_cast<std::size_t>(tri[2]));
  }
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!referenced[v]) {
      ++report.unreferenced_vertices;
    } else if (sets.find(v) == v) {
      ++report.connected_components;
    }
  }
}

// A vertex is manifold when the edges opposite it in its triangles (its link) form one path or
// one cycle: every link vertex has degree at most 2 and the link is connected.
void count_non_manifold_vertices(const TriMesh& mesh, MeshReport& report) {
  const std::size_t n = mesh.vertices.size();
  std::vector<std::size_t> start(n + 1, 0);
  for (const Triangle& tri : mesh.triangles) {
    if (has_repeated_index(tri)) continue;
    for (const std::int32_t index : tri) ++start[static_cast<std::size_t>(index) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::size_t> incident(start.back());
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    if (has_repeated_index(tri)) continue;
    for (const std::int32_t index : tri) incident[fill[static_cast<std::size_t>(index)]++] = t;
  }

  std::vector<std::int32_t> link_vertices;
  std::vector<int> degree;
  DisjointSets link_pieces;
  std::vector<std::pair<std::size_t, std::size_t>> link_edges;
  for (std::size_t v = 0; v < n; ++v) {
    if (start[v] == start[v + 1]) continue;
    // The link's vertices, numbered locally (sorted, so lookups stay O(log degree) even at
    // the pole of a fan with thousands of triangles).
    link_vertices.clear();
    for (std::size_t k = start[v]; k < start[v + 1]; ++k) {
      for (const std::int32_t id : mesh.triangles[incident[k]]) {
        if (id != static_cast<std::int32_t>(v)) link_vertices.push_back(id);
      }
    }
    std::sort(link_vertices.begin(), link_vertices.end());
    link_vertices.erase(std::unique(link_vertices.begin(), link_vertices.end()), link_vertices.end());
    auto local = [&](std::int32_t id) {
      return static_cast<std::size_t>(
          std::lower_bound(link_vertices.begin(), link_vertices.end(), id) - link_vertices.begin());
    };
    link_edges.clear();
    for (std::size_t k = start[v]; k < start[v + 1]; ++k) {
      const Triangle& tri = mesh.triangles[incident[k]];
      const int corner = tri[0] == static_cast<std::int32_t>(v)   ? 0
                         : tri[1] == static_cast<std::int32_t>(v) ? 1
                                                                  : 2;
      link_edges.emplace_back(local(tri[(corner + 1) % 3]), local(tri[(corner + 2) % 3]));
    }
    degree.assign(link_vertices.size(), 0);
    link_pieces.reset(link_vertices.size());
    for (const auto& [a, b] : link_edges) {
      ++degree[a];
      ++degree[b];
      link_pieces.unite(a, b);
    }
    std::size_t roots = 0;
    for (std::size_t i = 0; i < link_vertices.size(); ++i) roots += link_pieces.find(i) == i ? 1 : 0;
    const bool branching = std::any_of(degree.begin(), degree.end(), [](int d) { return d > 2; });
    if (roots > 1 || branching) ++report.non_manifold_vertices;
  }
}

}  // namespace

std::optional<std::vector<std::int32_t>> closed_shell_labels(std::span<const Triangle> triangles) {
  struct DirectedEdge {
    std::uint64_t key;
    bool forward;
    std::uint32_t triangle;
  };
  std::vector<DirectedEdge> edges;
  edges.reserve(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Triangle& tri = triangles[t];
    if (has_repeated_index(tri) || tri[0] < 0 || tri[1] < 0 || tri[2] < 0) return std::nullopt;
    for (int e = 0; e < 3; ++e) {
      const auto a = static_cast<std::uint32_t>(tri[e]);
      const auto b = static_cast<std::uint32_t>(tri[(e + 1) % 3]);
      edges.push_back({edge_key(a, b), a < b, static_cast<std::uint32_t>(t)});
    }
  }
  std::sort(edges.begin(), edges.end(),
            [](const DirectedEdge& x, const DirectedEdge& y) { return x.key < y.key; });
  DisjointSets sets(triangles.size());
  for (std::size_t i = 0; i < edges.size(); i += 2) {
    // Each edge exactly twice, once each way.
    if (i + 1 >= edges.size() || edges[i + 1].key != edges[i].key || edges[i].forward == edges[i + 1].forward ||
        (i + 2 < edges.size() && edges[i + 2].key == edges[i].key)) {
      return std::nullopt;
    }
    sets.unite(edges[i].triangle, edges[i + 1].triangle);
  }
  std::vector<std::int32_t> labels(triangles.size());
  std::vector<std::int32_t> label_of_root(triangles.size(), -1);
  std::int32_t count = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    std::int32_t& label = label_of_root[sets.find(t)];
    if (label < 0) label = count++;
    labels[t] = label;
  }
  return labels;
}

MeshReport check_mesh(const TriMesh& mesh) {
  MeshReport report;
  report.num_vertices = mesh.num_vertices();
  report.num_triangles = mesh.num_triangles();
  if (mesh.vertices.empty()) return report;
  report.bounds = bounding_box(mesh);
  report.surface_area_mm2 = surface_area(mesh);
  report.signed_volume_mm3 = signed_volume(mesh);
  count_edges(mesh, report);
  count_triangle_quality(mesh, report);
  count_components(mesh, report);
  count_non_manifold_vertices(mesh, report);
  report.closed = !mesh.triangles.empty() && report.boundary_edges == 0;
  report.orientation_consistent = !mesh.triangles.empty() && report.inconsistent_edges == 0;
  report.outward = report.closed && report.orientation_consistent && report.signed_volume_mm3 > 0.0;
  report.watertight_manifold = report.closed && report.orientation_consistent &&
                               report.non_manifold_edges == 0 && report.non_manifold_vertices == 0 &&
                               report.degenerate_triangles == 0 && report.duplicate_triangles == 0;
  return report;
}

}  // namespace hipfai::geometry
