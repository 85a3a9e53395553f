#include "bench/spatial_hashing.h"

#include "contact/ray_triangle.h"
#include "core/error.h"
#include "core/parallel.h"
#include "geometry/gmsh_runtime.h"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>

namespace hipfai::bench {

using Eigen::Vector3d;
using Box = std::pair<Vector3d, Vector3d>;

namespace {

std::size_t next_prime(std::size_t n) {
  if (n < 3) return 3;
  for (std::size_t candidate = n | 1u;; candidate += 2) {
    bool prime = true;
    for (std::size_t d = 3; d * d <= candidate; d += 2) {
      if (candidate % d == 0) {
        prime = false;
        break;
      }
    }
    if (prime) return candidate;
  }
}

bool boxes_overlap(const Box& a, const Box& b) {
  return (a.first.array() <= b.second.array()).all() && (b.first.array() <= a.second.array()).all();
}

Box box_of(const std::array<Vector3d, 3>& p) {
  return {p[0].cwiseMin(p[1]).cwiseMin(p[2]), p[0].cwiseMax(p[1]).cwiseMax(p[2])};
}

std::array<Vector3d, 3> corners(const geometry::TriMesh& mesh, std::size_t t) {
  const auto& tri = mesh.triangles[t];
  return {mesh.vertices[static_cast<std::size_t>(tri[0])], mesh.vertices[static_cast<std::size_t>(tri[1])],
          mesh.vertices[static_cast<std::size_t>(tri[2])]};
}

}  // namespace

TetMesh tetrahedralize(const geometry::TriMesh& closed_surface) {
  // gmsh's runtime is process-wide and shared with the hip generator and the volume mesher: held
  // for the whole use (the lock also initialises gmsh, quiet, on first use). After a failed 3D mesh
  // gmsh keeps an error state in which later meshing silently produces nothing (clear() does not
  // end it): every failure below restarts gmsh under this lock.
  const std::unique_lock<std::mutex> gmsh_lock = geometry::lock_gmsh();
  TetMesh out;
  try {
    gmsh::clear();
    gmsh::model::add("hipfai_bench_tetrahedralize");
    gmsh::option::setNumber("General.Terminal", 0);
    const int surface = gmsh::model::addDiscreteEntity(2);
    std::vector<std::size_t> node_tags(closed_surface.vertices.size());
    std::vector<double> coords;
    coords.reserve(3 * node_tags.size());
    for (std::size_t i = 0; i < node_tags.size(); ++i) {
      node_tags[i] = i + 1;
      for (int k = 0; k < 3; ++k) coords.push_back(closed_surface.vertices[i][k]);
    }
    gmsh::model::mesh::addNodes(2, surface, node_tags, coords);
    std::vector<std::size_t> triangle_nodes;
    triangle_nodes.reserve(3 * closed_surface.triangles.size());
    for (const auto& t : closed_surface.triangles) {
      for (int k = 0; k < 3; ++k) triangle_nodes.push_back(static_cast<std::size_t>(t[static_cast<std::size_t>(k)]) + 1);
    }
    gmsh::model::mesh::addElementsByType(surface, 2, {}, triangle_nodes);
    const int loop = gmsh::model::geo::addSurfaceLoop({surface});
    gmsh::model::geo::addVolume({loop});
    gmsh::model::geo::synchronize();
    // gmsh's default 3D Delaunay, sizes from the boundary only (no global size limit left over
    // from another user of the runtime, so no needless interior refinement) and no optimisation:
    // hashing needs a valid tetrahedralization, not quality tets. (HXT was tried: it aborts the
    // process on some of these boxes.) Options are global in gmsh: restored afterwards.
    const std::vector<std::pair<const char*, double>> settings{
        {"Mesh.Algorithm3D", 1.0}, {"Mesh.Optimize", 0.0}, {"Mesh.MeshSizeMax", 1e22},
        {"Mesh.MeshSizeMin", 0.0}, {"Mesh.MeshSizeExtendFromBoundary", 1.0}};
    std::vector<double> saved(settings.size(), 0.0);
    for (std::size_t i = 0; i < settings.size(); ++i) {
      gmsh::option::getNumber(settings[i].first, saved[i]);
      gmsh::option::setNumber(settings[i].first, settings[i].second);
    }
    const auto restore = [&] {
      for (std::size_t i = 0; i < settings.size(); ++i) gmsh::option::setNumber(settings[i].first, saved[i]);
    };
    try {
      gmsh::model::mesh::generate(3);
    } catch (...) {
      restore();
      throw;
    }
    restore();

    std::vector<std::size_t> all_tags;
    std::vector<double> all_coords, parametric;
    gmsh::model::mesh::getNodes(all_tags, all_coords, parametric, -1, -1, false, false);
    std::map<std::size_t, std::int32_t> index;
    out.nodes.reserve(all_tags.size());
    for (std::size_t i = 0; i < all_tags.size(); ++i) {
      index[all_tags[i]] = static_cast<std::int32_t>(out.nodes.size());
      out.nodes.emplace_back(all_coords[3 * i], all_coords[3 * i + 1], all_coords[3 * i + 2]);
    }
    std::vector<std::size_t> element_tags, tet_nodes;
    gmsh::model::mesh::getElementsByType(4, element_tags, tet_nodes);
    out.tets.reserve(element_tags.size());
    for (std::size_t e = 0; e < element_tags.size(); ++e) {
      std::array<std::int32_t, 4> tet{};
      for (std::size_t k = 0; k < 4; ++k) tet[k] = index.at(tet_nodes[4 * e + k]);
      out.tets.push_back(tet);
    }
    gmsh::clear();
  } catch (const std::exception& error) {
    geometry::reset_gmsh_locked(gmsh_lock);
    throw_error("tetrahedralize: gmsh failed: ", error.what());
  } catch (...) {
    geometry::reset_gmsh_locked(gmsh_lock);
    throw_error("tetrahedralize: gmsh failed on the surface mesh (self-intersecting or open?)");
  }
  if (out.tets.empty()) {
    geometry::reset_gmsh_locked(gmsh_lock);
    throw_error("tetrahedralize: gmsh produced no tetrahedra (self-intersecting or open surface?)");
  }
  return out;
}

SpatialHashGrid::SpatialHashGrid(const std::vector<Box>& boxes, double cell_size_mm,
                                 std::size_t table_size)
    : cell_(cell_size_mm), table_size_(table_size) {
  if (!(cell_ > 0.0) || table_size_ == 0) throw_error("spatial hashing: cell size and table size must be positive");
  const double pad = 1e-9 * cell_;
  std::vector<std::size_t> count(table_size_ + 1, 0);
  auto for_cells = [&](const Box& box, auto&& fn) {
    const auto lo = cell_of(box.first - Vector3d::Constant(pad));
    const auto hi = cell_of(box.second + Vector3d::Constant(pad));
    for (long long i = lo[0]; i <= hi[0]; ++i)
      for (long long j = lo[1]; j <= hi[1]; ++j)
        for (long long k = lo[2]; k <= hi[2]; ++k) fn(bucket(i, j, k));
  };
  for (const auto& box : boxes) for_cells(box, [&](std::size_t b) { ++count[b + 1]; });
  for (std::size_t b = 0; b < table_size_; ++b) count[b + 1] += count[b];
  start_ = count;
  entries_.resize(start_.back());
  std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t p = 0; p < boxes.size(); ++p) {
    for_cells(boxes[p], [&](std::size_t b) { entries_[fill[b]++] = static_cast<std::int32_t>(p); });
  }
}

std::array<long long, 3> SpatialHashGrid::cell_of(const Vector3d& p) const {
  return {static_cast<long long>(std::floor(p.x() / cell_)), static_cast<long long>(std::floor(p.y() / cell_)),
          static_cast<long long>(std::floor(p.z() / cell_))};
}

std::size_t SpatialHashGrid::bucket(long long i, long long j, long long k) const {
  // The three large primes of Teschner et al. (2003).
  const auto h = (static_cast<std::uint64_t>(i) * 73856093ull) ^
                 (static_cast<std::uint64_t>(j) * 19349663ull) ^
                 (static_cast<std::uint64_t>(k) * 83492791ull);
  return static_cast<std::size_t>(h % table_size_);
}

// ---------------------------------------------------------------- tetrahedral variant

TetSpatialHash::TetSpatialHash(TetMesh tets, const SpatialHashOptions& options)
    : mesh_(std::move(tets)) {
  double edge_sum = 0.0;
  std::size_t edges = 0;
  boxes_.reserve(mesh_.tets.size());
  for (const auto& tet : mesh_.tets) {
    Vector3d lo = mesh_.nodes[static_cast<std::size_t>(tet[0])], hi = lo;
    for (std::size_t k = 1; k < 4; ++k) {
      lo = lo.cwiseMin(mesh_.nodes[static_cast<std::size_t>(tet[k])]);
      hi = hi.cwiseMax(mesh_.nodes[static_cast<std::size_t>(tet[k])]);
    }
    boxes_.emplace_back(lo, hi);
    for (std::size_t a = 0; a < 4; ++a) {
      for (std::size_t b = a + 1; b < 4; ++b) {
        edge_sum += (mesh_.nodes[static_cast<std::size_t>(tet[a])] - mesh_.nodes[static_cast<std::size_t>(tet[b])]).norm();
        ++edges;
      }
    }
  }
  const double cell = options.cell_size_mm > 0.0 ? options.cell_size_mm : (edges > 0 ? edge_sum / static_cast<double>(edges) : 1.0);
  const std::size_t size = options.table_size > 0 ? options.table_size : next_prime(2 * mesh_.tets.size());
  grid_ = SpatialHashGrid(boxes_, cell, size);
}

std::vector<std::int32_t> TetSpatialHash::penetrating_vertices(const geometry::TriMesh& posed_mobile,
                                                               int num_threads) const {
  const int threads = num_threads < 1 ? 1 : num_threads;
  std::vector<std::vector<std::int32_t>> per_chunk(static_cast<std::size_t>(threads));
  parallel_chunks(
      posed_mobile.vertices.size(), threads, [&](std::size_t begin, std::size_t end, int chunk) {
        auto& found = per_chunk[static_cast<std::size_t>(chunk)];
        for (std::size_t v = begin; v < end; ++v) {
          const Vector3d& p = posed_mobile.vertices[v];
          const auto cell = grid_.cell_of(p);
          const std::size_t b = grid_.bucket(cell[0], cell[1], cell[2]);
          for (const std::int32_t* it = grid_.begin(b); it != grid_.end(b); ++it) {
            const auto& box = boxes_[static_cast<std::size_t>(*it)];
            if ((p.array() < box.first.array()).any() || (p.array() > box.second.array()).any()) continue;
            const auto& tet = mesh_.tets[static_cast<std::size_t>(*it)];
            const Vector3d& a = mesh_.nodes[static_cast<std::size_t>(tet[0])];
            Eigen::Matrix3d m;
            m.col(0) = mesh_.nodes[static_cast<std::size_t>(tet[1])] - a;
            m.col(1) = mesh_.nodes[static_cast<std::size_t>(tet[2])] - a;
            m.col(2) = mesh_.nodes[static_cast<std::size_t>(tet[3])] - a;
            const Vector3d w = m.partialPivLu().solve(p - a);
            // Boundary inclusive (a relative 1e-12 of rounding) so that inner faces leave no crack.
            constexpr double kEps = 1e-12;
            if (w.minCoeff() >= -kEps && w.sum() <= 1.0 + kEps) {
              found.push_back(static_cast<std::int32_t>(v));
              break;
            }
          }
        }
      });
  std::vector<std::int32_t> all;
  for (auto& part : per_chunk) all.insert(all.end(), part.begin(), part.end());
  return all;
}

// ---------------------------------------------------------------- surface variant

SurfaceSpatialHash::SurfaceSpatialHash(const geometry::TriMesh& fixed, const SpatialHashOptions& options)
    : fixed_(fixed) {
  boxes_.reserve(fixed_.triangles.size());
  for (std::size_t t = 0; t < fixed_.triangles.size(); ++t) boxes_.push_back(box_of(corners(fixed_, t)));
  const auto box = geometry::bounding_box(fixed_);
  box_min_ = box.min;
  box_max_ = box.max;
  const double cell = options.cell_size_mm > 0.0 ? options.cell_size_mm : geometry::mean_edge_length(fixed_);
  const std::size_t size = options.table_size > 0 ? options.table_size : next_prime(2 * fixed_.triangles.size());
  grid_ = SpatialHashGrid(boxes_, cell > 0.0 ? cell : 1.0, size);
}

namespace {

// Clips the walk [s0, s1] along origin + s u to the box [lo_box, hi_box] (slab test); false
// when nothing is left of it.
bool clip_to_box(const Vector3d& origin, const Vector3d& u, const Vector3d& lo_box, const Vector3d& hi_box,
                 double& s0, double& s1) {
  for (int k = 0; k < 3 && s0 <= s1; ++k) {
    if (u[k] == 0.0) {
      if (origin[k] < lo_box[k] || origin[k] > hi_box[k]) s1 = -1.0;
      continue;
    }
    double a = (lo_box[k] - origin[k]) / u[k], b = (hi_box[k] - origin[k]) / u[k];
    if (a > b) std::swap(a, b);
    s0 = std::max(s0, a);
    s1 = std::min(s1, b);
  }
  return !(s0 > s1);
}

// 3D DDA through the grid's cells along u, from `start` (at s0 along the walk).
struct CellWalk {
  std::array<long long, 3> cell_index;
  std::array<long long, 3> step{};
  std::array<double, 3> s_next{}, s_delta{};

  CellWalk(const SpatialHashGrid& grid, const Vector3d& start, const Vector3d& u, double s0)
      : cell_index(grid.cell_of(start)) {
    const double cell = grid.cell_size_mm();
    for (int k = 0; k < 3; ++k) {
      const auto K = static_cast<std::size_t>(k);
      if (u[k] > 0.0) {
        step[K] = 1;
        s_next[K] = s0 + ((static_cast<double>(cell_index[K]) + 1.0) * cell - start[k]) / u[k];
        s_delta[K] = cell / u[k];
      } else if (u[k] < 0.0) {
        step[K] = -1;
        s_next[K] = s0 + (static_cast<double>(cell_index[K]) * cell - start[k]) / u[k];
        s_delta[K] = -cell / u[k];
      } else {
        s_next[K] = std::numeric_limits<double>::infinity();
        s_delta[K] = std::numeric_limits<double>::infinity();
      }
    }
  }
  // Where the walk leaves the current cell.
  double exit() const { return std::min({s_next[0], s_next[1], s_next[2]}); }
  void advance() {
    const int axis = s_next[0] <= s_next[1] ? (s_next[0] <= s_next[2] ? 0 : 2) : (s_next[1] <= s_next[2] ? 1 : 2);
    cell_index[static_cast<std::size_t>(axis)] += step[static_cast<std::size_t>(axis)];
    s_next[static_cast<std::size_t>(axis)] += s_delta[static_cast<std::size_t>(axis)];
  }
};

// The crossing of the ray centre + t d chosen for a vertex (t = 1 at the vertex).
struct RadialHit {
  bool found = false;
  double t = 0.0;
  std::int32_t triangle = -1;
  int facing = 0;
};

// One thread's radial queries: per mobile vertex, the fixed triangle its ray from the centre
// crosses nearest to it on the penetrating side, found by walking the hash grid along the ray.
struct RadialRayWalker {
  const SpatialHashGrid& grid;
  const geometry::TriMesh& fixed;
  const Vector3d& centre;
  bool mobile_inside;
  Vector3d lo_box, hi_box;
  std::vector<std::uint32_t> seen = std::vector<std::uint32_t>(fixed.triangles.size(), 0);
  std::uint32_t stamp = 0;

  bool penetration(std::size_t v, const Vector3d& origin, contact::PenetrationPair& pair) {
    const Vector3d d = origin - centre;
    const double r = d.norm();
    if (!(r > 0.0)) return false;
    const Vector3d u = mobile_inside ? Vector3d(-d / r) : Vector3d(d / r);
    // Clip the walk [0, s_end] to the fixed mesh's box.
    double s0 = 0.0, s1 = mobile_inside ? r : std::numeric_limits<double>::infinity();
    if (!clip_to_box(origin, u, lo_box, hi_box, s0, s1)) return false;
    if (++stamp == 0) {
      std::fill(seen.begin(), seen.end(), 0);
      stamp = 1;
    }
    const RadialHit hit = walk(d, r, u, origin, s0, s1);
    if (!hit.found) return false;
    const bool penetrates = mobile_inside ? (hit.t < 1.0 && hit.facing == -1) : (hit.t > 1.0 && hit.facing == +1);
    if (!penetrates) return false;
    pair.mobile_vertex = static_cast<std::int32_t>(v);
    pair.fixed_triangle = hit.triangle;
    pair.depth_mm = std::abs(mobile_inside ? 1.0 - hit.t : hit.t - 1.0) * r;
    return true;
  }

  // Cells from the entry point until the best crossing so far lies within the cells walked.
  RadialHit walk(const Vector3d& d, double r, const Vector3d& u, const Vector3d& origin, double s0, double s1) {
    CellWalk cells(grid, origin + s0 * u, u, s0);
    RadialHit hit;
    while (true) {
      test_bucket(grid.bucket(cells.cell_index[0], cells.cell_index[1], cells.cell_index[2]), d, hit);
      const double s_exit = cells.exit();
      if (hit.found && std::abs(1.0 - hit.t) * r <= s_exit) break;
      if (s_exit > s1) break;
      cells.advance();
    }
    return hit;
  }

  // The bucket's triangles not tested yet for this vertex; ties go to the lower triangle id.
  void test_bucket(std::size_t b, const Vector3d& d, RadialHit& hit) {
    for (const std::int32_t* it = grid.begin(b); it != grid.end(b); ++it) {
      const auto t = static_cast<std::size_t>(*it);
      if (seen[t] == stamp) continue;
      seen[t] = stamp;
      const auto& tri = fixed.triangles[t];
      const auto crossing = contact::ray_triangle_crossing(
          d, fixed.vertices[static_cast<std::size_t>(tri[0])] - centre,
          fixed.vertices[static_cast<std::size_t>(tri[1])] - centre,
          fixed.vertices[static_cast<std::size_t>(tri[2])] - centre);
      if (!crossing.hit) continue;
      const bool side_ok = mobile_inside ? crossing.t <= 1.0 : crossing.t >= 1.0;
      if (!side_ok) continue;
      const bool better = !hit.found || (mobile_inside ? crossing.t > hit.t : crossing.t < hit.t) ||
                          (crossing.t == hit.t && *it < hit.triangle);
      if (better) {
        hit.found = true;
        hit.t = crossing.t;
        hit.triangle = *it;
        hit.facing = crossing.facing;
      }
    }
  }
};

}  // namespace

contact::PenetrationResult SurfaceSpatialHash::radial_query(const geometry::TriMesh& posed_mobile,
                                                            const Vector3d& centre,
                                                            contact::RadialConfiguration configuration,
                                                            int num_threads) const {
  contact::PenetrationResult result;
  const bool mobile_inside = configuration == contact::RadialConfiguration::kMobileInsideFixed;
  const int threads = num_threads < 1 ? 1 : num_threads;
  const double cell = grid_.cell_size_mm();
  const Vector3d pad = Vector3d::Constant(1e-9 * cell);
  const Vector3d lo_box = box_min_ - pad, hi_box = box_max_ + pad;
  std::vector<std::vector<contact::PenetrationPair>> per_chunk(static_cast<std::size_t>(threads));
  parallel_chunks(
      posed_mobile.vertices.size(), threads, [&](std::size_t begin, std::size_t end, int chunk) {
        auto& pairs = per_chunk[static_cast<std::size_t>(chunk)];
        RadialRayWalker walker{grid_, fixed_, centre, mobile_inside, lo_box, hi_box};
        for (std::size_t v = begin; v < end; ++v) {
          contact::PenetrationPair pair;
          if (walker.penetration(v, posed_mobile.vertices[v], pair)) pairs.push_back(pair);
        }
      });
  for (auto& pairs : per_chunk) result.pairs.insert(result.pairs.end(), pairs.begin(), pairs.end());
  return result;
}

bool SurfaceSpatialHash::first_collision(const geometry::TriMesh& posed_mobile) const {
  const double pad = 1e-9 * grid_.cell_size_mm();
  for (std::size_t m = 0; m < posed_mobile.triangles.size(); ++m) {
    const auto tri = corners(posed_mobile, m);
    const Box box = box_of(tri);
    if ((box.second.array() < box_min_.array()).any() || (box.first.array() > box_max_.array()).any()) continue;
    const auto lo = grid_.cell_of(box.first - Vector3d::Constant(pad));
    const auto hi = grid_.cell_of(box.second + Vector3d::Constant(pad));
    for (long long i = lo[0]; i <= hi[0]; ++i)
      for (long long j = lo[1]; j <= hi[1]; ++j)
        for (long long k = lo[2]; k <= hi[2]; ++k) {
          const std::size_t b = grid_.bucket(i, j, k);
          for (const std::int32_t* it = grid_.begin(b); it != grid_.end(b); ++it) {
            const auto t = static_cast<std::size_t>(*it);
            if (!boxes_overlap(box, boxes_[t])) continue;
            if (triangles_intersect(tri, corners(fixed_, t))) return true;
          }
        }
  }
  return false;
}

bool segment_crosses_triangle(const Vector3d& p, const Vector3d& q, const Vector3d& a,
                              const Vector3d& b, const Vector3d& c) {
  const auto crossing = contact::ray_triangle_crossing(q - p, a - p, b - p, c - p);
  return crossing.hit && crossing.t <= 1.0;
}

bool triangles_intersect(const std::array<Vector3d, 3>& first, const std::array<Vector3d, 3>& second) {
  for (int pass = 0; pass < 2; ++pass) {
    const auto& edges_of = pass == 0 ? first : second;
    const auto& other = pass == 0 ? second : first;
    for (std::size_t e = 0; e < 3; ++e) {
      if (segment_crosses_triangle(edges_of[e], edges_of[(e + 1) % 3], other[0], other[1], other[2])) return true;
    }
  }
  return false;
}

}  // namespace hipfai::bench
