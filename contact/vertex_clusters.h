// hipfai — a mobile mesh's vertices grouped into small spatial clusters, each with a bounding
// sphere, built once per body at rest. A rigid pose carries every sphere with its vertices, so a
// query that only needs the vertices near the fixed body decides a whole cluster with one test on
// its posed sphere (the leaf level of a bounding-volume hierarchy; FCL builds its hierarchy of the
// mobile body once too).
//
// The clusters are the leaves of a median split: a set of vertices larger than `cluster_size` is
// cut at the median of its bounding box's longest axis (the left part a multiple of cluster_size)
// and each side is cut again, so the clusters are compact and all but the last are full. Each
// sphere is centred on its cluster's bounding-box centre and its radius is the largest distance of
// a cluster vertex from it, rounded up by a relative 1e-12 (far above the rounding of that
// distance, so every vertex lies inside its sphere).
#pragma once

#include "geometry/tri_mesh.h"

#include <cstdint>
#include <span>
#include <vector>

namespace hipfai::contact {

struct VertexCluster {
  geometry::Vec3 centre = geometry::Vec3::Zero();  // mm, the mesh's frame at rest
  double radius_mm = 0.0;                          // every vertex of the cluster within it
  std::uint32_t first = 0, last = 0;               // its vertices: [first, last) of the ordering
};

class VertexClusters {
 public:
  VertexClusters() = default;
  // Clusters of `mesh`'s vertices (cluster_size >= 1). Throws hipfai::Error for a non-finite
  // coordinate or cluster_size 0.
  static VertexClusters build(const geometry::TriMesh& mesh, std::size_t cluster_size = 32);

  std::span<const VertexCluster> clusters() const { return clusters_; }
  std::size_t num_vertices() const { return vertices_.size(); }
  // The i-th vertex of the ordering (a copy of the mesh's coordinates) and its index in the mesh.
  const geometry::Vec3& vertex(std::size_t i) const { return vertices_[i]; }
  std::int32_t mesh_index(std::size_t i) const { return mesh_index_[i]; }

 private:
  std::vector<VertexCluster> clusters_;
  std::vector<geometry::Vec3> vertices_;
  std::vector<std::int32_t> mesh_index_;
};

}  // namespace hipfai::contact
