// Tests of the plane quad mesh repairs (geometry/planar_quad_mesh.h) on small meshes whose answer
// is known by construction.
#include "geometry/planar_quad_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

namespace hipfai::geometry {
namespace {

using Quad = std::array<std::int32_t, 4>;

// nx x ny unit squares on [0, nx] x [0, ny], node (i, j) at index j (nx + 1) + i.
PlanarQuadMesh grid(int nx, int ny) {
  PlanarQuadMesh mesh;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      mesh.nodes.emplace_back(i, j);
      mesh.on_boundary.push_back(i == 0 || j == 0 || i == nx || j == ny);
    }
  }
  const auto node = [&](int i, int j) { return static_cast<std::int32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) mesh.quads.push_back({node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)});
  }
  return mesh;
}

// A quad as the set of its corners in cyclic order, starting from its smallest index.
Quad canonical(Quad quad) {
  std::rotate(quad.begin(), std::min_element(quad.begin(), quad.end()), quad.end());
  return quad;
}
std::set<Quad> quad_set(const PlanarQuadMesh& mesh) {
  std::set<Quad> quads;
  for (const Quad& quad : mesh.quads) quads.insert(canonical(quad));
  return quads;
}

std::size_t flat_single_corners(const PlanarQuadMesh& mesh, double bound_deg) {
  std::vector<int> uses(mesh.nodes.size(), 0);
  for (const Quad& quad : mesh.quads) {
    for (auto v : quad) ++uses[static_cast<std::size_t>(v)];
  }
  std::size_t count = 0;
  for (const Quad& quad : mesh.quads) {
    for (std::size_t c = 0; c < 4; ++c) {
      const auto v = static_cast<std::size_t>(quad[c]);
      count += mesh.on_boundary[v] && uses[v] == 1 && quad_corner_angle(mesh, quad, c) > bound_deg * std::numbers::pi / 180.0;
    }
  }
  return count;
}

TEST(PlanarQuadMesh, CornerAnglesAndQualityOfASquareAndAKite) {
  PlanarQuadMesh mesh = grid(1, 1);
  for (std::size_t c = 0; c < 4; ++c) EXPECT_NEAR(quad_corner_angle(mesh, mesh.quads[0], c), std::numbers::pi / 2, 1e-15);
  EXPECT_NEAR(planar_quality(mesh), 1.0, 1e-15);
  // A kite (0,0) (2,-0.1) (4,0) (2,2): corner at (2,-0.1) is 180 - 2 atan(0.05) deg.
  mesh.nodes = {{0, 0}, {2, -0.1}, {4, 0}, {2, 2}};
  mesh.quads = {{0, 1, 2, 3}};
  const double flat = std::numbers::pi - 2.0 * std::atan(0.05);
  EXPECT_NEAR(quad_corner_angle(mesh, mesh.quads[0], 1), flat, 1e-14);
  EXPECT_NEAR(planar_quality(mesh), std::sin(flat), 1e-14);
}

// A 3 x 2 grid in which the two lower-left squares were recombined the wrong way: the hexagon
// they form split by the diagonal (0,0)-(2,1), so the boundary node (1,0), pulled slightly
// outwards, is the near-180 deg corner of one quad. The repair must find it and give back the
// grid's own two squares (the other neighbour's swap would leave (2,0) as a flat single corner).
TEST(PlanarQuadMesh, OpensAFlatBoundaryCornerBackToTheGrid) {
  PlanarQuadMesh mesh = grid(3, 2);
  mesh.nodes[1] = {1.0, -0.05};
  const std::set<Quad> expected = quad_set(mesh);
  // Nodes: (0,0)=0 (1,0)=1 (2,0)=2 (0,1)=4 (1,1)=5 (2,1)=6.
  mesh.quads[0] = {0, 1, 2, 6};
  mesh.quads[1] = {6, 5, 4, 0};
  ASSERT_EQ(flat_single_corners(mesh, kFlatBoundaryCornerDeg), 1u);
  const double before = planar_quality(mesh);
  const FlatCornerRepair repair = open_flat_boundary_corners(mesh);
  EXPECT_EQ(repair.found, 1u);
  EXPECT_EQ(repair.opened, 1u);
  EXPECT_EQ(quad_set(mesh), expected);
  EXPECT_EQ(flat_single_corners(mesh, kFlatBoundaryCornerDeg), 0u);
  EXPECT_GT(planar_quality(mesh), before);
}

// The repair finds `found` flat single corners and changes nothing.
void expect_left_as_it_is(PlanarQuadMesh mesh, std::size_t found) {
  const auto before = mesh.quads;
  const FlatCornerRepair repair = open_flat_boundary_corners(mesh);
  EXPECT_EQ(repair.found, found);
  EXPECT_EQ(repair.opened, 0u);
  EXPECT_EQ(mesh.quads, before);
}

TEST(PlanarQuadMesh, LeavesAGoodMeshAsItIs) {
  PlanarQuadMesh mesh = grid(4, 3);
  mesh.nodes[6] += Eigen::Vector2d(0.2, -0.1);  // an interior node off the grid: still convex
  expect_left_as_it_is(mesh, 0);
}

// A lone kite has no neighbour to swap with: found, not opened, not changed.
TEST(PlanarQuadMesh, CountsAFlatCornerItCannotOpen) {
  PlanarQuadMesh mesh = grid(1, 1);
  mesh.nodes = {{0, 0}, {2, -0.1}, {4, 0}, {2, 2}};
  mesh.quads = {{0, 1, 2, 3}};
  expect_left_as_it_is(mesh, 1);
}

// The bound is the caller's: a corner of 170 deg is flat at 150 and left alone at 175.
TEST(PlanarQuadMesh, TheBoundDecidesWhatIsFlat) {
  const auto wrong_way = [] {
    PlanarQuadMesh mesh = grid(3, 2);
    mesh.nodes[1] = {1.0, -std::tan(5.0 * std::numbers::pi / 180.0)};  // corner 170 deg
    mesh.quads[0] = {0, 1, 2, 6};
    mesh.quads[1] = {6, 5, 4, 0};
    return mesh;
  };
  PlanarQuadMesh strict = wrong_way();
  EXPECT_EQ(open_flat_boundary_corners(strict, 150.0).opened, 1u);
  PlanarQuadMesh lenient = wrong_way();
  EXPECT_EQ(open_flat_boundary_corners(lenient, 175.0).found, 0u);
}

// The hexagon (0,0) (1,-0.05) (2,0) (2,1) (1,1) (0,1) in four triangles, one of them the ear
// (0,0) (1,-0.05) (2,0) along the bottom (176 deg at its middle node). The flip across the ear's
// inner edge gives (1,-0.05) the triangles towards (1,1): known answer.
TEST(PlanarTriMesh, FlipsAnEarAlongTheOutline) {
  PlanarTriMesh mesh;
  mesh.nodes = {{0, 0}, {1, -0.05}, {2, 0}, {2, 1}, {1, 1}, {0, 1}};
  mesh.on_boundary.assign(6, true);
  mesh.triangles = {{1, 2, 0}, {0, 2, 4}, {2, 3, 4}, {0, 4, 5}};
  const FlatCornerRepair repair = flip_flat_boundary_ears(mesh);
  EXPECT_EQ(repair.found, 1u);
  EXPECT_EQ(repair.opened, 1u);
  std::set<std::array<std::int32_t, 3>> triangles;
  for (auto t : mesh.triangles) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    triangles.insert(t);
  }
  const std::set<std::array<std::int32_t, 3>> expected{{1, 2, 4}, {0, 1, 4}, {2, 3, 4}, {0, 4, 5}};
  EXPECT_EQ(triangles, expected);
  // Nothing left to flip: a second call finds no ear.
  EXPECT_EQ(flip_flat_boundary_ears(mesh).found, 0u);
}

// A lone ear has no triangle across its inner edge: found, not flipped.
TEST(PlanarTriMesh, CountsAnEarItCannotFlip) {
  PlanarTriMesh mesh;
  mesh.nodes = {{0, 0}, {1, -0.05}, {2, 0}};
  mesh.on_boundary.assign(3, true);
  mesh.triangles = {{1, 2, 0}};
  const FlatCornerRepair repair = flip_flat_boundary_ears(mesh);
  EXPECT_EQ(repair.found, 1u);
  EXPECT_EQ(repair.opened, 0u);
}

// Two triangles sharing an edge: 6 quads, every triangle's area kept, midpoints shared, only
// the outline's nodes on the boundary, every quad convex and counter-clockwise.
TEST(PlanarTriMesh, SplitsIntoThreeQuadsPerTriangle) {
  PlanarTriMesh mesh;
  mesh.nodes = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  mesh.on_boundary.assign(4, true);
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  const PlanarQuadMesh quads = split_into_quads(mesh, 0);
  ASSERT_EQ(quads.quads.size(), 6u);
  EXPECT_EQ(quads.nodes.size(), 4u + 5u + 2u);  // corners, 5 edge midpoints, 2 centroids
  double area = 0.0;
  for (const Quad& quad : quads.quads) {
    for (std::size_t c = 0; c < 4; ++c) {
      const auto& p = quads.nodes[static_cast<std::size_t>(quad[c])];
      const auto& q = quads.nodes[static_cast<std::size_t>(quad[(c + 1) % 4])];
      area += 0.5 * (p.x() * q.y() - q.x() * p.y());
    }
  }
  EXPECT_NEAR(area, 4.0, 1e-14);
  EXPECT_GT(planar_quality(quads), 0.0);
  std::size_t boundary = 0;
  for (std::size_t v = 0; v < quads.nodes.size(); ++v) {
    const auto& p = quads.nodes[v];
    const bool on_outline = p.x() == 0.0 || p.y() == 0.0 || p.x() == 2.0 || p.y() == 2.0;
    EXPECT_EQ(static_cast<bool>(quads.on_boundary[v]), on_outline) << "node " << v;
    boundary += quads.on_boundary[v];
  }
  EXPECT_EQ(boundary, 8u);
  // Smoothing moves interior nodes only, and never to a worse mesh.
  const PlanarQuadMesh smoothed = split_into_quads(mesh, 5);
  EXPECT_GE(planar_quality(smoothed), planar_quality(quads));
  for (std::size_t v = 0; v < quads.nodes.size(); ++v) {
    if (quads.on_boundary[v]) {
      EXPECT_EQ(smoothed.nodes[v], quads.nodes[v]);
    }
  }
}

}  // namespace
}  // namespace hipfai::geometry
