#include "fem/rigid_mesh_surface.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace hipfai::fem {

using geometry::Vec3;

namespace {

constexpr int kLeafSize = 4;  // triangles per BVH leaf: a few exact tests beat another box test

double box_distance_sq(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double excess = std::max({lo[k] - p[k], 0.0, p[k] - hi[k]});
    d2 += excess * excess;
  }
  return d2;
}

MeshClosestPoint at_vertex(const Vec3& point, int index) {
  MeshClosestPoint hit;
  hit.feature = TriangleFeature::kVertex;
  hit.index = index;
  hit.point_mm = point;
  return hit;
}

MeshClosestPoint on_edge(const Vec3& from, const Vec3& to, double t, int index) {
  MeshClosestPoint hit;
  hit.feature = TriangleFeature::kEdge;
  hit.index = index;
  hit.point_mm = from + t * (to - from);
  return hit;
}

}  // namespace

MeshClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                           const Vec3& c) {
  // Classify p against the Voronoi regions of the vertices, then the edges, else the face;
  // the d_i are the projections of p - vertex on the two edge vectors at a.
  const Vec3 ab = b - a, ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  MeshClosestPoint hit;
  if (d1 <= 0.0 && d2 <= 0.0) {
    hit = at_vertex(a, 0);
  } else {
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    const double vc = d1 * d4 - d3 * d2;  // barycentric numerators (signed sub-areas)
    const double vb = d5 * d2 - d1 * d6;
    const double va = d3 * d6 - d5 * d4;
    if (d3 >= 0.0 && d4 <= d3) {
      hit = at_vertex(b, 1);
    } else if (d6 >= 0.0 && d5 <= d6) {
      hit = at_vertex(c, 2);
    } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
      hit = on_edge(a, b, d1 / (d1 - d3), 0);
    } else if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
      hit = on_edge(b, c, (d4 - d3) / ((d4 - d3) + (d5 - d6)), 1);
    } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
      hit = on_edge(a, c, d2 / (d2 - d6), 2);
    } else {
      const double denominator = va + vb + vc;
      if (!(std::abs(denominator) > 0.0)) {
        hit = at_vertex(a, 0);  // fully degenerate: every point is as good
      } else {
        hit.feature = TriangleFeature::kFace;
        hit.point_mm = a + ab * (vb / denominator) + ac * (vc / denominator);
      }
    }
  }
  hit.distance_mm = (p - hit.point_mm).norm();
  return hit;
}

RigidMeshSurface::RigidMeshSurface(const geometry::TriMesh& mesh, const std::string& what)
    : vertices_(mesh.vertices), triangles_(mesh.triangles) {
  geometry::validate_mesh(mesh, what);
  if (triangles_.empty()) throw_error(what, ": no triangles (a rigid contact surface needs some)");
  const geometry::BoundingBox box = geometry::bounding_box(mesh);
  // Distances this far below the model size are round-off of the closest-point arithmetic.
  on_surface_mm_ = 1e-9 * (box.max - box.min).norm();

  face_normals_.resize(triangles_.size());
  vertex_normals_.assign(vertices_.size(), Vec3::Zero());
  std::map<std::pair<int, int>, Vec3> edge_sum;
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Vec3 area_normal = geometry::triangle_area_normal(mesh, t);
    if (!(area_normal.norm() > 0.0)) {
      throw_error(what, ": triangle ", t, " has zero area (no normal for contact)");
    }
    face_normals_[t] = area_normal.normalized();
    const auto& tri = triangles_[t];
    for (int k = 0; k < 3; ++k) {
      const Vec3& here = vertices_[tri[k]];
      const Vec3 e1 = (vertices_[tri[(k + 1) % 3]] - here).normalized();
      const Vec3 e2 = (vertices_[tri[(k + 2) % 3]] - here).normalized();
      const double angle = std::acos(std::clamp(e1.dot(e2), -1.0, 1.0));
      vertex_normals_[tri[k]] += angle * face_normals_[t];
      const int i = tri[k], j = tri[(k + 1) % 3];
      // try_emplace with an explicit zero: Eigen's default constructor leaves the vector
      // uninitialised.
      edge_sum.try_emplace({std::min(i, j), std::max(i, j)}, Vec3::Zero()).first->second +=
          face_normals_[t];
    }
  }
  for (Vec3& n : vertex_normals_) {
    if (n.norm() > 0.0) n.normalize();
  }
  edge_normals_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    for (int k = 0; k < 3; ++k) {
      const int i = tri[k], j = tri[(k + 1) % 3];
      const Vec3 sum = edge_sum.at({std::min(i, j), std::max(i, j)});
      // A knife edge (two opposite faces) has no pseudo-normal: fall back to this face's.
      edge_normals_[t][k] = sum.norm() > 1e-12 ? Vec3(sum.normalized()) : face_normals_[t];
    }
  }

  order_.resize(triangles_.size());
  for (std::size_t t = 0; t < order_.size(); ++t) order_[t] = static_cast<int>(t);
  nodes_.reserve(2 * triangles_.size() / kLeafSize + 2);
  build(0, static_cast<int>(order_.size()));
}

int RigidMeshSurface::build(int first, int count) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  Vec3 centroid_lo = lo, centroid_hi = hi;
  for (int i = first; i < first + count; ++i) {
    const auto& tri = triangles_[order_[i]];
    Vec3 centroid = Vec3::Zero();
    for (const int v : tri) {
      lo = lo.cwiseMin(vertices_[v]);
      hi = hi.cwiseMax(vertices_[v]);
      centroid += vertices_[v] / 3.0;
    }
    centroid_lo = centroid_lo.cwiseMin(centroid);
    centroid_hi = centroid_hi.cwiseMax(centroid);
  }
  nodes_[index].box_min = lo;
  nodes_[index].box_max = hi;
  if (count <= kLeafSize) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  int axis = 0;
  (centroid_hi - centroid_lo).maxCoeff(&axis);
  const int half = count / 2;
  const auto centroid_on_axis = [&](int t) {
    const auto& tri = triangles_[t];
    return vertices_[tri[0]][axis] + vertices_[tri[1]][axis] + vertices_[tri[2]][axis];
  };
  std::nth_element(order_.begin() + first, order_.begin() + first + half,
                   order_.begin() + first + count,
                   [&](int a, int b) { return centroid_on_axis(a) < centroid_on_axis(b); });
  const int left = build(first, half);
  const int right = build(first + half, count - half);
  nodes_[index].first = left;
  nodes_[index].count = 0;
  nodes_[index].right = right;
  return index;
}

void RigidMeshSurface::finish(const Vec3& query, MeshClosestPoint& hit) const {
  const auto& tri = triangles_[hit.triangle];
  Vec3 pseudo_normal = face_normals_[hit.triangle];
  if (hit.feature == TriangleFeature::kEdge) pseudo_normal = edge_normals_[hit.triangle][hit.index];
  if (hit.feature == TriangleFeature::kVertex) pseudo_normal = vertex_normals_[tri[hit.index]];
  const Vec3 offset = query - hit.point_mm;
  // Baerentzen & Aanaes (2005): the sign of offset . pseudo-normal at the closest feature tells
  // inside from outside for a closed, consistently oriented mesh.
  hit.inside = offset.dot(pseudo_normal) < 0.0;
  if (hit.feature == TriangleFeature::kFace || hit.distance_mm <= on_surface_mm_) {
    hit.normal = hit.feature == TriangleFeature::kFace ? face_normals_[hit.triangle] : pseudo_normal;
  } else {
    // On an edge or vertex the gap direction is the offset itself (the normal of the rounded
    // offset surface), pointing outward whether the query is inside or outside.
    hit.normal = (hit.inside ? -offset : offset) / hit.distance_mm;
  }
}

MeshClosestPoint RigidMeshSurface::closest(const Vec3& query) const {
  MeshClosestPoint best;
  double best_sq = std::numeric_limits<double>::infinity();
  // Depth-first, nearer child first, pruned by the box distance: exact nearest triangle.
  std::vector<int> stack;
  stack.reserve(64);
  stack.push_back(0);
  while (!stack.empty()) {
    const Node& node = nodes_[stack.back()];
    stack.pop_back();
    if (box_distance_sq(query, node.box_min, node.box_max) >= best_sq) continue;
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const auto& tri = triangles_[order_[i]];
        MeshClosestPoint hit =
            closest_point_on_triangle(query, vertices_[tri[0]], vertices_[tri[1]], vertices_[tri[2]]);
        const double d2 = hit.distance_mm * hit.distance_mm;
        if (d2 < best_sq) {
          best_sq = d2;
          best = hit;
          best.triangle = order_[i];
        }
      }
      continue;
    }
    const Node& left = nodes_[node.first];
    const Node& right = nodes_[node.right];
    const double d_left = box_distance_sq(query, left.box_min, left.box_max);
    const double d_right = box_distance_sq(query, right.box_min, right.box_max);
    // Push the farther child first so the nearer one is searched first.
    if (d_left < d_right) {
      stack.push_back(node.right);
      stack.push_back(node.first);
    } else {
      stack.push_back(node.first);
      stack.push_back(node.right);
    }
  }
  finish(query, best);
  return best;
}

MeshClosestPoint RigidMeshSurface::closest_brute_force(const Vec3& query) const {
  MeshClosestPoint best;
  best.distance_mm = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    MeshClosestPoint hit =
        closest_point_on_triangle(query, vertices_[tri[0]], vertices_[tri[1]], vertices_[tri[2]]);
    if (hit.distance_mm < best.distance_mm) {
      best = hit;
      best.triangle = static_cast<int>(t);
    }
  }
  finish(query, best);
  return best;
}

SurfacePoint RigidMeshSurface::closest_point(const dealii::Point<3>& query_mm) const {
  const MeshClosestPoint hit = closest(Vec3(query_mm[0], query_mm[1], query_mm[2]));
  SurfacePoint out;
  for (unsigned int k = 0; k < 3; ++k) {
    out.point_mm[k] = hit.point_mm[k];
    out.normal[k] = hit.normal[k];
  }
  return out;
}

}  // namespace hipfai::fem
