#include "contact/radial_mapping.h"

#include "core/error.h"
#include "core/numbers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace hipfai::contact {

namespace {

using hipfai::kPi;
// Margin added to every coordinate extent (rad, or unitless for x/R): far above the ~1e-15
// rounding of map_direction and of the watertight ray test, far below any useful cell width.
constexpr double kMargin = 1e-8;
// Angular tolerance of "the pole / the axis is inside the cone": a ray test error of ~1e-15 rad
// near a pole at distance >= 1e-6 rad moves the azimuth by at most ~1e-9 rad < kMargin.
constexpr double kPoleTolerance = 1e-6;

int clamp_index(double scaled, int dimension) {
  if (!(scaled >= 0.0)) return 0;  // also catches NaN defensively
  if (scaled >= dimension) return dimension - 1;
  return static_cast<int>(scaled);
}

int wrap_index(long long index, int dimension) {
  const long long wrapped = index % dimension;
  return static_cast<int>(wrapped < 0 ? wrapped + dimension : wrapped);
}

// Sign of the cone's orientation: +1 when the polygon is counter-clockwise seen from O.
double cone_orientation(std::span<const Vec3> units) {
  Vec3 newell = Vec3::Zero();
  for (std::size_t i = 0; i < units.size(); ++i) {
    newell += units[i].cross(units[(i + 1) % units.size()]);
  }
  Vec3 mean = Vec3::Zero();
  for (const Vec3& u : units) mean += u;
  return newell.dot(mean) >= 0.0 ? 1.0 : -1.0;
}

// Is the unit direction `axis` inside the cone spanned by the polygon (within `tolerance` rad)?
bool inside_cone(std::span<const Vec3> units, double orientation, const Vec3& axis,
                 double tolerance) {
  for (std::size_t i = 0; i < units.size(); ++i) {
    const Vec3 edge_normal = units[i].cross(units[(i + 1) % units.size()]);
    const double length = edge_normal.norm();
    if (length == 0.0) continue;  // repeated direction: no constraint from this edge
    if (orientation * axis.dot(edge_normal) / length < -tolerance) return false;
  }
  return true;
}

// Unit directions where axis . u can be extremal over the cone: the polygon's vertices and, on
// each great-circle edge, the points closest to and farthest from `axis` when they lie on the arc.
void extremal_directions(std::span<const Vec3> units, const Vec3& axis,
                         std::vector<Vec3>& directions) {
  directions.assign(units.begin(), units.end());
  for (std::size_t i = 0; i < units.size(); ++i) {
    const Vec3& p = units[i];
    const Vec3& q = units[(i + 1) % units.size()];
    const Vec3 normal = p.cross(q);
    const double normal_length = normal.norm();
    if (normal_length < 1e-300) continue;
    const Vec3 unit_normal = normal / normal_length;
    const Vec3 in_plane = axis - axis.dot(unit_normal) * unit_normal;
    const double in_plane_length = in_plane.norm();
    if (in_plane_length == 0.0) continue;  // axis normal to the arc's plane: constant along it
    for (const double sign : {1.0, -1.0}) {
      const Vec3 m = sign * in_plane / in_plane_length;
      // On the minor arc p -> q iff (p x m) and (m x q) both point along the arc normal; the
      // tolerance only ever adds a candidate, which widens (never narrows) the extent.
      if (p.cross(m).dot(unit_normal) >= -1e-12 && m.cross(q).dot(unit_normal) >= -1e-12) {
        directions.push_back(m);
      }
    }
  }
}

// [min, max] of axis . u over the cone.
std::array<double, 2> linear_extent(std::span<const Vec3> units, double orientation,
                                    const Vec3& axis, std::vector<Vec3>& scratch) {
  extremal_directions(units, axis, scratch);
  double low = 1.0, high = -1.0;
  for (const Vec3& u : scratch) {
    const double value = axis.dot(u);
    low = std::min(low, value);
    high = std::max(high, value);
  }
  if (inside_cone(units, orientation, axis, kPoleTolerance)) high = 1.0;
  if (inside_cone(units, orientation, -axis, kPoleTolerance)) low = -1.0;
  return {low, high};
}

void append_rectangle(const RadialGrid& grid, int face, int i_low, int i_high, int j_low,
                      int j_high, std::vector<int>& cells) {
  for (int j = j_low; j <= j_high; ++j) {
    for (int i = i_low; i <= i_high; ++i) {
      cells.push_back((face * grid.dimension + j) * grid.dimension + i);
    }
  }
}

int index_low(double value, double domain_min, double domain_width, int dimension) {
  return clamp_index((value - kMargin - domain_min) / domain_width * dimension, dimension);
}
int index_high(double value, double domain_min, double domain_width, int dimension) {
  return clamp_index((value + kMargin - domain_min) / domain_width * dimension, dimension);
}

void spherical_cells(const RadialGrid& grid, std::span<const Vec3> units, double orientation,
                     std::vector<int>& cells) {
  const int n = grid.dimension;
  const Vec3 z_axis = Vec3::UnitZ();
  std::vector<Vec3> candidates;
  extremal_directions(units, z_axis, candidates);
  double polar_low = kPi, polar_high = 0.0;
  for (const Vec3& u : candidates) {
    const double polar = std::atan2(std::hypot(u.x(), u.y()), u.z());
    polar_low = std::min(polar_low, polar);
    polar_high = std::max(polar_high, polar);
  }
  const bool north = inside_cone(units, orientation, z_axis, kPoleTolerance);
  const bool south = inside_cone(units, orientation, -z_axis, kPoleTolerance);
  if (north) polar_low = 0.0;
  if (south) polar_high = kPi;
  const int j_low = index_low(polar_low, 0.0, kPi, n);
  const int j_high = index_high(polar_high, 0.0, kPi, n);

  // Azimuth is monotone along every arc that keeps away from the poles, so the vertices bound it;
  // near a pole (or around one) the cell's whole ring is taken.
  const bool ring = north || south || polar_low < kPoleTolerance || polar_high > kPi - kPoleTolerance;
  if (ring) {
    append_rectangle(grid, 0, 0, n - 1, j_low, j_high, cells);
    return;
  }
  double azimuth = std::atan2(units[0].y(), units[0].x());
  double low = azimuth, high = azimuth;
  for (std::size_t i = 1; i < units.size(); ++i) {
    const double next = std::atan2(units[i].y(), units[i].x());
    double step = next - std::atan2(units[i - 1].y(), units[i - 1].x());
    if (step > kPi) step -= 2.0 * kPi;
    if (step < -kPi) step += 2.0 * kPi;
    azimuth += step;
    low = std::min(low, azimuth);
    high = std::max(high, azimuth);
  }
  low -= kMargin;
  high += kMargin;
  if (high - low >= 2.0 * kPi) {
    append_rectangle(grid, 0, 0, n - 1, j_low, j_high, cells);
    return;
  }
  const double scale = n / (2.0 * kPi);
  const long long i_low = static_cast<long long>(std::floor((low + kPi) * scale));
  const long long i_high = static_cast<long long>(std::floor((high + kPi) * scale));
  if (i_high - i_low + 1 >= n) {
    append_rectangle(grid, 0, 0, n - 1, j_low, j_high, cells);
    return;
  }
  for (long long i = i_low; i <= i_high; ++i) {
    const int wrapped = wrap_index(i, n);
    append_rectangle(grid, 0, wrapped, wrapped, j_low, j_high, cells);
  }
}

void cartesian_cells(const RadialGrid& grid, std::span<const Vec3> units, double orientation,
                     std::vector<int>& cells) {
  const int n = grid.dimension;
  std::vector<Vec3> scratch;
  const auto z_range = linear_extent(units, orientation, Vec3::UnitZ(), scratch);
  const auto x_range = linear_extent(units, orientation, Vec3::UnitX(), scratch);
  const auto y_range = linear_extent(units, orientation, Vec3::UnitY(), scratch);
  const int i_low = index_low(x_range[0], -1.0, 2.0, n);
  const int i_high = index_high(x_range[1], -1.0, 2.0, n);
  const int j_low = index_low(y_range[0], -1.0, 2.0, n);
  const int j_high = index_high(y_range[1], -1.0, 2.0, n);
  // The x/R, y/R extent of the whole cone is used on each hemisphere it reaches: a superset.
  if (z_range[0] <= kMargin) append_rectangle(grid, 0, i_low, i_high, j_low, j_high, cells);
  if (z_range[1] > -kMargin) append_rectangle(grid, 1, i_low, i_high, j_low, j_high, cells);
}

// Keeps the part of a convex polygon where plane(p) >= 0 (Sutherland-Hodgman, one plane).
template <typename Plane>
void clip_polygon(std::vector<Vec3>& polygon, Plane plane, std::vector<Vec3>& scratch) {
  scratch.clear();
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec3& p = polygon[i];
    const Vec3& q = polygon[(i + 1) % polygon.size()];
    const double fp = plane(p), fq = plane(q);
    if (fp >= 0.0) scratch.push_back(p);
    if ((fp >= 0.0) != (fq >= 0.0)) {
      const double s = fp / (fp - fq);
      scratch.push_back(p + s * (q - p));
    }
  }
  polygon.swap(scratch);
}

void cube_cells(const RadialGrid& grid, std::span<const Vec3> units, std::vector<int>& cells) {
  const int n = grid.dimension;
  std::vector<Vec3> clipped, scratch;
  for (int face = 0; face < 6; ++face) {
    const int k = face / 2, k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    const double sign = face % 2 == 0 ? 1.0 : -1.0;
    clipped.assign(units.begin(), units.end());
    // The face's pyramid |d[k1]|, |d[k2]| <= sign * d[k], slightly widened so a direction on the
    // border between faces is binned on both sides.
    const double widen = 1.0 + kMargin;
    for (const int other : {k1, k2}) {
      for (const double side : {1.0, -1.0}) {
        clip_polygon(clipped, [&](const Vec3& p) { return sign * p[k] * widen - side * p[other]; },
                     scratch);
        if (clipped.empty()) break;
      }
      if (clipped.empty()) break;
    }
    if (clipped.empty()) continue;
    // d[k1] / |d[k]| is linear-fractional on the plane and |d[k]| > 0 on the clipped part, so
    // its extremes are at the clipped polygon's vertices.
    double low1 = 2.0, high1 = -2.0, low2 = 2.0, high2 = -2.0;
    for (const Vec3& p : clipped) {
      const double along = sign * p[k];
      if (!(along > 0.0)) {  // only when the polygon touches O, excluded by the caller
        low1 = low2 = -1.0;
        high1 = high2 = 1.0;
        break;
      }
      const double r1 = std::clamp(p[k1] / along, -2.0, 2.0);
      const double r2 = std::clamp(p[k2] / along, -2.0, 2.0);
      low1 = std::min(low1, r1), high1 = std::max(high1, r1);
      low2 = std::min(low2, r2), high2 = std::max(high2, r2);
    }
    const double quarter = kPi / 2.0;
    const int i_low = index_low(std::atan(low1) + kPi / 4, 0.0, quarter, n);
    const int i_high = index_high(std::atan(high1) + kPi / 4, 0.0, quarter, n);
    const int j_low = index_low(std::atan(low2) + kPi / 4, 0.0, quarter, n);
    const int j_high = index_high(std::atan(high2) + kPi / 4, 0.0, quarter, n);
    if (i_low == i_high && j_low == j_high) {
      append_rectangle(grid, face, i_low, i_high, j_low, j_high, cells);
      continue;
    }
    // The rectangle bounds the polygon's cone; a triangle covers about half of it. A cell is a
    // convex cone too (its borders are planes through O: d[k1] / |d[k]| = tan(border)), spanned by
    // its four corner rays, and two convex cones within a half-space are disjoint exactly when a
    // face plane of one separates them. So a cell whose four corners lie beyond one of the
    // polygon's edge planes (through O) by more than kSeparation (as an angle) holds no direction
    // within kSeparation of the cone, far beyond the rounding of the lookup and the ray test; it is
    // left out. Cells separated only by their own borders are already outside the rectangle.
    std::vector<double> tan1, tan2;
    for (int i = i_low; i <= i_high + 1; ++i) tan1.push_back(std::tan(i * quarter / n - kPi / 4));
    for (int j = j_low; j <= j_high + 1; ++j) tan2.push_back(std::tan(j * quarter / n - kPi / 4));
    const double orientation = cone_orientation(units);
    std::vector<Vec3> edge_normals;
    for (std::size_t e = 0; e < units.size(); ++e) {
      const Vec3 normal = units[e].cross(units[(e + 1) % units.size()]);
      const double length = normal.norm();
      if (length > 0.0) edge_normals.push_back(orientation * normal / length);
    }
    constexpr double kSeparation = 1e-6;
    for (int j = j_low; j <= j_high; ++j) {
      for (int i = i_low; i <= i_high; ++i) {
        std::array<Vec3, 4> corners;
        for (int c = 0; c < 4; ++c) {
          Vec3 d;
          d[k] = sign;
          d[k1] = tan1[static_cast<std::size_t>(i - i_low + (c & 1))];
          d[k2] = tan2[static_cast<std::size_t>(j - j_low + (c >> 1))];
          corners[static_cast<std::size_t>(c)] = d.normalized();
        }
        bool separated = false;
        for (const Vec3& normal : edge_normals) {
          separated = std::all_of(corners.begin(), corners.end(),
                                  [&](const Vec3& corner) { return normal.dot(corner) < -kSeparation; });
          if (separated) break;
        }
        if (!separated) cells.push_back((face * grid.dimension + j) * grid.dimension + i);
      }
    }
  }
}

}  // namespace

const char* to_string(RadialMapping mapping) {
  switch (mapping) {
    case RadialMapping::kSpherical: return "spherical";
    case RadialMapping::kCartesian: return "cartesian";
    case RadialMapping::kCube: return "cube";
  }
  return "unknown";
}

double RadialGrid::a1_min() const {
  switch (mapping) {
    case RadialMapping::kSpherical: return -kPi;
    case RadialMapping::kCartesian: return -1.0;
    case RadialMapping::kCube: return 0.0;
  }
  return 0.0;
}
double RadialGrid::a1_width() const {
  switch (mapping) {
    case RadialMapping::kSpherical: return 2.0 * kPi;
    case RadialMapping::kCartesian: return 2.0;
    case RadialMapping::kCube: return kPi / 2.0;
  }
  return 1.0;
}
double RadialGrid::a2_min() const { return mapping == RadialMapping::kCartesian ? -1.0 : 0.0; }
double RadialGrid::a2_width() const {
  switch (mapping) {
    case RadialMapping::kSpherical: return kPi;
    case RadialMapping::kCartesian: return 2.0;
    case RadialMapping::kCube: return kPi / 2.0;
  }
  return 1.0;
}
double RadialGrid::nominal_cell_angle_rad() const {
  // Spherical: an a1 cell at the equator; cartesian: an x/R step near the pole, where it is an
  // angle (wider near the equator, see the header); cube: one equal-angle step.
  return std::max(a1_width(), a2_width()) / dimension;
}

RadialGrid make_radial_grid(RadialMapping mapping, std::int64_t table_size) {
  if (table_size < 1 || table_size > (std::int64_t{1} << 30)) {
    throw_error("radial table: table_size must be in 1..2^30, got ", table_size);
  }
  RadialGrid grid;
  grid.mapping = mapping;
  grid.faces = mapping == RadialMapping::kSpherical ? 1 : mapping == RadialMapping::kCartesian ? 2 : 6;
  grid.dimension = static_cast<int>(
      std::ceil(std::sqrt(static_cast<double>(table_size) / grid.faces) - 1e-12));
  grid.dimension = std::max(grid.dimension, 1);
  return grid;
}

RadialCoordinates map_direction(RadialMapping mapping, const Vec3& d) {
  RadialCoordinates c;
  switch (mapping) {
    case RadialMapping::kSpherical:
      c.a1 = std::atan2(d.y(), d.x());
      c.a2 = std::atan2(std::hypot(d.x(), d.y()), d.z());
      break;
    case RadialMapping::kCartesian: {
      const double r = d.norm();
      c.a1 = d.x() / r;
      c.a2 = d.y() / r;
      c.a3 = d.z() > 0.0 ? 1 : 0;
      break;
    }
    case RadialMapping::kCube: {
      int k = 0;
      if (std::abs(d.y()) > std::abs(d[k])) k = 1;
      if (std::abs(d.z()) > std::abs(d[k])) k = 2;
      const double along = std::abs(d[k]);
      c.a3 = 2 * k + (d[k] < 0.0 ? 1 : 0);
      c.a1 = std::atan(d[(k + 1) % 3] / along) + kPi / 4;
      c.a2 = std::atan(d[(k + 2) % 3] / along) + kPi / 4;
      break;
    }
  }
  return c;
}

int cell_of_direction(const RadialGrid& grid, const Vec3& direction) {
  const RadialCoordinates c = map_direction(grid.mapping, direction);
  const int n = grid.dimension;
  int i;
  if (grid.mapping == RadialMapping::kSpherical) {
    i = wrap_index(static_cast<long long>(std::floor((c.a1 + kPi) / (2.0 * kPi) * n)), n);
  } else {
    i = clamp_index((c.a1 - grid.a1_min()) / grid.a1_width() * n, n);
  }
  const int j = clamp_index((c.a2 - grid.a2_min()) / grid.a2_width() * n, n);
  return (c.a3 * n + j) * n + i;
}

Vec3 cell_centre_direction(const RadialGrid& grid, int cell) {
  const int n = grid.dimension;
  const int i = cell % n, j = (cell / n) % n, face = cell / (n * n);
  const double a1 = grid.a1_min() + (i + 0.5) * grid.a1_width() / n;
  const double a2 = grid.a2_min() + (j + 0.5) * grid.a2_width() / n;
  switch (grid.mapping) {
    case RadialMapping::kSpherical:
      return Vec3(std::sin(a2) * std::cos(a1), std::sin(a2) * std::sin(a1), std::cos(a2));
    case RadialMapping::kCartesian: {
      // A cell centre outside the unit disk has no direction of its own: use the rim.
      const double rim = std::hypot(a1, a2);
      const double x = rim > 1.0 ? a1 / rim : a1, y = rim > 1.0 ? a2 / rim : a2;
      const double z = std::sqrt(std::max(0.0, 1.0 - x * x - y * y));
      return Vec3(x, y, face == 1 ? z : -z).normalized();
    }
    case RadialMapping::kCube: {
      const int k = face / 2;
      Vec3 d;
      d[k] = face % 2 == 0 ? 1.0 : -1.0;
      d[(k + 1) % 3] = std::tan(a1 - kPi / 4);
      d[(k + 2) % 3] = std::tan(a2 - kPi / 4);
      return d.normalized();
    }
  }
  return Vec3::UnitZ();
}

bool polygon_plane_clear_of_centre(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 normal = (b - a).cross(c - a);
  const double normal_length = normal.norm();
  if (normal_length == 0.0) return false;
  const double plane_distance = std::abs(a.dot(normal)) / normal_length;
  const double size = std::max({a.norm(), b.norm(), c.norm()});
  return plane_distance > 1e-6 * size;
}

void cells_of_polygon(const RadialGrid& grid, std::span<const Vec3> polygon,
                      std::vector<int>& cells) {
  std::vector<Vec3> units;
  units.reserve(polygon.size());
  for (const Vec3& p : polygon) units.push_back(p.normalized());
  switch (grid.mapping) {
    case RadialMapping::kSpherical:
      spherical_cells(grid, units, cone_orientation(units), cells);
      break;
    case RadialMapping::kCartesian:
      cartesian_cells(grid, units, cone_orientation(units), cells);
      break;
    case RadialMapping::kCube:
      cube_cells(grid, units, cells);
      break;
  }
}

void cells_of_cap(const RadialGrid& grid, const Vec3& direction, double radius_rad,
                  std::vector<int>& cells) {
  if (radius_rad >= 1.4) {  // ~80 deg: the square would be huge; take everything
    for (int cell = 0; cell < grid.num_cells(); ++cell) cells.push_back(cell);
    return;
  }
  const Vec3 centre = direction.normalized();
  const Vec3 helper = std::abs(centre.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = centre.cross(helper).normalized();
  const Vec3 e2 = centre.cross(e1);
  // The square tangent at `centre` with half-side tan(radius) circumscribes the cap's circle.
  const double half = std::tan(radius_rad) * (1.0 + 1e-9);
  const std::array<Vec3, 4> square = {centre + half * (e1 + e2), centre + half * (-e1 + e2),
                                      centre + half * (-e1 - e2), centre + half * (e1 - e2)};
  cells_of_polygon(grid, square, cells);
}

}  // namespace hipfai::contact
