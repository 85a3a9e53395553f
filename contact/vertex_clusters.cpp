#include "contact/vertex_clusters.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hipfai::contact {
namespace {

// Splits order[first, last) at the median of its bounding box's longest axis until each part
// holds at most `size` vertices; appends the parts in order.
void split(const std::vector<geometry::Vec3>& points, std::vector<std::int32_t>& order, std::size_t first,
           std::size_t last, std::size_t size, std::vector<std::pair<std::size_t, std::size_t>>& parts) {
  if (last - first <= size) {
    parts.emplace_back(first, last);
    return;
  }
  geometry::Vec3 lo = points[static_cast<std::size_t>(order[first])], hi = lo;
  for (std::size_t i = first; i < last; ++i) {
    lo = lo.cwiseMin(points[static_cast<std::size_t>(order[i])]);
    hi = hi.cwiseMax(points[static_cast<std::size_t>(order[i])]);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  // A multiple of `size` on the left keeps every part but the last full.
  const std::size_t half = (last - first + 1) / 2;
  const std::size_t middle = first + std::max(size, (half + size - 1) / size * size);
  std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(first), order.begin() + static_cast<std::ptrdiff_t>(middle),
                   order.begin() + static_cast<std::ptrdiff_t>(last), [&](std::int32_t a, std::int32_t b) {
                     const double pa = points[static_cast<std::size_t>(a)][axis], pb = points[static_cast<std::size_t>(b)][axis];
                     return pa < pb || (pa == pb && a < b);
                   });
  split(points, order, first, middle, size, parts);
  split(points, order, middle, last, size, parts);
}

}  // namespace

VertexClusters VertexClusters::build(const geometry::TriMesh& mesh, std::size_t cluster_size) {
  if (cluster_size == 0) throw_error("vertex clusters: the cluster size must be at least 1");
  for (const geometry::Vec3& p : mesh.vertices) {
    if (!p.allFinite()) throw_error("vertex clusters: the mesh has a non-finite coordinate");
  }
  VertexClusters out;
  const std::size_t n = mesh.vertices.size();
  if (n == 0) return out;
  std::vector<std::int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::vector<std::pair<std::size_t, std::size_t>> parts;
  split(mesh.vertices, order, 0, n, cluster_size, parts);
  out.vertices_.resize(n);
  out.mesh_index_ = order;
  for (std::size_t i = 0; i < n; ++i) out.vertices_[i] = mesh.vertices[static_cast<std::size_t>(order[i])];
  for (const auto& [first, last] : parts) {
    geometry::Vec3 box_lo = out.vertices_[first], box_hi = out.vertices_[first];
    for (std::size_t i = first; i < last; ++i) {
      box_lo = box_lo.cwiseMin(out.vertices_[i]);
      box_hi = box_hi.cwiseMax(out.vertices_[i]);
    }
    VertexCluster cluster;
    cluster.centre = 0.5 * (box_lo + box_hi);
    for (std::size_t i = first; i < last; ++i) {
      cluster.radius_mm = std::max(cluster.radius_mm, (out.vertices_[i] - cluster.centre).norm());
    }
    cluster.radius_mm *= 1.0 + 1e-12;
    cluster.first = static_cast<std::uint32_t>(first);
    cluster.last = static_cast<std::uint32_t>(last);
    out.clusters_.push_back(cluster);
  }
  return out;
}

}  // namespace hipfai::contact
