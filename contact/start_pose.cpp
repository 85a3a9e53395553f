#include "contact/start_pose.h"

#include "contact/arc_triangle.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_table.h"
#include "core/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;

const Vec3& corner(const TriMesh& mesh, std::size_t t, int k) {
  return mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][static_cast<std::size_t>(k)])];
}

// Uniform grid of a mesh's triangles, each listed in every cell its bounding box meets. Serves
// the nearest-triangle distance of inside vertices and the broad phase of the triangle pairs.
class TriangleGrid {
 public:
  explicit TriangleGrid(const TriMesh& mesh) : mesh_(mesh), stamp_(mesh.num_triangles(), 0) {
    const geometry::BoundingBox box = geometry::bounding_box(mesh);
    origin_ = box.min;
    const Vec3 extent = box.extent();
    // About two mean edges per cell keeps a few triangles per cell; never more cells than
    // eight per triangle (thin or sparse meshes), never a zero cell.
    cell_mm_ = std::max(2.0 * geometry::mean_edge_length(mesh), 1e-9 * (1.0 + extent.maxCoeff()));
    const double max_cells = 8.0 * static_cast<double>(std::max<std::size_t>(mesh.num_triangles(), 1));
    while ((std::floor(extent.x() / cell_mm_) + 1) * (std::floor(extent.y() / cell_mm_) + 1) *
               (std::floor(extent.z() / cell_mm_) + 1) > max_cells) {
      cell_mm_ *= 1.5;
    }
    for (int axis = 0; axis < 3; ++axis) dims_[axis] = static_cast<int>(std::floor(extent[axis] / cell_mm_)) + 1;
    const std::size_t num_cells = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
    std::vector<std::uint32_t> counts(num_cells + 1, 0);
    auto for_each_cell = [&](std::size_t t, auto&& visit) {
      std::array<int, 3> lo{}, hi{};
      cell_range(triangle_min(t), triangle_max(t), lo, hi);
      for (int k = lo[2]; k <= hi[2]; ++k) {
        for (int j = lo[1]; j <= hi[1]; ++j) {
          for (int i = lo[0]; i <= hi[0]; ++i) visit(index(i, j, k));
        }
      }
    };
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) for_each_cell(t, [&](std::size_t c) { ++counts[c + 1]; });
    for (std::size_t c = 0; c < num_cells; ++c) counts[c + 1] += counts[c];
    start_ = counts;
    items_.resize(counts.back());
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
      for_each_cell(t, [&](std::size_t c) { items_[counts[c]++] = static_cast<std::int32_t>(t); });
    }
  }

  Vec3 triangle_min(std::size_t t) const {
    return corner(mesh_, t, 0).cwiseMin(corner(mesh_, t, 1)).cwiseMin(corner(mesh_, t, 2));
  }
  Vec3 triangle_max(std::size_t t) const {
    return corner(mesh_, t, 0).cwiseMax(corner(mesh_, t, 1)).cwiseMax(corner(mesh_, t, 2));
  }

  // Calls visit(t) once for every triangle listed in a cell that the box [lo, hi] meets (a
  // superset of the triangles whose bounding boxes meet it).
  template <typename Visit>
  void for_each_near(const Vec3& lo, const Vec3& hi, Visit&& visit) const {
    std::array<int, 3> first{}, last{};
    if (!cell_range(lo, hi, first, last)) return;
    if (++current_stamp_ == 0) {  // wrapped: forget every old mark
      std::fill(stamp_.begin(), stamp_.end(), 0);
      current_stamp_ = 1;
    }
    for (int k = first[2]; k <= last[2]; ++k) {
      for (int j = first[1]; j <= last[1]; ++j) {
        for (int i = first[0]; i <= last[0]; ++i) {
          const std::size_t c = index(i, j, k);
          for (std::uint32_t n = start_[c]; n < start_[c + 1]; ++n) {
            const std::int32_t t = items_[n];
            if (stamp_[static_cast<std::size_t>(t)] == current_stamp_) continue;
            stamp_[static_cast<std::size_t>(t)] = current_stamp_;
            visit(t);
          }
        }
      }
    }
  }

  // Exact distance from p to the mesh, given that it is at most `upper_bound_mm`: boxes of
  // half-width r around p, r doubling from one cell; a triangle outside the box is farther than r.
  double distance(const Vec3& p, double upper_bound_mm) const {
    double best = std::numeric_limits<double>::infinity();
    for (double r = cell_mm_;; r *= 2.0) {
      const double half = std::min(r, upper_bound_mm);
      for_each_near(p - Vec3::Constant(half), p + Vec3::Constant(half), [&](std::int32_t t) {
        const auto u = static_cast<std::size_t>(t);
        best = std::min(best, point_triangle_distance(p, corner(mesh_, u, 0), corner(mesh_, u, 1), corner(mesh_, u, 2)));
      });
      if (best <= half || half >= upper_bound_mm) return std::min(best, upper_bound_mm);
    }
  }

 private:
  // Cells [first, last] covering the box, clipped to the grid; false if the box misses the grid.
  bool cell_range(const Vec3& lo, const Vec3& hi, std::array<int, 3>& first, std::array<int, 3>& last) const {
    for (int axis = 0; axis < 3; ++axis) {
      const double a = std::floor((lo[axis] - origin_[axis]) / cell_mm_);
      const double b = std::floor((hi[axis] - origin_[axis]) / cell_mm_);
      if (b < 0.0 || a >= dims_[axis]) return false;
      first[static_cast<std::size_t>(axis)] = static_cast<int>(std::max(a, 0.0));
      last[static_cast<std::size_t>(axis)] = static_cast<int>(std::min(b, dims_[axis] - 1.0));
    }
    return true;
  }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * dims_[1] + j) * dims_[0] + i;
  }

  const TriMesh& mesh_;
  Vec3 origin_ = Vec3::Zero();
  double cell_mm_ = 1.0;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::uint32_t> start_;  // cell -> first entry in items_ (CSR)
  std::vector<std::int32_t> items_;
  mutable std::vector<std::uint32_t> stamp_;  // triangle -> last query that visited it
  mutable std::uint32_t current_stamp_ = 0;
};

struct InsideVertices {
  std::size_t count = 0;
  double deepest_mm = 0.0;
  std::int32_t deepest_vertex = -1;
  std::vector<std::uint8_t> inside;  // vertex -> inside the solid at any depth (winding > 0)
};

// Vertices of `points` inside the closed solid `solid` deeper than the tolerance: the kUnion
// radial query finds the inside ones (its depth along the ray bounds the distance from above),
// the grid gives each one's exact distance to the surface.
InsideVertices vertices_inside(const TriMesh& solid, const TriangleGrid& solid_grid, const TriMesh& points,
                               const Vec3& centre, const StartPoseOptions& options) {
  RadialTableOptions table_options;
  table_options.table_size = std::max<std::int64_t>(64, static_cast<std::int64_t>(solid.num_triangles()));
  const RadialTable table = build_radial_table(solid, centre, table_options);
  RadialQueryOptions query;
  query.configuration = RadialConfiguration::kFixedInsideMobile;  // depth measured away from O
  query.rule = RadialCrossingRule::kUnion;
  query.num_threads = std::clamp(options.num_threads, 1, 2);
  const PenetrationResult result = radial_segmenting(table, solid, points, query);
  if (result.status == QueryStatus::kInvalidInput) throw_error(result.message);
  InsideVertices inside;
  inside.inside.assign(points.num_vertices(), 0);
  for (const PenetrationPair& pair : result.pairs) {
    inside.inside[static_cast<std::size_t>(pair.mobile_vertex)] = 1;
    if (!(pair.depth_mm > options.touching_mm)) continue;  // the distance is at most the ray depth
    const double depth = solid_grid.distance(points.vertices[static_cast<std::size_t>(pair.mobile_vertex)], pair.depth_mm);
    if (!(depth > options.touching_mm)) continue;
    ++inside.count;
    if (depth > inside.deepest_mm) {
      inside.deepest_mm = depth;
      inside.deepest_vertex = pair.mobile_vertex;
    }
  }
  return inside;
}

struct EdgeCrossing {
  double t = 0.0;           // along the edge, 0 at its first vertex, 1 at its second
  int facing = 0;           // +1 the edge leaves the solid there, -1 it enters
  std::int32_t triangle = -1;
};

struct EdgesThrough {
  std::size_t count = 0;
  double deepest_mm = 0.0;
};

// Edges of `edges_of` with a stretch inside `solid` deeper than the tolerance (header comment).
EdgesThrough edges_through(const TriMesh& edges_of, const std::vector<std::uint8_t>& vertex_inside,
                           const TriMesh& solid, const TriangleGrid& solid_grid, double touching_mm) {
  const geometry::BoundingBox solid_box = geometry::bounding_box(solid);
  EdgesThrough through;
  std::vector<EdgeCrossing> crossings, unique;
  for (const auto& triangle : edges_of.triangles) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::int32_t a = triangle[k], b = triangle[(k + 1) % 3];
      if (a > b) continue;  // each edge once: its twin in the neighbouring triangle runs a < b
      const Vec3& pa = edges_of.vertices[static_cast<std::size_t>(a)];
      const Vec3& pb = edges_of.vertices[static_cast<std::size_t>(b)];
      const Vec3 lo = pa.cwiseMin(pb), hi = pa.cwiseMax(pb);
      if ((lo.array() > solid_box.max.array()).any() || (hi.array() < solid_box.min.array()).any()) continue;
      const Vec3 along = pb - pa;
      crossings.clear();
      solid_grid.for_each_near(lo, hi, [&](std::int32_t f) {
        const auto u = static_cast<std::size_t>(f);
        if ((lo.array() > solid_grid.triangle_max(u).array()).any() ||
            (hi.array() < solid_grid.triangle_min(u).array()).any()) {
          return;
        }
        const RayCrossing c = ray_triangle_crossing(along, corner(solid, u, 0) - pa, corner(solid, u, 1) - pa,
                                                    corner(solid, u, 2) - pa);
        if (c.hit && c.t < 1.0) crossings.push_back({c.t, c.facing, f});
      });
      if (crossings.empty()) continue;
      std::sort(crossings.begin(), crossings.end(), [](const EdgeCrossing& x, const EdgeCrossing& y) {
        return x.t != y.t ? x.t < y.t : x.triangle < y.triangle;
      });
      // One hit split over the triangles around a shared edge or vertex counts once.
      unique.clear();
      for (const EdgeCrossing& c : crossings) {
        const bool duplicate = !unique.empty() && unique.back().facing == c.facing &&
                               c.t - unique.back().t <= 1e-12 && geometry::triangles_share_a_vertex(solid, unique.back().triangle, c.triangle);
        if (!duplicate) unique.push_back(c);
      }
      // Inside stretches [start, end]: at least one end is a crossing, on the surface, so the
      // midpoint is at most half the stretch from it.
      double deepest = 0.0;
      auto stretch = [&](double start, double end) {
        const double half_mm = 0.5 * (end - start) * along.norm();
        if (!(half_mm > touching_mm)) return;
        deepest = std::max(deepest, solid_grid.distance(pa + 0.5 * (start + end) * along, half_mm));
      };
      int winding = vertex_inside[static_cast<std::size_t>(a)] ? 1 : 0;
      double start = 0.0;
      for (const EdgeCrossing& c : unique) {
        const int before = winding;
        winding -= c.facing;
        if (before > 0 && winding <= 0) stretch(start, c.t);
        if (before <= 0 && winding > 0) start = c.t;
      }
      if (winding > 0) stretch(start, 1.0);
      if (deepest > touching_mm) {
        ++through.count;
        through.deepest_mm = std::max(through.deepest_mm, deepest);
      }
    }
  }
  return through;
}

}  // namespace

double StartPoseOverlap::deepest_mm() const {
  return std::max({mobile_deepest_mm, fixed_deepest_mm, edge_deepest_mm});
}

std::string StartPoseOverlap::summary() const {
  auto vertices = [](std::size_t count, double deepest_mm, const char* of, const char* in) {
    char part[128];
    if (count == 0) {
      std::snprintf(part, sizeof(part), "no %s vertex inside the %s mesh", of, in);
    } else {
      std::snprintf(part, sizeof(part), "%zu %s vert%s inside the %s mesh (deepest %.3g mm)", count, of,
                    count == 1 ? "ex" : "ices", in, deepest_mm);
    }
    return std::string(part);
  };
  const std::size_t edges = mobile_edges_through + fixed_edges_through;
  char part[128];
  if (edges == 0) {
    std::snprintf(part, sizeof(part), "no edge through the other surface");
  } else {
    std::snprintf(part, sizeof(part), "%zu edge%s through the other surface (deepest %.3g mm)", edges,
                  edges == 1 ? "" : "s", edge_deepest_mm);
  }
  return vertices(mobile_vertices_inside, mobile_deepest_mm, "mobile", "fixed") + ", " +
         vertices(fixed_vertices_inside, fixed_deepest_mm, "fixed", "mobile") + ", " + part;
}

StartPoseOverlap check_start_pose(const TriMesh& fixed, const TriMesh& mobile, const StartPoseOptions& options) {
  StartPoseOverlap overlap;
  overlap.touching_mm = options.touching_mm;
  try {
    if (!(options.touching_mm >= 0.0) || !std::isfinite(options.touching_mm)) {
      throw_error("start pose: touching_mm must be finite and >= 0");
    }
    geometry::validate_mesh(fixed, "start pose: fixed mesh");
    geometry::validate_mesh(mobile, "start pose: mobile mesh");
    const geometry::BoundingBox box = geometry::bounding_box(fixed);
    const Vec3 centre = options.centre.value_or(0.5 * (box.min + box.max));
    if (!centre.allFinite()) throw_error("start pose: centre is not finite");
    const TriangleGrid fixed_grid(fixed);
    const TriangleGrid mobile_grid(mobile);
    const InsideVertices mobile_inside = vertices_inside(fixed, fixed_grid, mobile, centre, options);
    const InsideVertices fixed_inside = vertices_inside(mobile, mobile_grid, fixed, centre, options);
    overlap.mobile_vertices_inside = mobile_inside.count;
    overlap.mobile_deepest_mm = mobile_inside.deepest_mm;
    overlap.mobile_deepest_vertex = mobile_inside.deepest_vertex;
    overlap.fixed_vertices_inside = fixed_inside.count;
    overlap.fixed_deepest_mm = fixed_inside.deepest_mm;
    overlap.fixed_deepest_vertex = fixed_inside.deepest_vertex;
    if (options.check_edges) {
      const EdgesThrough mobile_edges = edges_through(mobile, mobile_inside.inside, fixed, fixed_grid, options.touching_mm);
      const EdgesThrough fixed_edges = edges_through(fixed, fixed_inside.inside, mobile, mobile_grid, options.touching_mm);
      overlap.mobile_edges_through = mobile_edges.count;
      overlap.fixed_edges_through = fixed_edges.count;
      overlap.edge_deepest_mm = std::max(mobile_edges.deepest_mm, fixed_edges.deepest_mm);
    }
  } catch (const Error& e) {
    StartPoseOverlap invalid;
    invalid.status = QueryStatus::kInvalidInput;
    invalid.message = e.what();
    invalid.touching_mm = options.touching_mm;
    return invalid;
  }
  return overlap;
}

}  // namespace hipfai::contact
