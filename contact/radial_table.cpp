#include "contact/radial_table.h"

#include "core/error.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace hipfai::contact {

namespace {

// Bins triangle t of `fixed` into the table (its cells or the always list).
void insert_triangle(RadialTable& table, const geometry::TriMesh& fixed, std::int32_t t,
                     std::vector<int>& scratch) {
  const auto& tri = fixed.triangles[static_cast<std::size_t>(t)];
  const std::array<Vec3, 3> corners = {fixed.vertices[static_cast<std::size_t>(tri[0])] - table.centre,
                                       fixed.vertices[static_cast<std::size_t>(tri[1])] - table.centre,
                                       fixed.vertices[static_cast<std::size_t>(tri[2])] - table.centre};
  auto& own_cells = table.triangle_cells[static_cast<std::size_t>(t)];
  own_cells.clear();
  table.is_always[static_cast<std::size_t>(t)] = 0;
  const Vec3 area_normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
  if (area_normal.isZero(0.0)) return;  // zero area: never crossed
  if (!polygon_plane_clear_of_centre(corners[0], corners[1], corners[2])) {
    table.is_always[static_cast<std::size_t>(t)] = 1;
    table.always_candidates.push_back(t);
    return;
  }
  scratch.clear();
  cells_of_polygon(table.grid, corners, scratch);
  for (const int id : scratch) {
    table.cells[static_cast<std::size_t>(id)].push_back(t);
    own_cells.push_back(id);
  }
}

}  // namespace

std::size_t RadialTable::num_entries() const {
  std::size_t total = always_candidates.size();
  for (const auto& c : cells) total += c.size();
  return total;
}

RadialTable build_radial_table(const geometry::TriMesh& fixed, const Vec3& centre,
                               const RadialTableOptions& options) {
  geometry::validate_mesh(fixed, "radial table: fixed mesh");
  if (!centre.allFinite()) throw_error("radial table: centre is not finite");
  RadialTable table;
  table.grid = make_radial_grid(options.mapping, options.table_size);
  table.centre = centre;
  table.num_triangles = fixed.num_triangles();
  table.cells.resize(static_cast<std::size_t>(table.grid.num_cells()));
  table.triangle_cells.resize(table.num_triangles);
  table.is_always.assign(table.num_triangles, 0);
  std::vector<int> scratch;
  for (std::size_t t = 0; t < table.num_triangles; ++t) {
    insert_triangle(table, fixed, static_cast<std::int32_t>(t), scratch);
  }
  return table;
}

void update_triangles(RadialTable& table, const geometry::TriMesh& fixed,
                      std::span<const std::int32_t> changed_triangles) {
  if (fixed.num_triangles() != table.num_triangles) {
    throw_error("radial table update: mesh has ", fixed.num_triangles(),
                " triangles, the table was built for ", table.num_triangles);
  }
  std::vector<std::int32_t> changed(changed_triangles.begin(), changed_triangles.end());
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  for (const std::int32_t t : changed) {
    if (t < 0 || static_cast<std::size_t>(t) >= table.num_triangles) {
      throw_error("radial table update: triangle index ", t, " out of range 0..",
                  table.num_triangles - 1);
    }
    for (const auto v : fixed.triangles[static_cast<std::size_t>(t)]) {
      if (v < 0 || static_cast<std::size_t>(v) >= fixed.num_vertices() ||
          !fixed.vertices[static_cast<std::size_t>(v)].allFinite()) {
        throw_error("radial table update: triangle ", t, " has an invalid or non-finite vertex");
      }
    }
  }
  // Remove the old entries first, then re-bin: removal is by value within the old cells only.
  for (const std::int32_t t : changed) {
    for (const int id : table.triangle_cells[static_cast<std::size_t>(t)]) {
      auto& entries = table.cells[static_cast<std::size_t>(id)];
      entries.erase(std::remove(entries.begin(), entries.end(), t), entries.end());
    }
    if (table.is_always[static_cast<std::size_t>(t)]) {
      auto& always = table.always_candidates;
      always.erase(std::remove(always.begin(), always.end(), t), always.end());
    }
  }
  std::vector<int> scratch;
  for (const std::int32_t t : changed) insert_triangle(table, fixed, t, scratch);
}

}  // namespace hipfai::contact
