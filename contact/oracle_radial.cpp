#include "contact/oracle_radial.h"

#include "contact/ray_triangle.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <vector>

namespace hipfai::contact {

namespace {

// kUnion by brute force: every crossing of every triangle, then the winding number evaluated
// directly at the midpoint between consecutive distinct crossing distances.
PenetrationResult oracle_radial_union(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                                      const Vec3& centre, RadialConfiguration configuration) {
  PenetrationResult result;
  const bool inside_fixed = configuration == RadialConfiguration::kMobileInsideFixed;
  for (std::size_t v = 0; v < mobile.num_vertices(); ++v) {
    const Vec3 direction = mobile.vertices[v] - centre;
    if (direction.isZero(0.0)) continue;
    struct Hit {
      double t;
      int facing;
      std::int32_t triangle;
    };
    std::vector<Hit> hits;
    for (std::size_t t = 0; t < fixed.num_triangles(); ++t) {
      const auto& tri = fixed.triangles[t];
      const RayCrossing crossing = ray_triangle_crossing(
          direction, fixed.vertices[static_cast<std::size_t>(tri[0])] - centre,
          fixed.vertices[static_cast<std::size_t>(tri[1])] - centre,
          fixed.vertices[static_cast<std::size_t>(tri[2])] - centre);
      if (!crossing.hit) continue;
      // One geometric crossing split over triangles sharing an edge or vertex counts once.
      bool duplicate = false;
      for (const Hit& h : hits) {
        if (h.facing != crossing.facing || std::abs(h.t - crossing.t) > 1e-12 * crossing.t) continue;
        for (auto i : fixed.triangles[static_cast<std::size_t>(h.triangle)]) {
          for (auto j : tri) duplicate = duplicate || i == j;
        }
      }
      if (!duplicate) hits.push_back({crossing.t, crossing.facing, static_cast<std::int32_t>(t)});
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
    // Collect the adjacent crossing by a full scan; the lowest index wins ties because the scan
    // goes upward and only a strictly closer crossing replaces the current one.
    bool found = false;
    double best_t = 0.0;
    int best_facing = 0;
    std::int32_t best_triangle = -1;
    for (std::size_t t = 0; t < fixed.num_triangles(); ++t) {
      const auto& tri = fixed.triangles[t];
      const RayCrossing crossing = ray_triangle_crossing(
          direction, fixed.vertices[static_cast<std::size_t>(tri[0])] - centre,
          fixed.vertices[static_cast<std::size_t>(tri[1])] - centre,
          fixed.vertices[static_cast<std::size_t>(tri[2])] - centre);
      if (!crossing.hit) continue;
      const bool on_side = inside_fixed ? crossing.t <= 1.0 : crossing.t >= 1.0;
      if (!on_side) continue;
      const bool closer = inside_fixed ? crossing.t > best_t : crossing.t < best_t;
      if (!found || closer) {
        found = true;
        best_t = crossing.t;
        best_facing = crossing.facing;
        best_triangle = static_cast<std::int32_t>(t);
      }
    }
    if (!found || best_t == 1.0) continue;
    if (best_facing != (inside_fixed ? -1 : 1)) continue;
    const double depth = (inside_fixed ? 1.0 - best_t : best_t - 1.0) * direction.norm();
    result.pairs.push_back({static_cast<std::int32_t>(v), best_triangle, depth});
  }
  return result;
}

}  // namespace hipfai::contact
