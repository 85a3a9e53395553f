#include "contact/oracle_radial.h"

#include "contact/ray_triangle.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <vector>

namespace hipfai::contact {

namespace {

struct Hit {
  double t;
  int facing;
  std::int32_t triangle;
};

// Every crossing of the ray from `centre` along `direction` with every fixed triangle, in
// triangle order.
std::vector<Hit> all_crossings(const geometry::TriMesh& fixed, const Vec3& centre, const Vec3& direction) {
  std::vector<Hit> hits;
  for (std::size_t t = 0; t < fixed.num_triangles(); ++t) {
    const auto& tri = fixed.triangles[t];
    const RayCrossing crossing = ray_triangle_crossing(
        direction, fixed.vertices[static_cast<std::size_t>(tri[0])] - centre,
        fixed.vertices[static_cast<std::size_t>(tri[1])] - centre,
        fixed.vertices[static_cast<std::size_t>(tri[2])] - centre);
    if (crossing.hit) hits.push_back({crossing.t, crossing.facing, static_cast<std::int32_t>(t)});
  }
  return hits;
}

// The accepted hit with the smallest t (`smallest`) or the largest; equal t keeps the lowest
// triangle index (hits come in triangle order). Null when no hit is accepted.
template <typename Accept>
const Hit* pick(const std::vector<Hit>& hits, bool smallest, Accept accept) {
  const Hit* best = nullptr;
  for (const Hit& h : hits) {
    if (!accept(h.t)) continue;
    if (best == nullptr || (smallest ? h.t < best->t : h.t > best->t)) best = &h;
  }
  return best;
}

// kUnion by brute force: every crossing of every triangle, then the winding number evaluated
// directly at the midpoint between consecutive distinct crossing distances.
PenetrationResult oracle_radial_union(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                                      const Vec3& centre, RadialConfiguration configuration) {
  PenetrationResult result;
  const bool inside_fixed = configuration == RadialConfiguration::kMobileInsideFixed;
  for (std::size_t v = 0; v < mobile.num_vertices(); ++v) {
    const Vec3 direction = mobile.vertices[v] - centre;
    if (direction.isZero(0.0)) continue;
    // One geometric crossing split over triangles sharing an edge or vertex counts once.
    std::vector<Hit> hits;
    for (const Hit& crossing : all_crossings(fixed, centre, direction)) {
      const auto& tri = fixed.triangles[static_cast<std::size_t>(crossing.triangle)];
      bool duplicate = false;
      for (const Hit& h : hits) {
        if (h.facing != crossing.facing || std::abs(h.t - crossing.t) > 1e-12 * crossing.t) continue;
        for (auto i : fixed.triangles[static_cast<std::size_t>(h.triangle)]) {
          for (auto j : tri) duplicate = duplicate || i == j;
        }
      }
      if (!duplicate) hits.push_back(crossing);
    }
    auto winding_at = [&](double s) {
      int w = 0;
      for (const Hit& h : hits) w += h.t > s ? h.facing : 0;
      return w;
    };
    bool on_surface = false;
    for (const Hit& h : hits) on_surface = on_surface || h.t == 1.0;
    if (on_surface || winding_at(1.0) <= 0) continue;
    // The boundary of the union region containing t = 1: the nearest crossing distance at which
    // the winding number on the far side (from v) drops to zero.
    double boundary = inside_fixed ? 0.0 : -1.0;
    std::int32_t triangle = -1;
    // Distinct crossing distances; crossings within a relative 1e-12 are one distance (the shared
    // face of two touching solids).
    std::vector<double> all;
    for (const Hit& h : hits) all.push_back(h.t);
    std::sort(all.begin(), all.end());
    std::vector<double> distances;
    for (double t : all) {
      if (distances.empty() || t > distances.back() * (1.0 + 1e-12)) distances.push_back(t);
    }
    auto same = [](double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(a, b); };
    if (inside_fixed) {
      for (auto it = distances.rbegin(); it != distances.rend(); ++it) {
        if (*it >= 1.0) continue;
        const double below = std::next(it) == distances.rend() ? 0.0 : *std::next(it);
        if (winding_at(0.5 * (*it + below)) == 0) {
          boundary = *it;
          break;
        }
      }
    } else {
      for (auto it = distances.begin(); it != distances.end(); ++it) {
        if (*it <= 1.0) continue;
        if (winding_at(*it * (1.0 + 2e-12)) == 0) {  // just beyond this distance group
          boundary = *it;
          break;
        }
      }
      if (boundary < 0.0) continue;
    }
    // Report the lowest-index triangle of the boundary group that faces the right way (entering
    // for the inward boundary, exiting for the outward one), and its own distance.
    double boundary_t = boundary;
    for (const Hit& h : hits) {
      if (!same(h.t, boundary) || h.facing != (inside_fixed ? -1 : 1)) continue;
      if (triangle < 0 || h.triangle < triangle) triangle = h.triangle, boundary_t = h.t;
    }
    boundary = boundary_t;
    const double depth = (inside_fixed ? 1.0 - boundary : boundary - 1.0) * direction.norm();
    result.pairs.push_back({static_cast<std::int32_t>(v), triangle, depth});
  }
  return result;
}

}  // namespace

PenetrationResult oracle_radial(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                                const Vec3& centre, RadialConfiguration configuration,
                                RadialCrossingRule rule) {
  if (rule == RadialCrossingRule::kUnion) return oracle_radial_union(fixed, mobile, centre, configuration);
  PenetrationResult result;
  const bool inside_fixed = configuration == RadialConfiguration::kMobileInsideFixed;
  for (std::size_t v = 0; v < mobile.num_vertices(); ++v) {
    const Vec3 direction = mobile.vertices[v] - centre;
    if (direction.isZero(0.0)) continue;
    const auto hits = all_crossings(fixed, centre, direction);
    const Hit* best = nullptr;
    if (rule == RadialCrossingRule::kBeyond) {
      // The crossing farthest from v on its side: towards O (smallest t in (0, 1)) or away (largest t > 1).
      best = pick(hits, inside_fixed, [&](double t) { return inside_fixed ? t > 0.0 && t < 1.0 : t > 1.0; });
      if (best == nullptr) continue;
    } else {
      // The adjacent crossing: nearest v on its side (largest t <= 1, or smallest t >= 1); the
      // normals decide, and a vertex on the surface does not penetrate.
      best = pick(hits, !inside_fixed, [&](double t) { return inside_fixed ? t <= 1.0 : t >= 1.0; });
      if (best == nullptr || best->t == 1.0 || best->facing != (inside_fixed ? -1 : 1)) continue;
    }
    const double depth = (inside_fixed ? 1.0 - best->t : best->t - 1.0) * direction.norm();
    result.pairs.push_back({static_cast<std::int32_t>(v), best->triangle, depth});
  }
  return result;
}

}  // namespace hipfai::contact
