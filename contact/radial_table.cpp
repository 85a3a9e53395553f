#include "contact/radial_table.h"

#include "contact/radial_spans.h"

#include "core/error.h"
#include "core/numbers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace hipfai::contact {

namespace {

using hipfai::kPi;

// A triangle whose plane passes (nearly) through O: its cone from O degenerates toward a fan in
// that plane, which cells_of_polygon cannot bin robustly, but every direction it covers lies
// close to ONE great circle (the plane through O parallel to the triangle's). Let n be the unit
// normal, h = |n . a| the plane's distance from O and d the distance from O to the triangle: a
// point x of the triangle has direction at angle asin(|n . x| / |x|) <= asin(h / d) = delta from
// that great circle, and its projection onto the circle lies within the angular range of the
// triangle's projection into the plane (the vertices' range, or the full circle when the
// projection surrounds O). Cells are collected from caps of radius step/2 + delta around points
// of that arc spaced by step <= one cell: every direction is within step/2 along the arc plus
// delta across it of a cap centre (triangle inequality), so the coverage is conservative; the
// 1e-8 rad margin absorbs the rounding of the ray test and of map_direction, as in
// cells_of_polygon.
// Rays exactly tangent to such a triangle (lying in its plane, which happens for every ray that
// meets it when the plane contains O exactly) never count: the exact edge signs are then all zero
// or the facing d . N is zero, and ray_triangle_crossing reports no crossing (a crossing needs a
// proper facing, i.e. a non-zero-length crossing parameter along N). So only triangles with
// h > 0 can produce crossings at all, and for them the bound above holds.
// Returns false (the caller falls back to the always-checked list) when the triangle is so close
// to O that delta is large (>= 0.2 rad): the arc would be a thick band, no cheaper than a list.
bool cells_of_arc_triangle(const RadialGrid& grid, const std::array<Vec3, 3>& corners,
                           const Vec3& area_normal, std::vector<int>& cells) {
  const Vec3 n = area_normal.normalized();
  double scale = 0.0, h = 0.0;
  for (const Vec3& corner : corners) {
    scale = std::max(scale, corner.norm());
    h = std::max(h, std::abs(n.dot(corner)));
  }
  h += 1e-12 * scale;  // rounding of n and of the dot products
  const double d = distance_to_origin(corners[0], corners[1], corners[2]);
  if (!(d > 0.0) || h >= std::sin(0.2) * d) return false;
  const double delta = std::asin(h / d) + 1e-8;
  const Vec3 helper = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = n.cross(helper).normalized();
  const Vec3 e2 = n.cross(e1);
  std::array<double, 3> px{}, py{}, alpha{};
  for (int i = 0; i < 3; ++i) {
    px[static_cast<std::size_t>(i)] = corners[static_cast<std::size_t>(i)].dot(e1);
    py[static_cast<std::size_t>(i)] = corners[static_cast<std::size_t>(i)].dot(e2);
    alpha[static_cast<std::size_t>(i)] = std::atan2(py[static_cast<std::size_t>(i)], px[static_cast<std::size_t>(i)]);
  }
  // Does the projected triangle surround O' (the projection of O)? Then the arc is the full circle.
  int positive = 0, negative = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::size_t j = (i + 1) % 3;
    const double side = px[i] * py[j] - py[i] * px[j];
    positive += side >= 0.0;
    negative += side <= 0.0;
  }
  double lo = 0.0, hi = 2.0 * kPi;
  if (positive != 3 && negative != 3) {
    // O' outside: the angular range is the vertices' range, less than pi wide, so offsets from
    // the first vertex's angle wrapped to (-pi, pi] order them.
    lo = hi = 0.0;
    for (std::size_t i = 1; i < 3; ++i) {
      double offset = alpha[i] - alpha[0];
      if (offset > kPi) offset -= 2.0 * kPi;
      if (offset <= -kPi) offset += 2.0 * kPi;
      lo = std::min(lo, offset);
      hi = std::max(hi, offset);
    }
    if (hi - lo > 0.9 * kPi) {  // nearly surrounding O': rounding could misorder; take the circle
      lo = 0.0;
      hi = 2.0 * kPi;
    } else {
      lo += alpha[0];
      hi += alpha[0];
    }
  }
  const double max_step = std::min(grid.nominal_cell_angle_rad(), 0.1);
  const int samples = std::max(2, static_cast<int>(std::ceil((hi - lo) / max_step)) + 1);
  const double step = (hi - lo) / (samples - 1);
  for (int k = 0; k < samples; ++k) {
    const double angle = lo + step * k;
    cells_of_cap(grid, std::cos(angle) * e1 + std::sin(angle) * e2, 0.5 * step + delta + 1e-8, cells);
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  return true;
}

// Bins triangle t of `fixed` into the table (its cells or the always list).
void insert_triangle(RadialTable& table, const geometry::TriMesh& fixed, std::int32_t t,
                     std::vector<int>& scratch) {
  const std::array<Vec3, 3> corners = triangle_relative(fixed, static_cast<std::size_t>(t), table.centre);
  auto& own_cells = table.triangle_cells[static_cast<std::size_t>(t)];
  own_cells.clear();
  table.is_always[static_cast<std::size_t>(t)] = 0;
  const Vec3 area_normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
  if (area_normal.isZero(0.0)) return;  // zero area: never crossed
  scratch.clear();
  if (!polygon_plane_clear_of_centre(corners[0], corners[1], corners[2])) {
    if (!cells_of_arc_triangle(table.grid, corners, area_normal, scratch)) {
      table.is_always[static_cast<std::size_t>(t)] = 1;
      table.always_candidates.push_back(t);
      return;
    }
  } else {
    cells_of_polygon(table.grid, corners, scratch);
  }
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
  compute_radial_spans(table, fixed);
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
  compute_radial_spans(table, fixed);
}

}  // namespace hipfai::contact
