// hipfai — cartilage and labrum synthesised on segmented bones (see soft_tissue.h for the method).
#include "anatomy/soft_tissue.h"

#include "core/error.h"
#include "core/stopwatch.h"
#include "geometry/hip_frame.h"
#include "geometry/hjc_regions.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <functional>
#include <cmath>
#include <numbers>
#include <numeric>
#include <array>
#include <limits>
#include <map>
#include <optional>
#include <unordered_map>

namespace hipfai::anatomy {
namespace {

using geometry::Triangle;
using geometry::TriMesh;
using geometry::Vec3;

using Kernel = CGAL::Simple_cartesian<double>;
using CgalTriangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<CgalTriangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using TriangleTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 to_point(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

// Where a ray meets a mesh: distance from its origin, the triangle, and the barycentric weights
// of the triangle's corners at the hit.
struct RayHit {
  double distance = 0.0;
  std::size_t triangle = 0;
  Vec3 weights = Vec3::Zero();
};

// Ray casts and inside tests against one closed mesh (CGAL AABB tree of its triangles).
class MeshQueries {
 public:
  explicit MeshQueries(const TriMesh& mesh) : mesh_(mesh) {
    triangles_.reserve(mesh.triangles.size());
    for (const Triangle& t : mesh.triangles) {
      triangles_.emplace_back(to_point(vertex(t[0])), to_point(vertex(t[1])), to_point(vertex(t[2])));
    }
    tree_.insert(triangles_.begin(), triangles_.end());
    tree_.build();
  }

  std::optional<RayHit> first_hit(const Vec3& origin, const Vec3& direction) const {
    const Kernel::Ray_3 ray(to_point(origin), to_point(origin + direction));
    const auto hit = tree_.first_intersection(ray);
    if (!hit) return std::nullopt;
    const Kernel::Point_3* point = boost::get<Kernel::Point_3>(&hit->first);
    if (point == nullptr) return std::nullopt;  // the ray runs along a triangle: treat as a miss
    RayHit out;
    out.triangle = static_cast<std::size_t>(hit->second - triangles_.begin());
    const Vec3 p(point->x(), point->y(), point->z());
    out.distance = (p - origin).norm();
    const Triangle& t = mesh_.triangles[out.triangle];
    const Vec3 a = vertex(t[0]), b = vertex(t[1]), c = vertex(t[2]);
    const Vec3 n = (b - a).cross(c - a);
    const double area2 = n.squaredNorm();
    if (area2 > 0.0) {
      out.weights.x() = (b - p).cross(c - p).dot(n) / area2;
      out.weights.y() = (c - p).cross(a - p).dot(n) / area2;
      out.weights.z() = 1.0 - out.weights.x() - out.weights.y();
    } else {
      out.weights = Vec3::Constant(1.0 / 3.0);
    }
    return out;
  }

  // Ray parity along three fixed, unrelated directions, majority vote (a ray grazing an edge
  // miscounts at most one of them).
  bool inside(const Vec3& p) const {
    static const Vec3 kDirections[3] = {Vec3(0.5773, 0.5801, 0.5746).normalized(),
                                        Vec3(-0.3131, 0.8712, -0.3781).normalized(),
                                        Vec3(0.7071, -0.1234, -0.6963).normalized()};
    int votes = 0;
    for (const Vec3& d : kDirections) {
      const Kernel::Ray_3 ray(to_point(p), to_point(p + d));
      if (tree_.number_of_intersected_primitives(ray) % 2 == 1) ++votes;
    }
    return votes >= 2;
  }

 private:
  const Vec3& vertex(std::int32_t i) const { return mesh_.vertices[static_cast<std::size_t>(i)]; }
  const TriMesh& mesh_;
  std::vector<CgalTriangle> triangles_;
  TriangleTree tree_;
};

std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
  return (hi << 32) | lo;
}

// The triangles across each edge of a mesh.
class EdgeAdjacency {
 public:
  explicit EdgeAdjacency(const TriMesh& mesh) {
    edges_.reserve(mesh.triangles.size() * 2);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      for (int k = 0; k < 3; ++k) edges_[edge_key(tri[k], tri[(k + 1) % 3])].push_back(static_cast<std::int32_t>(t));
    }
  }
  const std::vector<std::int32_t>& across(std::int32_t a, std::int32_t b) const {
    static const std::vector<std::int32_t> kNone;
    const auto it = edges_.find(edge_key(a, b));
    return it == edges_.end() ? kNone : it->second;
  }

 private:
  std::unordered_map<std::uint64_t, std::vector<std::int32_t>> edges_;
};

// Connected groups (through shared edges) of the triangles with in[t]; labels -1 elsewhere.
std::vector<std::int32_t> components(const TriMesh& mesh, const EdgeAdjacency& adjacency, const std::vector<char>& in,
                                     int* count) {
  std::vector<std::int32_t> label(mesh.triangles.size(), -1);
  int next = 0;
  std::vector<std::int32_t> stack;
  for (std::size_t seed = 0; seed < mesh.triangles.size(); ++seed) {
    if (!in[seed] || label[seed] >= 0) continue;
    label[seed] = next;
    stack.assign(1, static_cast<std::int32_t>(seed));
    while (!stack.empty()) {
      const std::int32_t t = stack.back();
      stack.pop_back();
      const Triangle& tri = mesh.triangles[static_cast<std::size_t>(t)];
      for (int k = 0; k < 3; ++k) {
        for (std::int32_t u : adjacency.across(tri[k], tri[(k + 1) % 3])) {
          if (in[static_cast<std::size_t>(u)] && label[static_cast<std::size_t>(u)] < 0) {
            label[static_cast<std::size_t>(u)] = next;
            stack.push_back(u);
          }
        }
      }
    }
    ++next;
  }
  *count = next;
  return label;
}

// Keeps only the largest (by area) group of the triangles in `in`.
void keep_largest(const TriMesh& mesh, const EdgeAdjacency& adjacency, std::vector<char>& in) {
  int count = 0;
  const auto label = components(mesh, adjacency, in, &count);
  if (count <= 1) return;
  std::vector<double> area(static_cast<std::size_t>(count), 0.0);
  for (std::size_t t = 0; t < label.size(); ++t) {
    if (label[t] >= 0) area[static_cast<std::size_t>(label[t])] += geometry::triangle_area(mesh, t);
  }
  const auto best = static_cast<std::int32_t>(std::max_element(area.begin(), area.end()) - area.begin());
  for (std::size_t t = 0; t < label.size(); ++t) in[t] = label[t] == best;
}

// A patch of a closed mesh made a manifold surface with boundary (see the header: largest part,
// small holes filled, pinched vertices removed). Returns the triangle mask.
std::vector<char> clean_patch(const TriMesh& mesh, const EdgeAdjacency& adjacency, std::vector<char> in,
                              LayerReport& report, const std::function<bool(const Vec3&)>& depression = {},
                              std::vector<char>* filled = nullptr) {
  if (filled != nullptr) filled->assign(in.size(), 0);
  // Holes are noise of the region's band when smaller than a 3 mm disc (see the header); with
  // `depression`, also every hole (a part of the rest of the mesh but the largest) whose vertices
  // all pass it.
  constexpr double kHoleAreaMm2 = std::numbers::pi * 3.0 * 3.0;
  keep_largest(mesh, adjacency, in);
  {
    std::vector<char> out(in.size());
    for (std::size_t t = 0; t < in.size(); ++t) out[t] = !in[t];
    int count = 0;
    const auto label = components(mesh, adjacency, out, &count);
    std::vector<double> area(static_cast<std::size_t>(count), 0.0);
    for (std::size_t t = 0; t < label.size(); ++t) {
      if (label[t] >= 0) area[static_cast<std::size_t>(label[t])] += geometry::triangle_area(mesh, t);
    }
    const int outside = count == 0 ? -1 : static_cast<int>(std::max_element(area.begin(), area.end()) - area.begin());
    std::vector<char> sunk(static_cast<std::size_t>(count), depression ? 1 : 0);
    if (depression) {
      for (std::size_t t = 0; t < label.size(); ++t) {
        if (label[t] < 0 || !sunk[static_cast<std::size_t>(label[t])]) continue;
        for (std::int32_t v : mesh.triangles[t]) {
          if (!depression(mesh.vertices[static_cast<std::size_t>(v)])) sunk[static_cast<std::size_t>(label[t])] = 0;
        }
      }
    }
    for (int g = 0; g < count; ++g) {
      const bool hole = g != outside && (area[static_cast<std::size_t>(g)] < kHoleAreaMm2 || sunk[static_cast<std::size_t>(g)]);
      if (!hole) continue;
      ++report.holes_filled;
      for (std::size_t t = 0; t < label.size(); ++t) {
        if (label[t] != g) continue;
        in[t] = 1;
        if (filled != nullptr) (*filled)[t] = 1;
      }
    }
  }
  // Pinched vertices: the patch triangles around a vertex in more than one fan.
  for (int round = 0; round < 50; ++round) {
    std::unordered_map<std::int32_t, std::vector<std::int32_t>> around;
    for (std::size_t t = 0; t < in.size(); ++t) {
      if (!in[t]) continue;
      for (std::int32_t v : mesh.triangles[t]) around[v].push_back(static_cast<std::int32_t>(t));
    }
    std::size_t dropped = 0;
    for (const auto& [v, tris] : around) {
      // Union-find of the triangles at v through their edges from v.
      std::vector<int> parent(tris.size());
      std::iota(parent.begin(), parent.end(), 0);
      const auto find = [&](int i) {
        while (parent[static_cast<std::size_t>(i)] != i) i = parent[static_cast<std::size_t>(i)];
        return i;
      };
      for (std::size_t i = 0; i < tris.size(); ++i) {
        for (std::size_t j = i + 1; j < tris.size(); ++j) {
          const Triangle& a = mesh.triangles[static_cast<std::size_t>(tris[i])];
          const Triangle& b = mesh.triangles[static_cast<std::size_t>(tris[j])];
          int shared = 0;
          for (auto x : a) {
            if (x != v && std::find(b.begin(), b.end(), x) != b.end()) ++shared;
          }
          if (shared > 0) parent[static_cast<std::size_t>(find(static_cast<int>(i)))] = find(static_cast<int>(j));
        }
      }
      std::map<int, int> fan_size;
      for (std::size_t i = 0; i < tris.size(); ++i) ++fan_size[find(static_cast<int>(i))];
      if (fan_size.size() <= 1) continue;
      int keep = fan_size.begin()->first;
      for (const auto& [root, size] : fan_size) {
        if (size > fan_size[keep]) keep = root;
      }
      for (std::size_t i = 0; i < tris.size(); ++i) {
        if (find(static_cast<int>(i)) != keep && in[static_cast<std::size_t>(tris[i])]) {
          in[static_cast<std::size_t>(tris[i])] = 0;
          ++dropped;
        }
      }
    }
    if (dropped == 0) break;
    report.pinches_removed += dropped;
    keep_largest(mesh, adjacency, in);
  }
  return in;
}

// The patch's vertices (mesh indices, in first-use order) and each mesh vertex's patch index.
struct PatchVertices {
  std::vector<std::int32_t> mesh_index;
  std::unordered_map<std::int32_t, std::int32_t> local;
};

PatchVertices patch_vertices(const TriMesh& mesh, const std::vector<char>& in) {
  PatchVertices out;
  for (std::size_t t = 0; t < in.size(); ++t) {
    if (!in[t]) continue;
    for (std::int32_t v : mesh.triangles[t]) {
      if (out.local.emplace(v, static_cast<std::int32_t>(out.mesh_index.size())).second) out.mesh_index.push_back(v);
    }
  }
  return out;
}

// Is edge k (tri[k] -> tri[k + 1]) of patch triangle `tri` on the patch's boundary (no other patch
// triangle across it)?
bool on_patch_boundary(const Triangle& tri, int k, const EdgeAdjacency& adjacency, const std::vector<char>& in) {
  int inside = 0;
  for (std::int32_t u : adjacency.across(tri[k], tri[(k + 1) % 3])) inside += in[static_cast<std::size_t>(u)] ? 1 : 0;
  return inside == 1;
}

// Directed boundary edges (a -> b as in their triangle) of the patch.
std::vector<std::pair<std::int32_t, std::int32_t>> boundary_edges(const TriMesh& mesh, const EdgeAdjacency& adjacency,
                                                                  const std::vector<char>& in) {
  std::vector<std::pair<std::int32_t, std::int32_t>> out;
  for (std::size_t t = 0; t < in.size(); ++t) {
    if (!in[t]) continue;
    const Triangle& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (on_patch_boundary(tri, k, adjacency, in)) out.emplace_back(tri[k], tri[(k + 1) % 3]);
    }
  }
  return out;
}

// The layer solid of a patch extruded radially about `centre` (see the header), outward.
TriMesh layer_solid(const TriMesh& mesh, const std::vector<char>& in, const PatchVertices& pv,
                    const std::vector<std::pair<std::int32_t, std::int32_t>>& boundary, const Vec3& centre,
                    const std::vector<double>& r_in, const std::vector<double>& r_out,
                    const std::vector<double>& thickness) {
  const std::size_t n = pv.mesh_index.size();
  TriMesh solid;
  solid.vertices.resize(2 * n);
  std::vector<double> field(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = (mesh.vertices[static_cast<std::size_t>(pv.mesh_index[i])] - centre).normalized();
    solid.vertices[i] = centre + r_in[i] * d;
    solid.vertices[n + i] = centre + r_out[i] * d;
    field[i] = field[n + i] = thickness[i];
  }
  const auto inner = [&](std::int32_t v) { return pv.local.at(v); };
  const auto outer = [&](std::int32_t v) { return static_cast<std::int32_t>(n) + pv.local.at(v); };
  for (std::size_t t = 0; t < in.size(); ++t) {
    if (!in[t]) continue;
    const Triangle& tri = mesh.triangles[t];
    solid.triangles.push_back({outer(tri[0]), outer(tri[1]), outer(tri[2])});
    solid.triangles.push_back({inner(tri[0]), inner(tri[2]), inner(tri[1])});
  }
  for (const auto& [a, b] : boundary) {
    solid.triangles.push_back({outer(b), outer(a), inner(a)});
    solid.triangles.push_back({outer(b), inner(a), inner(b)});
  }
  if (geometry::signed_volume(solid) < 0.0) {
    for (Triangle& t : solid.triangles) std::swap(t[1], t[2]);
  }
  solid.vertex_fields["thickness_mm"] = std::move(field);
  return solid;
}

// Area of the patch around each of its vertices (a third of each triangle's).
std::vector<double> vertex_areas(const TriMesh& mesh, const std::vector<char>& in, const PatchVertices& pv) {
  std::vector<double> area(pv.mesh_index.size(), 0.0);
  for (std::size_t t = 0; t < in.size(); ++t) {
    if (!in[t]) continue;
    const double a = geometry::triangle_area(mesh, t) / 3.0;
    for (std::int32_t v : mesh.triangles[t]) area[static_cast<std::size_t>(pv.local.at(v))] += a;
  }
  return area;
}

void fill_layer_numbers(LayerReport& report, const std::vector<double>& area, const std::vector<double>& thickness,
                        const TriMesh& solid) {
  report.patch_vertices = area.size();
  report.covered_area_mm2 = std::accumulate(area.begin(), area.end(), 0.0);
  double weighted = 0.0;
  report.min_thickness_mm = thickness.empty() ? 0.0 : thickness[0];
  report.max_thickness_mm = report.min_thickness_mm;
  for (std::size_t i = 0; i < area.size(); ++i) {
    weighted += area[i] * thickness[i];
    report.min_thickness_mm = std::min(report.min_thickness_mm, thickness[i]);
    report.max_thickness_mm = std::max(report.max_thickness_mm, thickness[i]);
  }
  report.mean_thickness_mm = report.covered_area_mm2 > 0.0 ? weighted / report.covered_area_mm2 : 0.0;
  report.volume_mm3 = geometry::signed_volume(solid);
}

double interpolate(const TriMesh& mesh, const RayHit& hit, const PatchVertices& pv, const std::vector<double>& value) {
  const Triangle& t = mesh.triangles[hit.triangle];
  double out = 0.0;
  for (int k = 0; k < 3; ++k) out += hit.weights[k] * value[static_cast<std::size_t>(pv.local.at(t[k]))];
  return out;
}

// A triangle mask of the mesh's triangles whose three corners are in `vertices`.
std::vector<char> triangles_of(const TriMesh& mesh, const std::vector<std::int32_t>& vertices) {
  std::vector<char> vertex_in(mesh.vertices.size(), 0);
  for (std::int32_t v : vertices) {
    if (v >= 0 && static_cast<std::size_t>(v) < vertex_in.size()) vertex_in[static_cast<std::size_t>(v)] = 1;
  }
  std::vector<char> in(mesh.triangles.size(), 0);
  for (std::size_t t = 0; t < in.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    in[t] = vertex_in[static_cast<std::size_t>(tri[0])] && vertex_in[static_cast<std::size_t>(tri[1])] &&
            vertex_in[static_cast<std::size_t>(tri[2])];
  }
  return in;
}

// --- labrum ---------------------------------------------------------------------------------

// The section's corners: A (base, inner), B (base, outer), T (tip), three on the inner face; the
// base A-B (5 mm) and the outer face B-T (~9 mm) are split so that no edge of the swept labrum is
// much longer than the bones' (the studies' contact tolerance follows the longest tissue edge).
constexpr int kCorners = 6;
constexpr int kBaseSplits = 3;   // A -> B in 3 pieces
constexpr int kOuterSplits = 5;  // B -> T in 5 pieces
constexpr int kSectionPoints = kCorners + (kBaseSplits - 1) + (kOuterSplits - 1);
using Section = std::array<Vec3, kSectionPoints>;

// The section polygon A, (base points), B, (outer-face points), T, inner face, from its corners.
Section subdivided(const std::array<Vec3, kCorners>& corner) {
  Section out;
  int k = 0;
  for (int i = 0; i < kBaseSplits; ++i) out[k++] = corner[0] + (corner[1] - corner[0]) * (double(i) / kBaseSplits);
  for (int i = 0; i < kOuterSplits; ++i) out[k++] = corner[1] + (corner[2] - corner[1]) * (double(i) / kOuterSplits);
  for (int j = 2; j < kCorners; ++j) out[k++] = corner[static_cast<std::size_t>(j)];
  return out;
}

// Runs of kept sections swept into closed solids (see the header), one shell per run.
TriMesh sweep_sections(const std::vector<std::optional<Section>>& sections, SoftTissueReport& report) {
  const int count = static_cast<int>(sections.size());
  TriMesh labrum;
  const bool ring = std::all_of(sections.begin(), sections.end(), [](const auto& s) { return s.has_value(); });
  report.labrum_closed_ring = ring;
  std::vector<std::vector<int>> runs;
  if (ring) {
    runs.emplace_back(static_cast<std::size_t>(count));
    std::iota(runs.back().begin(), runs.back().end(), 0);
  } else {
    int start = 0;
    while (sections[static_cast<std::size_t>(start)]) ++start;  // a missing one exists
    std::vector<int> run;
    for (int k = 1; k <= count; ++k) {
      const int i = (start + k) % count;
      if (sections[static_cast<std::size_t>(i)]) {
        run.push_back(i);
      } else if (!run.empty()) {
        runs.push_back(run);
        run.clear();
      }
    }
    if (!run.empty()) runs.push_back(run);
  }
  for (const auto& run : runs) {
    if (run.size() < 3) continue;  // too short to be a solid worth meshing
    TriMesh piece;
    for (int i : run) {
      for (const Vec3& p : *sections[static_cast<std::size_t>(i)]) piece.vertices.push_back(p);
    }
    const int m = static_cast<int>(run.size());
    const auto at = [](int section, int j) { return static_cast<std::int32_t>(section * kSectionPoints + j % kSectionPoints); };
    const int spans = ring ? m : m - 1;
    for (int k = 0; k < spans; ++k) {
      const int k1 = (k + 1) % m;
      for (int j = 0; j < kSectionPoints; ++j) {
        piece.triangles.push_back({at(k, j), at(k, j + 1), at(k1, j + 1)});
        piece.triangles.push_back({at(k, j), at(k1, j + 1), at(k1, j)});
      }
    }
    if (!ring) {
      // Caps: fans from each end section's centroid, reversed at the start, in polygon order at the end.
      const auto centroid = [&](int section) {
        Vec3 c = Vec3::Zero();
        for (int j = 0; j < kSectionPoints; ++j) c += piece.vertices[static_cast<std::size_t>(at(section, j))];
        return Vec3(c / kSectionPoints);
      };
      const auto first = static_cast<std::int32_t>(piece.vertices.size());
      piece.vertices.push_back(centroid(0));
      piece.vertices.push_back(centroid(m - 1));
      for (int j = 0; j < kSectionPoints; ++j) {
        piece.triangles.push_back({first, at(0, j + 1), at(0, j)});
        piece.triangles.push_back({first + 1, at(m - 1, j), at(m - 1, j + 1)});
      }
    }
    if (geometry::signed_volume(piece) < 0.0) {
      for (Triangle& t : piece.triangles) std::swap(t[1], t[2]);
    }
    labrum = geometry::merge_meshes({&labrum, &piece});
    ++report.labrum_pieces;
  }
  return labrum;
}

// --- patches -------------------------------------------------------------------------------

Vec3 ray_direction(const Vec3& centre, const Vec3& p) { return Vec3((p - centre).normalized()); }

// Where the head ends towards the neck: the alpha angle's clock profile about the neck axis,
// linear between the profile's planes (SoftTissueRequest::head_neck_junction).
class HeadNeckJunction {
 public:
  explicit HeadNeckJunction(const SoftTissueRequest& request)
      : n_(request.neck_axis.norm() > 0.0 ? Vec3(request.neck_axis.normalized()) : Vec3::Zero()),
        e1_(n_.norm() > 0.0 ? Vec3(n_.unitOrthogonal()) : Vec3::UnitX()),
        e2_(n_.cross(e1_)) {
    for (const auto& [u, alpha] : request.head_neck_junction) {
      if (std::isfinite(alpha) && n_.norm() > 0.0) junction_.emplace_back(std::atan2(u.dot(e2_), u.dot(e1_)), alpha);
    }
    std::sort(junction_.begin(), junction_.end());
  }

  // Is the direction d from the head centre at or beyond the junction's alpha at its clock?
  bool beyond(const Vec3& d) const {
    if (junction_.empty()) return true;
    const double azimuth = std::atan2(d.dot(e2_), d.dot(e1_));
    auto after = std::upper_bound(junction_.begin(), junction_.end(), std::make_pair(azimuth, -1e300));
    const auto& hi = after == junction_.end() ? junction_.front() : *after;
    const auto& lo = after == junction_.begin() ? junction_.back() : *(after - 1);
    const auto turn = [](double a) { return std::fmod(std::fmod(a, 2.0 * std::numbers::pi) + 2.0 * std::numbers::pi, 2.0 * std::numbers::pi); };
    const double span = junction_.size() == 1 ? 2.0 * std::numbers::pi : turn(hi.first - lo.first);
    const double from_lo = turn(azimuth - lo.first);
    const double f = span > 0.0 ? std::clamp(from_lo / span, 0.0, 1.0) : 0.0;
    const double alpha = lo.second + f * (hi.second - lo.second);
    return std::acos(std::clamp(d.normalized().dot(n_), -1.0, 1.0)) * geometry::kRadToDeg >= alpha;
  }

 private:
  Vec3 n_, e1_, e2_;
  std::vector<std::pair<double, double>> junction_;  // (azimuth about n, alpha), by azimuth
};

// The request's head vertices, or the femur's vertices on the head sphere (within `band`), facing
// out of it and beyond the head-neck junction.
std::vector<std::int32_t> head_vertices(const SoftTissueRequest& request, double band) {
  if (!request.head_vertices.empty()) return request.head_vertices;
  const TriMesh& femur = *request.femur;
  std::vector<std::int32_t> head;
  const double cos_facing = std::cos(40.0 * geometry::kDegToRad);
  const std::vector<Vec3> normals = geometry::vertex_normals(femur);
  const HeadNeckJunction junction(request);
  for (std::size_t v = 0; v < femur.vertices.size(); ++v) {
    const Vec3 d = femur.vertices[v] - request.head_centre_mm;
    if (!junction.beyond(d)) continue;
    const double r = d.norm();
    if (std::abs(r - request.head_radius_mm) <= band && r > 0.0 && normals[v].dot(d / r) >= cos_facing) {
      head.push_back(static_cast<std::int32_t>(v));
    }
  }
  return head;
}

// The femoral head and lunate patches the cartilage layers grow on.
struct Patches {
  std::vector<char> head_in, lunate_in;  // triangle masks of femur and pelvis
  std::vector<char> head_filled;         // the head's holes filled (the fovea): a femur triangle mask
  PatchVertices head, socket;
  std::vector<std::pair<std::int32_t, std::int32_t>> head_boundary, socket_boundary;
};

Patches find_patches(const SoftTissueRequest& request, const EdgeAdjacency& femur_edges,
                     const EdgeAdjacency& pelvis_edges, double band, SoftTissueReport& report) {
  const TriMesh& femur = *request.femur;
  const TriMesh& pelvis = *request.pelvis;
  const Vec3 head_centre = request.head_centre_mm;
  Patches patches;
  patches.head_in = triangles_of(femur, head_vertices(request, band));
  if (std::count(patches.head_in.begin(), patches.head_in.end(), 1) < 20) {
    throw_error(request.femur_name, ": no femoral head region on the sphere (centre [", head_centre.x(), ", ",
                head_centre.y(), ", ", head_centre.z(),
                "] mm, radius ", request.head_radius_mm, " mm)");
  }
  patches.head_in = clean_patch(femur, femur_edges, patches.head_in, report.femoral, [&](const Vec3& x) {
    return (x - head_centre).norm() <= request.head_radius_mm + band;
  }, &patches.head_filled);
  const geometry::SurfaceRegion lunate =
      geometry::find_lunate_surface(pelvis, head_centre, request.head_radius_mm, {}, request.pelvis_name);
  patches.lunate_in = triangles_of(pelvis, lunate.mesh_vertices);
  if (std::count(patches.lunate_in.begin(), patches.lunate_in.end(), 1) < 20) {
    throw_error(request.pelvis_name, ": no lunate surface around the femoral head");
  }
  patches.lunate_in = clean_patch(pelvis, pelvis_edges, patches.lunate_in, report.acetabular);
  patches.head = patch_vertices(femur, patches.head_in);
  patches.socket = patch_vertices(pelvis, patches.lunate_in);
  patches.head_boundary = boundary_edges(femur, femur_edges, patches.head_in);
  patches.socket_boundary = boundary_edges(pelvis, pelvis_edges, patches.lunate_in);
  return patches;
}

// --- layers ---------------------------------------------------------------------------------

// The femoral lens: the literature maximum where the head is farthest (in angle about c) from its
// patch's edge, thinning to 0 at the edge. It only says where the femoral cartilage is thickest
// (where the articular sphere's radius is taken); the layer itself reaches the sphere everywhere.
std::vector<double> nominal_femoral_thickness(const TriMesh& femur, const Patches& patches, const Vec3& c,
                                              const SoftTissueOptions& o) {
  const PatchVertices& head = patches.head;
  std::vector<Vec3> edge_directions;
  for (const auto& e : patches.head_boundary) {
    edge_directions.push_back(ray_direction(c, femur.vertices[static_cast<std::size_t>(e.first)]));
  }
  std::vector<double> to_edge(head.mesh_index.size(), std::numbers::pi);
  for (std::size_t i = 0; i < head.mesh_index.size(); ++i) {
    const Vec3 d = ray_direction(c, femur.vertices[static_cast<std::size_t>(head.mesh_index[i])]);
    double best = -1.0;
    for (const Vec3& e : edge_directions) best = std::max(best, d.dot(e));
    to_edge[i] = std::acos(std::clamp(best, -1.0, 1.0));
  }
  const double b_max = edge_directions.empty() ? std::numbers::pi : *std::max_element(to_edge.begin(), to_edge.end());
  std::vector<double> t_f_nominal(head.mesh_index.size(), o.femoral_max_thickness_mm);
  if (b_max > 0.0 && !edge_directions.empty()) {
    for (std::size_t i = 0; i < to_edge.size(); ++i) {
      t_f_nominal[i] = o.femoral_max_thickness_mm * (std::cos(b_max - to_edge[i]) - std::cos(b_max)) /
                       (1.0 - std::cos(b_max));
    }
  }
  return t_f_nominal;
}

// The common articular sphere about c (see the header): its radius splits the bone-to-bone gap
// in the ratio of the two literature thicknesses where the femoral lens is thickest (within 10 %
// of its maximum) and the ray meets the lunate surface; where that gap is wider than both
// thicknesses the acetabular layer keeps its own and the femoral layer takes the rest. It lies
// no farther than the femoral maximum above the deepest head bone facing the lunate surface
// outside the head's filled holes (the fovea, where no cartilage grows).
double articular_radius(const SoftTissueRequest& request, const Patches& patches, const MeshQueries& pelvis_queries,
                        const std::vector<double>& t_f_nominal, const Vec3& c) {
  const TriMesh& femur = *request.femur;
  const double t_f_max = request.options.femoral_max_thickness_mm, t_a_lit = request.options.acetabular_thickness_mm;
  std::vector<char> in_hole(femur.vertices.size(), 0);
  for (std::size_t t = 0; t < patches.head_filled.size(); ++t) {
    if (!patches.head_filled[t]) continue;
    for (std::int32_t v : femur.triangles[t]) in_hole[static_cast<std::size_t>(v)] = 1;
  }
  std::vector<double> split, split_all;
  double deepest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < patches.head.mesh_index.size(); ++i) {
    const auto v = static_cast<std::size_t>(patches.head.mesh_index[i]);
    const Vec3& x = femur.vertices[v];
    const auto hit = pelvis_queries.first_hit(c, ray_direction(c, x));
    if (!hit || !patches.lunate_in[hit->triangle]) continue;
    const double r = (x - c).norm(), gap = hit->distance - r;
    if (!in_hole[v]) deepest = std::min(deepest, r);
    const double meet = gap >= t_f_max + t_a_lit ? hit->distance - t_a_lit : r + std::max(0.0, gap) * t_f_max / (t_f_max + t_a_lit);
    split_all.push_back(meet);
    if (t_f_nominal[i] >= 0.9 * t_f_max) split.push_back(meet);
  }
  if (split.empty()) split = split_all;
  if (split.empty()) throw_error(request.femur_name, ": the femoral head region faces no lunate surface");
  std::nth_element(split.begin(), split.begin() + static_cast<std::ptrdiff_t>(split.size() / 2), split.end());
  return std::min(split[split.size() / 2], deepest + t_f_max);
}

// The head region's edge peeled where its bone stands within the minimum thickness of the
// articular sphere (see the header): edge triangles with a vertex there are taken off the region,
// round by round, until every vertex of the edge lies deeper, so that no part of the edge stands
// proud of the sphere. A bump inside the region keeps its layer. Returns the number of triangles
// peeled.
std::size_t peel_bare_rim(const TriMesh& femur, const EdgeAdjacency& adjacency, Patches& patches, double r_art,
                          const Vec3& c, double min_thickness) {
  std::vector<char> bare(femur.vertices.size(), 0);
  for (std::int32_t v : patches.head.mesh_index) {
    bare[static_cast<std::size_t>(v)] = r_art - (femur.vertices[static_cast<std::size_t>(v)] - c).norm() < min_thickness;
  }
  std::vector<char>& in = patches.head_in;
  std::size_t peeled = 0;
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<std::size_t> edge_bare;
    for (std::size_t t = 0; t < in.size(); ++t) {
      if (!in[t]) continue;
      const Triangle& tri = femur.triangles[t];
      if (!bare[static_cast<std::size_t>(tri[0])] && !bare[static_cast<std::size_t>(tri[1])] &&
          !bare[static_cast<std::size_t>(tri[2])]) {
        continue;
      }
      if (on_patch_boundary(tri, 0, adjacency, in) || on_patch_boundary(tri, 1, adjacency, in) ||
          on_patch_boundary(tri, 2, adjacency, in)) {
        edge_bare.push_back(t);
      }
    }
    for (std::size_t t : edge_bare) in[t] = 0;
    peeled += edge_bare.size();
    changed = !edge_bare.empty();
  }
  if (peeled > 0) {
    LayerReport unused;
    in = clean_patch(femur, adjacency, in, unused);
    patches.head = patch_vertices(femur, in);
    patches.head_boundary = boundary_edges(femur, adjacency, in);
  }
  return peeled;
}

// The acetabular fossa taken off the lunate patch (see the header): the patch triangles with a
// corner deeper from c than the articular sphere plus the thickest cartilage, and for each such
// part the patch encloses, the patch inferior of the part's centre within its width, which opens
// it to the outline towards the notch. Then the largest piece, made manifold again.
void remove_fossa(const TriMesh& pelvis, const EdgeAdjacency& adjacency, Patches& patches, double r_art, const Vec3& c,
                  const Acetabulum& acetabulum, const SoftTissueOptions& o, SoftTissueReport& report) {
  std::vector<char>& in = patches.lunate_in;
  const double deepest_cartilage = r_art + o.fossa_depth_mm;
  std::vector<char> fossa(in.size(), 0);
  for (std::size_t t = 0; t < in.size(); ++t) {
    if (!in[t]) continue;
    for (std::int32_t v : pelvis.triangles[t]) {
      if ((pelvis.vertices[static_cast<std::size_t>(v)] - c).norm() > deepest_cartilage) fossa[t] = 1;
    }
    if (fossa[t]) report.fossa_area_mm2 += geometry::triangle_area(pelvis, t);
  }
  if (report.fossa_area_mm2 == 0.0) return;
  const auto centroid_direction = [&](std::size_t t) {
    const Triangle& tri = pelvis.triangles[t];
    return ray_direction(c, (pelvis.vertices[static_cast<std::size_t>(tri[0])] + pelvis.vertices[static_cast<std::size_t>(tri[1])] +
                             pelvis.vertices[static_cast<std::size_t>(tri[2])]) / 3.0);
  };
  std::vector<char> kept = in, bare(in.size(), 0);
  for (std::size_t t = 0; t < in.size(); ++t) {
    kept[t] = in[t] && !fossa[t];
    bare[t] = !kept[t];
  }
  // The parts of the mesh off the patch: the largest is its outside; a fossa part in any other is
  // enclosed by the patch (a hole).
  int parts = 0;
  const std::vector<std::int32_t> part = components(pelvis, adjacency, bare, &parts);
  std::vector<double> part_area(static_cast<std::size_t>(parts), 0.0);
  std::vector<Vec3> centre(static_cast<std::size_t>(parts), Vec3::Zero());
  for (std::size_t t = 0; t < in.size(); ++t) {
    if (part[t] < 0) continue;
    const double area = geometry::triangle_area(pelvis, t);
    part_area[static_cast<std::size_t>(part[t])] += area;
    if (fossa[t]) centre[static_cast<std::size_t>(part[t])] += area * centroid_direction(t);
  }
  const auto outside = static_cast<int>(std::max_element(part_area.begin(), part_area.end()) - part_area.begin());
  const Vec3 inferior = -acetabulum.clock_superior;
  for (int g = 0; g < parts; ++g) {
    if (g == outside || centre[static_cast<std::size_t>(g)].norm() == 0.0) continue;
    // Seen from c: f the hole's centre, s the inferior direction along the sphere there, n across.
    const Vec3 f = centre[static_cast<std::size_t>(g)].normalized();
    const Vec3 s = (inferior - inferior.dot(f) * f).normalized();
    const Vec3 n = f.cross(s);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t t = 0; t < in.size(); ++t) {
      if (part[t] != g || !fossa[t]) continue;
      for (std::int32_t v : pelvis.triangles[t]) {
        const double across = ray_direction(c, pelvis.vertices[static_cast<std::size_t>(v)]).dot(n);
        lo = std::min(lo, across);
        hi = std::max(hi, across);
      }
    }
    for (std::size_t t = 0; t < in.size(); ++t) {
      if (!kept[t]) continue;
      const Vec3 d = centroid_direction(t);
      if (d.dot(f) > 0.0 && d.dot(s) >= 0.0 && d.dot(n) >= lo && d.dot(n) <= hi) {
        kept[t] = 0;
        report.fossa_opening_area_mm2 += geometry::triangle_area(pelvis, t);
      }
    }
    ++report.fossa_holes_opened;
  }
  LayerReport cleaning;
  in = clean_patch(pelvis, adjacency, kept, cleaning);
  report.acetabular.holes_filled += cleaning.holes_filled;
  report.acetabular.pinches_removed += cleaning.pinches_removed;
  patches.socket = patch_vertices(pelvis, in);
  patches.socket_boundary = boundary_edges(pelvis, adjacency, in);
}

// A layer's thickness and its inner and outer radius about c, per patch vertex.
struct LayerRadii {
  std::vector<double> thickness, r_in, r_out;
};

// Femoral layer: from the head up to the sphere over the whole head region, never thinner than the
// minimum. Not only where it faces the lunate surface in the neutral pose: the head turns under the
// socket (in flexion its anterior part comes under the dome), so every part of it must stay
// congruent, as the generator's does (its lens lies between an eccentric head and the R sphere).
LayerRadii femoral_layer(const TriMesh& femur, const PatchVertices& head, const std::vector<double>& head_area,
                         double r_art, const Vec3& c, const SoftTissueOptions& o, LayerReport& report) {
  const std::size_t n = head.mesh_index.size();
  LayerRadii layer{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& x = femur.vertices[static_cast<std::size_t>(head.mesh_index[i])];
    const double r = (x - c).norm();
    const double to_sphere = r_art - r;
    report.articular_area_mm2 += head_area[i];
    if (to_sphere < o.min_thickness_mm) report.overlap_area_mm2 += head_area[i];
    layer.thickness[i] = std::max(o.min_thickness_mm, to_sphere);
    layer.r_in[i] = r;
    layer.r_out[i] = r + layer.thickness[i];
  }
  return layer;
}

// Acetabular layer: from the lunate bone down to the sphere, never thinner than the minimum.
LayerRadii acetabular_layer(const TriMesh& pelvis, const PatchVertices& socket, const std::vector<double>& socket_area,
                            double r_art, const Vec3& c, const SoftTissueOptions& o, LayerReport& report) {
  const std::size_t n = socket.mesh_index.size();
  LayerRadii layer{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& y = pelvis.vertices[static_cast<std::size_t>(socket.mesh_index[i])];
    const double r = (y - c).norm();
    report.articular_area_mm2 += socket_area[i];
    if (r - r_art < o.min_thickness_mm) report.overlap_area_mm2 += socket_area[i];
    layer.thickness[i] = std::max(o.min_thickness_mm, r - r_art);
    layer.r_out[i] = r;
    layer.r_in[i] = r - layer.thickness[i];
  }
  return layer;
}

// The two layers' surfaces are piecewise linear over different meshes (and a femoral layer kept
// at the minimum over a bone bump stands proud of the sphere), so the acetabular joint side is
// also kept at or above the femoral layer's outer surface along its own ray (looking back from the
// bone), down to the minimum thickness.
void clear_femoral_layer(LayerRadii& acetabular, const TriMesh& pelvis, const PatchVertices& socket,
                         const TriMesh& femoral_cartilage, const Vec3& c, const SoftTissueOptions& o) {
  const MeshQueries femoral_layer(femoral_cartilage);
  for (std::size_t i = 0; i < acetabular.thickness.size(); ++i) {
    const Vec3& y = pelvis.vertices[static_cast<std::size_t>(socket.mesh_index[i])];
    const auto hit = femoral_layer.first_hit(y, -ray_direction(c, y));
    if (!hit || hit->distance >= acetabular.r_out[i]) continue;
    const double femoral_outer = acetabular.r_out[i] - hit->distance;
    if (femoral_outer <= acetabular.r_in[i]) continue;
    acetabular.r_in[i] = std::min(femoral_outer, acetabular.r_out[i] - o.min_thickness_mm);
    acetabular.thickness[i] = acetabular.r_out[i] - acetabular.r_in[i];
  }
}

// --- labrum sections ------------------------------------------------------------------------

// Places the labrum's sections in the meridian planes of the acetabular axis through the joint
// centre c, their bases along its rays (so the hexahedral mesher, which looks from there, sees the
// base edge-on); the inner face on the common articular sphere.
class LabrumSections {
 public:
  enum class Verdict { kPlaced, kOnFemur, kInPelvis };

  LabrumSections(const SoftTissueRequest& request, const Patches& patches, const std::vector<double>& t_f,
                 const MeshQueries& femur_queries, const MeshQueries& pelvis_queries,
                 const MeshQueries& cartilage_queries, const Vec3& c, double r_art)
      : femur_(*request.femur), acetabulum_(*request.acetabulum), o_(request.options), patches_(patches), t_f_(t_f),
        femur_queries_(femur_queries), pelvis_queries_(pelvis_queries), cartilage_queries_(cartilage_queries), c_(c),
        r_art_(r_art) {}

  // Clock and polar angles seen from the joint centre (the acetabulum's own are about the lunate
  // sphere's centre; the sections are laid about c).
  std::pair<double, double> clock_polar(const Vec3& x) const {
    const Vec3 d = x - c_;
    const double clock = std::atan2(d.dot(acetabulum_.clock_superior), d.dot(acetabulum_.clock_anterior)) * geometry::kRadToDeg;
    return std::make_pair(clock, std::atan2(d.cross(acetabulum_.axis).norm(), d.dot(acetabulum_.axis)) * geometry::kRadToDeg);
  }

  // The section at `clock` under the rim at `polar` (deg), tilted deeper step by step until it is
  // clear of the pelvis and its cartilage; not placed where it would stand on the femur.
  Verdict place(double clock, double polar, Section& section) const {
    const double phi = clock * geometry::kDegToRad;
    const Vec3 meridian = std::cos(phi) * acetabulum_.clock_anterior + std::sin(phi) * acetabulum_.clock_superior;
    const auto ray = [&](double polar_rad) { return Vec3(std::cos(polar_rad) * acetabulum_.axis + std::sin(polar_rad) * meridian); };
    constexpr double kTiltStepDeg = 0.5, kMaxTiltDeg = 10.0;
    std::array<Vec3, kCorners> corner;
    for (double tilt = 0.0; tilt <= kMaxTiltDeg + 1e-9; tilt += kTiltStepDeg) {
      const double base_polar = (polar - tilt) * geometry::kDegToRad;
      const Vec3 ub = ray(base_polar);
      const double rho_a = labrum_inner(ub);
      const double tip_polar = base_polar - std::asin(std::min(1.0, o_.labrum_height_mm / rho_a));
      corner[0] = c_ + rho_a * ub;
      corner[1] = c_ + (rho_a + o_.labrum_base_mm) * ub;
      // Tip and inner face, from the tip back towards A.
      bool femur_hit = false;
      for (int j = 0; j < 4; ++j) {
        const double f = static_cast<double>(j) / 4.0;
        const Vec3 u = ray(tip_polar + f * (base_polar - tip_polar));
        if (femoral_outer(u) > r_art_ + o_.labrum_height_mm) femur_hit = true;  // the neck stands under the rim
        corner[static_cast<std::size_t>(2 + j)] = c_ + labrum_inner(u) * u;
      }
      if (femur_hit) return Verdict::kOnFemur;
      section = subdivided(corner);
      const Verdict verdict = probe(section, corner, meridian);
      if (verdict != Verdict::kInPelvis) return verdict;
    }
    return Verdict::kInPelvis;
  }

 private:
  // Outer radius of the femur with its cartilage along a ray from c.
  double femoral_outer(const Vec3& u) const {
    const auto hit = femur_queries_.first_hit(c_, u);
    if (!hit) return 0.0;
    return hit->distance + (patches_.head_in[hit->triangle] ? interpolate(femur_, *hit, patches_.head, t_f_) : 0.0);
  }

  // The labrum's inner face: on the articular sphere, as the generator's (the labrum extends the
  // socket), lifted only over the femoral cartilage where it stands proud of that sphere; bone
  // outside the cartilage (a cam, the neck) does not shape it: that is what it meets in motion.
  double labrum_inner(const Vec3& u) const {
    const auto hit = femur_queries_.first_hit(c_, u);
    if (!hit || !patches_.head_in[hit->triangle]) return r_art_;
    return std::max(r_art_, hit->distance + interpolate(femur_, *hit, patches_.head, t_f_));
  }

  // Probes the section's points, edge midpoints and base centroid: on the femur, in the pelvis or
  // its cartilage, or placed (clear of both). The base lies on the rim's face, which the bone's
  // triangles only approximate: between two rim vertices the face's chord stands up to
  // L^2 / (8 rho) off the true surface (0.02 mm for 2 mm edges), into the socket where the rim
  // cone is convex towards it (opening < 90 deg; on a plane rim either way by round-off), so a
  // base laid on the rim read as inside the pelvis and its section tilted a step deeper than the
  // rim (0.5 deg; every section of the generated CE 30 and 40 hips). A section is in the pelvis or
  // its cartilage only where it reaches more than the touching tolerance (o_.min_thickness_mm,
  // the sphericity tolerance) into them: the pelvis probes are moved that far off the rim's
  // face, towards the acetabular axis in the section's meridian plane. Likewise on the femur:
  // its inner face lies on the articular sphere, where the bone of a congruent head may lie too
  // (the generated heads' bare band beyond the cartilage, on the sphere: with the radius exactly
  // the generator's, round-off there dropped 2 to 32 of the 144 sections of CE 20-40 hips), so
  // the femur probes are moved that far out along their ray from c.
  Verdict probe(const Section& section, const std::array<Vec3, kCorners>& corner, const Vec3& meridian) const {
    std::vector<Vec3> probes(section.begin(), section.end());
    for (int j = 0; j < kSectionPoints; ++j) {
      probes.push_back(0.5 * (section[static_cast<std::size_t>(j)] + section[static_cast<std::size_t>((j + 1) % kSectionPoints)]));
    }
    probes.push_back((corner[0] + corner[1] + corner[2]) / 3.0);
    bool in_femur = false, in_pelvis = false;
    for (const Vec3& p : probes) {
      const Vec3 d = p - c_;
      const double polar = std::atan2(d.dot(meridian), d.dot(acetabulum_.axis));
      const Vec3 towards_axis = std::sin(polar) * acetabulum_.axis - std::cos(polar) * meridian;
      const Vec3 q = p + o_.min_thickness_mm * towards_axis;
      in_femur = in_femur || femur_queries_.inside(Vec3(p + o_.min_thickness_mm * d.normalized()));
      in_pelvis = in_pelvis || pelvis_queries_.inside(q) || cartilage_queries_.inside(q);
    }
    if (in_femur) return Verdict::kOnFemur;
    return in_pelvis ? Verdict::kInPelvis : Verdict::kPlaced;
  }

  const TriMesh& femur_;
  const Acetabulum& acetabulum_;
  const SoftTissueOptions& o_;
  const Patches& patches_;
  const std::vector<double>& t_f_;
  const MeshQueries& femur_queries_;
  const MeshQueries& pelvis_queries_;
  const MeshQueries& cartilage_queries_;
  Vec3 c_;
  double r_art_;
};

// The rim's polar angle at `clock`, smoothed over kReachDeg either side; none where the rim has a
// one-sided gap there.
std::optional<double> rim_polar_at(const std::vector<std::pair<double, double>>& rim, double clock, double step_deg) {
  constexpr double kReachDeg = 10.0;  // rim smoothing half-width and largest one-sided gap
  double weight = 0.0, polar = 0.0;
  bool before = false, after = false;
  for (const auto& [rim_clock, rim_polar] : rim) {
    const double delta = std::remainder(rim_clock - clock, 360.0);
    if (std::abs(delta) > kReachDeg) continue;
    const double w = 1.0 - std::abs(delta) / kReachDeg + 1e-9;
    weight += w;
    polar += w * rim_polar;
    if (delta <= 0.5 * step_deg) before = true;
    if (delta >= -0.5 * step_deg) after = true;
  }
  if (!(before && after)) return std::nullopt;
  return polar / weight;
}

// One section per labrum_step_deg of clock where the rim carries one, counted in the report.
std::vector<std::optional<Section>> labrum_sections(const SoftTissueRequest& request, const LabrumSections& placer,
                                                    const PatchVertices& socket, SoftTissueReport& report) {
  const SoftTissueOptions& o = request.options;
  std::vector<std::pair<double, double>> rim;  // (clock, polar) of the plane-fit rim points
  for (const RimPoint& p : request.acetabulum->rim) {
    if (p.in_plane_fit) rim.push_back(placer.clock_polar(p.point_mm));
  }
  if (rim.size() < 3) throw_error(request.pelvis_name, ": too little acetabular rim to carry a labrum");
  // The horseshoe's opening (the acetabular notch): clock angles with no lunate surface within
  // kNotchPolarDeg below the rim. The rim finder may keep the notch's rim (it dips only ~10 deg
  // deeper there), the articular surface does not reach it.
  std::vector<std::pair<double, double>> lunate_clock_polar;  // (clock, polar) of lunate vertices
  for (std::int32_t v : socket.mesh_index) {
    lunate_clock_polar.push_back(placer.clock_polar(request.pelvis->vertices[static_cast<std::size_t>(v)]));
  }
  constexpr double kNotchPolarDeg = 30.0, kNotchClockDeg = 5.0;
  const int count = static_cast<int>(std::lround(360.0 / o.labrum_step_deg));
  report.labrum_sections_total = count;
  std::vector<std::optional<Section>> sections(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    const double clock = -180.0 + k * o.labrum_step_deg;
    const std::optional<double> polar = rim_polar_at(rim, clock, o.labrum_step_deg);
    const bool over_lunate = polar && std::any_of(lunate_clock_polar.begin(), lunate_clock_polar.end(), [&](const auto& cp) {
      return std::abs(std::remainder(cp.first - clock, 360.0)) <= kNotchClockDeg && cp.second <= *polar + kNotchPolarDeg;
    });
    if (!over_lunate) {
      ++report.labrum_missing_rim;
      continue;
    }
    Section section;
    switch (placer.place(clock, *polar, section)) {
      case LabrumSections::Verdict::kOnFemur: ++report.labrum_dropped_femur; break;
      case LabrumSections::Verdict::kInPelvis: ++report.labrum_dropped_pelvis; break;
      case LabrumSections::Verdict::kPlaced:
        sections[static_cast<std::size_t>(k)] = section;
        ++report.labrum_sections;
        break;
    }
  }
  return sections;
}

void check_request(const SoftTissueRequest& request) {
  if (request.femur == nullptr || request.pelvis == nullptr || request.acetabulum == nullptr) {
    throw_error("soft tissue: a femur, a pelvis and an acetabulum are required");
  }
  geometry::validate_mesh(*request.femur, request.femur_name);
  geometry::validate_mesh(*request.pelvis, request.pelvis_name);
  if (request.femur->empty()) throw_error(request.femur_name, ": empty mesh");
  if (request.pelvis->empty()) throw_error(request.pelvis_name, ": empty mesh");
  if (!(request.head_radius_mm > 0.0)) throw_error(request.femur_name, ": no femoral head sphere given");
  const SoftTissueOptions& o = request.options;
  if (!(o.fossa_depth_mm > o.min_thickness_mm)) {
    throw_error("soft tissue: fossa_depth_mm = ", o.fossa_depth_mm, " must exceed the minimum thickness ",
                o.min_thickness_mm, " mm");
  }
}

}  // namespace

SoftTissues synthesise_soft_tissues(const SoftTissueRequest& request) {
  const auto start = SteadyClock::now();
  check_request(request);
  const TriMesh& femur = *request.femur;
  const TriMesh& pelvis = *request.pelvis;
  const SoftTissueOptions& o = request.options;
  // The head sphere's centre selects the head region; the layers are extruded along the rays from
  // the joint centre (the FE meshes and the depths look from there).
  const Vec3 c = request.joint_centre_mm.value_or(request.head_centre_mm);
  SoftTissues out;
  SoftTissueReport& report = out.report;
  const EdgeAdjacency femur_edges(femur), pelvis_edges(pelvis);
  Patches patches =
      find_patches(request, femur_edges, pelvis_edges, std::max(0.5, 2.5 * request.head_fit_rms_mm), report);
  const std::vector<double> t_f_nominal = nominal_femoral_thickness(femur, patches, c, o);

  const MeshQueries femur_queries(femur), pelvis_queries(pelvis);
  const double r_art = articular_radius(request, patches, pelvis_queries, t_f_nominal, c);
  report.articular_radius_mm = r_art;
  report.femoral_rim_peeled = peel_bare_rim(femur, femur_edges, patches, r_art, c, o.min_thickness_mm);
  remove_fossa(pelvis, pelvis_edges, patches, r_art, c, *request.acetabulum, o, report);
  if (std::count(patches.lunate_in.begin(), patches.lunate_in.end(), 1) < 20) {
    throw_error(request.pelvis_name, ": no lunate surface left outside the acetabular fossa (bone deeper than ",
                r_art + o.fossa_depth_mm, " mm from the joint centre)");
  }
  const std::vector<double> head_area = vertex_areas(femur, patches.head_in, patches.head);
  const std::vector<double> socket_area = vertex_areas(pelvis, patches.lunate_in, patches.socket);
  const LayerRadii femoral =
      femoral_layer(femur, patches.head, head_area, r_art, c, o, report.femoral);
  LayerRadii acetabular = acetabular_layer(pelvis, patches.socket, socket_area, r_art, c, o, report.acetabular);
  out.femoral_cartilage = layer_solid(femur, patches.head_in, patches.head, patches.head_boundary, c, femoral.r_in,
                                      femoral.r_out, femoral.thickness);
  clear_femoral_layer(acetabular, pelvis, patches.socket, out.femoral_cartilage, c, o);
  out.acetabular_cartilage = layer_solid(pelvis, patches.lunate_in, patches.socket, patches.socket_boundary, c,
                                         acetabular.r_in, acetabular.r_out, acetabular.thickness);
  fill_layer_numbers(report.femoral, head_area, femoral.thickness, out.femoral_cartilage);
  fill_layer_numbers(report.acetabular, socket_area, acetabular.thickness, out.acetabular_cartilage);

  const MeshQueries cartilage_queries(out.acetabular_cartilage);
  const LabrumSections placer(request, patches, femoral.thickness, femur_queries, pelvis_queries, cartilage_queries, c,
                              r_art);
  out.labrum = sweep_sections(labrum_sections(request, placer, patches.socket, report), report);
  if (out.labrum.empty()) {
    throw_error(request.pelvis_name, ": no labrum could be placed on the acetabular rim (", report.labrum_dropped_pelvis,
                " sections inside the pelvis, ", report.labrum_dropped_femur, " on the femur, ",
                report.labrum_missing_rim, " without rim)");
  }
  report.labrum_volume_mm3 = geometry::signed_volume(out.labrum);
  report.seconds = seconds_since(start);
  return out;
}

}  // namespace hipfai::anatomy
