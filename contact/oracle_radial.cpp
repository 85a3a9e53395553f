#include "contact/oracle_radial.h"

#include "contact/ray_triangle.h"

namespace hipfai::contact {

PenetrationResult oracle_radial(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                                const Vec3& centre, RadialConfiguration configuration) {
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
