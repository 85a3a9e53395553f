#include "contact/ray_sampling.h"

#include "contact/ray_triangle.h"

#include <string>

namespace hipfai::contact {

namespace {

RayCrossing cross(const geometry::TriMesh& fixed, const Vec3& centre, const Vec3& direction,
                  std::int32_t t) {
  const auto& tri = fixed.triangles[static_cast<std::size_t>(t)];
  return ray_triangle_crossing(direction, fixed.vertices[static_cast<std::size_t>(tri[0])] - centre,
                               fixed.vertices[static_cast<std::size_t>(tri[1])] - centre,
                               fixed.vertices[static_cast<std::size_t>(tri[2])] - centre);
}

}  // namespace

RaySamplingTable build_ray_sampling_table(const geometry::TriMesh& fixed, const Vec3& centre,
                                          const RadialTableOptions& options,
                                          RadialConfiguration configuration,
                                          bool scan_all_triangles) {
  RadialTable exact;
  if (scan_all_triangles) {
    geometry::validate_mesh(fixed, "ray sampling table: fixed mesh");
    exact.grid = make_radial_grid(options.mapping, options.table_size);
    exact.always_candidates.resize(fixed.num_triangles());
    for (std::size_t t = 0; t < fixed.num_triangles(); ++t) {
      exact.always_candidates[t] = static_cast<std::int32_t>(t);
    }
    exact.cells.resize(static_cast<std::size_t>(exact.grid.num_cells()));
  } else {
    exact = build_radial_table(fixed, centre, options);
  }
  RaySamplingTable table;
  table.grid = exact.grid;
  table.centre = centre;
  table.configuration = configuration;
  table.num_triangles = fixed.num_triangles();
  table.cell_triangle.assign(static_cast<std::size_t>(table.grid.num_cells()), -1);
  const int wanted_facing = configuration == RadialConfiguration::kMobileInsideFixed ? -1 : 1;
  for (int id = 0; id < table.grid.num_cells(); ++id) {
    const Vec3 direction = cell_centre_direction(table.grid, id);
    double best_t = 0.0;
    std::int32_t best = -1;
    auto visit = [&](const std::vector<std::int32_t>& candidates) {
      for (const std::int32_t t : candidates) {
        const RayCrossing crossing = cross(fixed, centre, direction, t);
        if (!crossing.hit || crossing.facing != wanted_facing) continue;
        if (best < 0 || crossing.t < best_t || (crossing.t == best_t && t < best)) {
          best = t;
          best_t = crossing.t;
        }
      }
    };
    // The centre direction of a cell lies in that cell's region, so the cell's own list (and the
    // always list) holds every triangle its ray crosses.
    visit(exact.cell(cell_of_direction(exact.grid, direction)));
    visit(exact.always_candidates);
    table.cell_triangle[static_cast<std::size_t>(id)] = best;
  }
  return table;
}

PenetrationResult ray_sampling(const RaySamplingTable& table, const geometry::TriMesh& fixed,
                               const geometry::TriMesh& mobile) {
  PenetrationResult result;
  if (fixed.num_triangles() != table.num_triangles) {
    result.status = QueryStatus::kInvalidInput;
    result.message = "ray sampling: fixed mesh has " + std::to_string(fixed.num_triangles()) +
                     " triangles, the table was built for " + std::to_string(table.num_triangles);
    return result;
  }
  const bool inside_fixed = table.configuration == RadialConfiguration::kMobileInsideFixed;
  for (std::size_t v = 0; v < mobile.num_vertices(); ++v) {
    const Vec3 direction = mobile.vertices[v] - table.centre;
    if (!direction.allFinite()) {
      result.status = QueryStatus::kInvalidInput;
      result.message = "ray sampling: mobile mesh has a non-finite vertex";
      result.pairs.clear();
      return result;
    }
    if (direction.isZero(0.0)) continue;
    const std::int32_t t =
        table.cell_triangle[static_cast<std::size_t>(cell_of_direction(table.grid, direction))];
    if (t < 0) continue;
    const RayCrossing crossing = cross(fixed, table.centre, direction, t);
    if (!crossing.hit) continue;  // the Fig. 19 miss: the vertex's ray passes another triangle
    const bool penetrates = inside_fixed ? crossing.t < 1.0 : crossing.t > 1.0;
    if (!penetrates) continue;
    const double depth = (inside_fixed ? 1.0 - crossing.t : crossing.t - 1.0) * direction.norm();
    result.pairs.push_back({static_cast<std::int32_t>(v), t, depth});
  }
  return result;
}

}  // namespace hipfai::contact
