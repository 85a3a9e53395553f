// Tests of the three mapping functions and of the exact cell coverage of triangles
// (contact/radial_mapping.h).
#include "contact/radial_mapping.h"
#include "core/numbers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <set>

namespace hipfai::contact {
namespace {

using hipfai::kPi;

TEST(RadialMapping, TableDimensionFollowsEq8) {
  EXPECT_EQ(make_radial_grid(RadialMapping::kSpherical, 4096).dimension, 64);
  EXPECT_EQ(make_radial_grid(RadialMapping::kCartesian, 4096).dimension, 46);  // ceil(sqrt(2048))
  EXPECT_EQ(make_radial_grid(RadialMapping::kCube, 4096).dimension, 27);       // ceil(sqrt(682.7))
  EXPECT_EQ(make_radial_grid(RadialMapping::kCube, 6).dimension, 1);
  EXPECT_EQ(make_radial_grid(RadialMapping::kCube, 6 * 100).dimension, 10);  // exact square
  EXPECT_THROW(make_radial_grid(RadialMapping::kCube, 0), std::exception);
}

TEST(RadialMapping, ClosedFormCoordinates) {
  // Spherical (Eq. 5): azimuth and polar angle.
  auto s = map_direction(RadialMapping::kSpherical, Vec3(0, 2, 0));
  EXPECT_NEAR(s.a1, kPi / 2, 1e-15);
  EXPECT_NEAR(s.a2, kPi / 2, 1e-15);
  s = map_direction(RadialMapping::kSpherical, Vec3(-1, -1, std::sqrt(2.0)));
  EXPECT_NEAR(s.a1, -3 * kPi / 4, 1e-15);
  EXPECT_NEAR(s.a2, kPi / 4, 1e-15);
  // Cartesian (Eq. 6): normalised x, y and the hemisphere flag (z > 0).
  auto c = map_direction(RadialMapping::kCartesian, Vec3(3, 0, -4));
  EXPECT_DOUBLE_EQ(c.a1, 0.6);
  EXPECT_DOUBLE_EQ(c.a2, 0.0);
  EXPECT_EQ(c.a3, 0);
  EXPECT_EQ(map_direction(RadialMapping::kCartesian, Vec3(0, 0, 1e-300)).a3, 1);
  // Cube: each face centre maps to (pi/4, pi/4) on its own face.
  for (int face = 0; face < 6; ++face) {
    Vec3 d = Vec3::Zero();
    d[face / 2] = face % 2 == 0 ? 7.0 : -7.0;
    const auto q = map_direction(RadialMapping::kCube, d);
    EXPECT_EQ(q.a3, face);
    EXPECT_NEAR(q.a1, kPi / 4, 1e-15);
    EXPECT_NEAR(q.a2, kPi / 4, 1e-15);
  }
  // Equal angle: turning about z by 10 deg on face +x moves a1 by exactly 10 deg.
  const double step = 10.0 * kPi / 180.0;
  const auto q = map_direction(RadialMapping::kCube, Vec3(std::cos(step), std::sin(step), 0));
  EXPECT_NEAR(q.a1 - kPi / 4, step, 1e-15);
}

TEST(RadialMapping, CellCentreDirectionsMapBackToTheirCell) {
  for (const auto mapping : kRadialMappings) {
    const RadialGrid grid = make_radial_grid(mapping, 3000);
    for (int cell = 0; cell < grid.num_cells(); ++cell) {
      const Vec3 d = cell_centre_direction(grid, cell);
      if (mapping == RadialMapping::kCartesian) {
        const auto coords = map_direction(mapping, d);
        // Cells outside the unit disk have no direction of their own (documented).
        const int n = grid.dimension, i = cell % n, j = (cell / n) % n;
        const double x = -1 + (i + 0.5) * 2.0 / n, y = -1 + (j + 0.5) * 2.0 / n;
        if (x * x + y * y >= 1.0) continue;
        (void)coords;
      }
      ASSERT_EQ(cell_of_direction(grid, d), cell) << to_string(mapping);
    }
  }
}

// Dense samples of the triangle (barycentric grid, edges, vertices) as directions from O.
std::vector<Vec3> dense_samples(const Vec3& a, const Vec3& b, const Vec3& c, int n) {
  std::vector<Vec3> samples;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; i + j <= n; ++j) {
      const double u = double(i) / n, v = double(j) / n;
      samples.push_back((1 - u - v) * a + u * b + v * c);
    }
  }
  for (int k = 0; k <= 20 * n; ++k) {  // edges much denser: borders are crossed there
    const double s = double(k) / (20 * n);
    samples.push_back((1 - s) * a + s * b);
    samples.push_back((1 - s) * b + s * c);
    samples.push_back((1 - s) * c + s * a);
  }
  return samples;
}

// Asserts every sampled direction's cell is among the triangle's cells; returns the count.
void expect_covers(const RadialGrid& grid, const Vec3& a, const Vec3& b, const Vec3& c,
                   const std::string& what) {
  std::vector<Vec3> polygon = {a, b, c};
  if (!polygon_plane_clear_of_centre(a, b, c)) return;
  std::vector<int> cells;
  cells_of_polygon(grid, polygon, cells);
  const std::set<int> stored(cells.begin(), cells.end());
  ASSERT_EQ(stored.size(), cells.size()) << "duplicate cells for " << what;
  for (const Vec3& p : dense_samples(a, b, c, 60)) {
    const int cell = cell_of_direction(grid, p);
    ASSERT_TRUE(stored.count(cell)) << to_string(grid.mapping) << " " << what << ": sample "
                                    << p.transpose() << " in cell " << cell << " is missing";
  }
}

Vec3 unit_from_angles(double azimuth, double polar) {
  return Vec3(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
              std::cos(polar));
}

TEST(RadialMapping, TriangleCellsAreExactOnSeamPolesBordersAndSingularities) {
  struct Case {
    std::string name;
    Vec3 a, b, c;
  };
  const double r = 20.0;
  std::vector<Case> cases = {
      // atan2 seam a1 = +-pi (x < 0, y changes sign).
      {"seam", r * unit_from_angles(kPi - 0.2, 1.2), r * unit_from_angles(-kPi + 0.15, 1.3),
       r * unit_from_angles(kPi - 0.05, 1.9)},
      // Containing the north pole, and the south pole.
      {"north pole inside", r * unit_from_angles(0.1, 0.3), r * unit_from_angles(2.2, 0.3),
       r * unit_from_angles(-2.0, 0.35)},
      {"south pole inside", r * unit_from_angles(0.1, kPi - 0.3), r * unit_from_angles(-2.0, kPi - 0.35),
       r * unit_from_angles(2.2, kPi - 0.3)},
      // Pole exactly at a vertex, and an edge through the pole.
      {"pole vertex", Vec3(0, 0, r), r * unit_from_angles(0.3, 0.4), r * unit_from_angles(1.5, 0.5)},
      {"edge through pole", r * unit_from_angles(0.0, 0.4), r * unit_from_angles(kPi, 0.4),
       r * unit_from_angles(kPi / 2, 0.6)},
      // Edge bulging toward the pole past its vertices' polar range (Fig. 24's curved borders).
      {"bulging edge", r * unit_from_angles(-1.4, 0.5), r * unit_from_angles(1.4, 0.5),
       r * unit_from_angles(0.0, 0.9)},
      // Equator (cartesian hemisphere border) and cube corner (three faces meet).
      {"equator", r * unit_from_angles(0.2, kPi / 2 - 0.3), r * unit_from_angles(0.6, kPi / 2 + 0.2),
       r * unit_from_angles(0.9, kPi / 2 - 0.1)},
      {"cube corner", Vec3(r, r * 0.8, r * 1.2), Vec3(r * 1.2, r, r * 0.7), Vec3(r * 0.8, r * 1.1, r)},
      {"cube edge", Vec3(r, r * 0.95, -3), Vec3(r, r * 1.05, 3), Vec3(r * 1.1, r * 0.9, 0)},
      // Large triangle near O (wide cone), and one straddling x = 0 on the cube face border.
      {"near centre", Vec3(1, -0.5, 0.3), Vec3(-0.4, 1, 0.35), Vec3(-0.6, -0.8, 0.4)},
      {"huge", Vec3(30, -30, 5), Vec3(-30, 30, 5), Vec3(-30, -30, 5)},
  };
  for (const auto mapping : kRadialMappings) {
    for (const std::int64_t size : {6, 600, 20000}) {
      const RadialGrid grid = make_radial_grid(mapping, size);
      for (const auto& c : cases) {
        expect_covers(grid, c.a, c.b, c.c, c.name);
        expect_covers(grid, c.a, c.c, c.b, c.name + " reversed");
      }
    }
  }
}

TEST(RadialMapping, TriangleCellsAreExactForRandomTriangles) {
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const auto mapping : kRadialMappings) {
    const RadialGrid grid = make_radial_grid(mapping, 5000);
    for (int k = 0; k < 300; ++k) {
      const Vec3 centre = Vec3(g(rng), g(rng), g(rng)).normalized() * (5 + 45 * u(rng));
      const double size = std::pow(10.0, -2.0 + 3.5 * u(rng));  // 0.01 .. 30 mm
      const Vec3 a = centre + size * Vec3(g(rng), g(rng), g(rng));
      const Vec3 b = centre + size * Vec3(g(rng), g(rng), g(rng));
      const Vec3 c = centre + size * Vec3(g(rng), g(rng), g(rng));
      expect_covers(grid, a, b, c, "random " + std::to_string(k));
    }
  }
}

// The cube mapping drops the cells of a triangle's rectangle that one of its edge planes
// separates from it (radial_mapping.h). A thin triangle along a face's diagonal keeps about one
// cell per diagonal step, not its whole square; and where an edge passes exactly through a cell
// corner, the four cells meeting there are all kept (each touches the cone at that corner ray).
TEST(RadialMapping, CubeCellsLeaveOutOnlyCellsAnEdgePlaneSeparates) {
  const RadialGrid grid = make_radial_grid(RadialMapping::kCube, 6 * 40 * 40);
  const int n = grid.dimension;
  const double r = 20.0;
  const Vec3 a(-0.8 * r, -0.8 * r, r), b(0.8 * r, 0.8 * r, r), c(0.8 * r, 0.81 * r, r);
  std::vector<int> cells;
  cells_of_polygon(grid, std::vector<Vec3>{a, b, c}, cells);
  const int across = cell_of_direction(grid, b) % n - cell_of_direction(grid, a) % n + 1;  // the square's side
  EXPECT_LT(static_cast<int>(cells.size()), 4 * across);
  EXPECT_GT(across * across, 8 * static_cast<int>(cells.size()));
  expect_covers(grid, a, b, c, "diagonal sliver");
  // A corner of the face's grid: u = tan(i pi / (2n) - pi / 4) on both axes.
  const double t = std::tan(12 * (kPi / 2.0) / n - kPi / 4.0), w = std::tan(25 * (kPi / 2.0) / n - kPi / 4.0);
  const Vec3 corner = r * Vec3(t, w, 1.0);
  const Vec3 along(1.0, -1.0, 0.0);
  const Vec3 p = corner + 2.0 * along, q = corner - 2.0 * along, s = corner + Vec3(3.0, 3.0, 0.0);
  cells.clear();
  cells_of_polygon(grid, std::vector<Vec3>{p, q, s}, cells);
  const std::set<int> stored(cells.begin(), cells.end());
  const int face = 4;  // +z
  for (const int i : {11, 12}) {
    for (const int j : {24, 25}) {
      EXPECT_TRUE(stored.count((face * n + j) * n + i)) << "cell " << i << ", " << j << " at the corner";
    }
  }
  expect_covers(grid, p, q, s, "edge through a corner");
}

// Documents why the vertex bounding range of Fig. 25 is not enough: a triangle whose edge bulges
// toward the pole occupies a polar cell none of its vertices is in.
TEST(RadialMapping, VertexRangeAloneMissesCellsThatExactCoverageFinds) {
  const RadialGrid grid = make_radial_grid(RadialMapping::kSpherical, 400);  // 20 x 20
  const double r = 20.0;
  const Vec3 a = r * unit_from_angles(-1.4, 0.5), b = r * unit_from_angles(1.4, 0.5),
             c = r * unit_from_angles(0.0, 0.9);
  int polar_max_index = 0, polar_min_index = grid.dimension;
  for (const Vec3& v : {a, b, c}) {
    const int j = (cell_of_direction(grid, v) / grid.dimension) % grid.dimension;
    polar_min_index = std::min(polar_min_index, j);
    polar_max_index = std::max(polar_max_index, j);
  }
  const Vec3 bulge = (a + b) / 2;  // midpoint of edge AB: polar angle ~0.09 rad < 0.5
  const int bulge_j = (cell_of_direction(grid, bulge) / grid.dimension) % grid.dimension;
  EXPECT_LT(bulge_j, polar_min_index);  // outside the vertices' range
  std::vector<int> cells;
  cells_of_polygon(grid, std::vector<Vec3>{a, b, c}, cells);
  EXPECT_NE(std::find(cells.begin(), cells.end(), cell_of_direction(grid, bulge)), cells.end());
}

TEST(RadialMapping, CapCellsContainEveryDirectionInTheCap) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const auto mapping : kRadialMappings) {
    const RadialGrid grid = make_radial_grid(mapping, 2000);
    for (int k = 0; k < 100; ++k) {
      Vec3 d = Vec3(g(rng), g(rng), g(rng)).normalized();
      if (k < 6) d = Vec3::Unit(k / 2) * (k % 2 ? -1.0 : 1.0);  // poles, face centres
      const double radius = 0.3 * u(rng);
      std::vector<int> cells;
      cells_of_cap(grid, d, radius, cells);
      const std::set<int> stored(cells.begin(), cells.end());
      const Vec3 e1 = d.unitOrthogonal(), e2 = d.cross(e1);
      for (int s = 0; s < 400; ++s) {
        const double angle = radius * std::sqrt(u(rng)), turn = 2 * kPi * u(rng);
        const Vec3 sample = std::cos(angle) * d +
                            std::sin(angle) * (std::cos(turn) * e1 + std::sin(turn) * e2);
        ASSERT_TRUE(stored.count(cell_of_direction(grid, sample))) << to_string(mapping);
      }
    }
  }
}

}  // namespace
}  // namespace hipfai::contact
