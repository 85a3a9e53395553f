// Hard cases of radial segmenting, each its own test: directions on cell borders, table edges,
// the atan2 seam and the poles; a vertex at the centre; slivers and zero-area triangles; a vertex
// exactly on the surface; rays through shared edges and vertices; open meshes with holes; two
// nested layers (thesis Fig. 40); coordinates far from the origin. Each case is compared with the
// exhaustive oracle for every mapping and, where the geometry allows, with a closed form.
#include "contact/oracle_radial.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_table.h"

#include "core/numbers.h"
#include "geometry/primitive_meshes.h"
#include "tests/contact/random_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>

namespace hipfai::contact {
namespace {

using test_shapes::flipped;

using geometry::TriMesh;
using hipfai::kPi;

TriMesh bare_points(const std::vector<Vec3>& vertices) {
  TriMesh mesh;
  mesh.vertices = vertices;
  return mesh;
}

// Runs every mapping (two table sizes, 1 and 2 threads) and asserts the oracle's answer exactly;
// returns the oracle's answer for the closed-form checks of each test.
PenetrationResult check_all(const TriMesh& fixed, const TriMesh& mobile, const Vec3& centre,
                            RadialConfiguration configuration) {
  const PenetrationResult expected = oracle_radial(fixed, mobile, centre, configuration);
  for (const auto mapping : kRadialMappings) {
    for (const std::int64_t size : {7, 600, 5000}) {
      const RadialTable table = build_radial_table(fixed, centre, {mapping, size});
      for (const int threads : {1, 2}) {
        RadialQueryOptions options;
        options.configuration = configuration;
        options.num_threads = threads;
        const auto got = radial_segmenting(table, fixed, mobile, options);
        EXPECT_EQ(got.status, QueryStatus::kOk) << got.message;
        EXPECT_EQ(got.pairs.size(), expected.pairs.size()) << to_string(mapping) << " " << size;
        if (got.pairs.size() != expected.pairs.size()) continue;
        for (std::size_t i = 0; i < got.pairs.size(); ++i) {
          EXPECT_EQ(got.pairs[i].mobile_vertex, expected.pairs[i].mobile_vertex);
          EXPECT_EQ(got.pairs[i].fixed_triangle, expected.pairs[i].fixed_triangle);
          EXPECT_TRUE(std::isfinite(got.pairs[i].depth_mm));
          // Same primitive on the same numbers: bit-identical in practice; 1e-9 mm is the bound.
          EXPECT_NEAR(got.pairs[i].depth_mm, expected.pairs[i].depth_mm, 1e-9);
        }
      }
    }
  }
  return expected;
}

// Flat square patch z = height, x, y in [-half, half], an n x n grid of integer-spaced quads,
// normals facing O (-z): an open "socket" surface. Coordinates are small integers, so every
// quantity the ray test computes for integer-valued rays is exact.
TriMesh patch(int half, double height, const Vec3& offset = Vec3::Zero()) {
  TriMesh mesh;
  const int n = 2 * half;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) mesh.vertices.push_back(offset + Vec3(i - half, j - half, height));
  }
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      // Clockwise seen from +z: the normal points to -z, toward O.
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
      mesh.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
    }
  }
  return mesh;
}

TEST(RadialHardCases, DirectionsOnCellBordersAndTableEdges) {
  const TriMesh socket = flipped(geometry::make_octasphere(Vec3::Zero(), 25.0, 3));
  std::vector<Vec3> vertices;
  for (const auto mapping : kRadialMappings) {
    const RadialGrid grid = make_radial_grid(mapping, 600);
    // Cell centres (the ray-sampling directions).
    for (int cell = 0; cell < grid.num_cells(); cell += 7) {
      vertices.push_back(30.0 * cell_centre_direction(grid, cell));
    }
  }
  // Cell borders of the cube map: a1 = k (pi/2) / n on every face, i.e. d[k1] = tan(a1 - pi/4).
  const int n_cube = make_radial_grid(RadialMapping::kCube, 600).dimension;
  for (int face = 0; face < 6; ++face) {
    for (int k = 0; k <= n_cube; k += 2) {
      for (int j = 0; j <= n_cube; j += 3) {
        Vec3 d;
        d[face / 2] = face % 2 == 0 ? 1.0 : -1.0;
        d[(face / 2 + 1) % 3] = std::tan(k * (kPi / 2) / n_cube - kPi / 4);
        d[(face / 2 + 2) % 3] = std::tan(j * (kPi / 2) / n_cube - kPi / 4);
        vertices.push_back(30.0 * d.normalized());
      }
    }
  }
  // Cell borders of the cartesian map: x/R = -1 + 2k/n, y/R = -1 + 2j/n, both hemispheres.
  const int n_cart = make_radial_grid(RadialMapping::kCartesian, 600).dimension;
  for (int k = 0; k <= n_cart; ++k) {
    for (int j = 0; j <= n_cart; j += 2) {
      const double x = -1.0 + 2.0 * k / n_cart, y = -1.0 + 2.0 * j / n_cart;
      if (x * x + y * y > 1.0) continue;
      const double z = std::sqrt(1.0 - x * x - y * y);
      vertices.push_back(30.0 * Vec3(x, y, z));
      vertices.push_back(30.0 * Vec3(x, y, -z));
    }
  }
  // Table edges: poles, seam (with +0 and -0 in y), cartesian rim (x/R = +-1), cube face edges
  // and corners.
  for (const Vec3& d : {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(-1, 0.0, 0.3), Vec3(-1, -0.0, 0.3),
                        Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0),
                        Vec3(1, 1, 0), Vec3(1, -1, 0), Vec3(1, 1, 1), Vec3(-1, -1, -1),
                        Vec3(0, 1, 1), Vec3(1, 0, -1), Vec3(1e-300, 0, 1), Vec3(0, -1e-300, -1)}) {
    vertices.push_back(30.0 * d.normalized());
  }
  // Exact cell borders of the spherical map: azimuths k * 2 pi / n - pi, polar j * pi / n.
  const int n = make_radial_grid(RadialMapping::kSpherical, 600).dimension;
  for (int k = 0; k <= n; k += 3) {
    for (int j = 0; j <= n; j += 4) {
      const double azimuth = k * 2 * kPi / n - kPi, polar = j * kPi / n;
      vertices.emplace_back(30 * std::sin(polar) * std::cos(azimuth),
                            30 * std::sin(polar) * std::sin(azimuth), 30 * std::cos(polar));
    }
  }
  const TriMesh mobile = bare_points(vertices);
  const auto expected =
      check_all(socket, mobile, Vec3::Zero(), RadialConfiguration::kMobileInsideFixed);
  // Every vertex is 30 mm out, beyond the 25 mm socket: all penetrate. The crossing lies on a
  // triangle, at a radius between that triangle's plane distance and 25 mm, so the depth is in
  // [5, 30 - (smallest plane distance of any triangle)].
  double nearest_plane = 25.0;
  for (std::size_t t = 0; t < socket.num_triangles(); ++t) {
    const Vec3 normal = geometry::triangle_unit_normal(socket, t);
    nearest_plane = std::min(nearest_plane, std::abs(normal.dot(socket.vertices[socket.triangles[t][0]])));
  }
  EXPECT_EQ(expected.pairs.size(), vertices.size());
  for (const auto& pair : expected.pairs) {
    EXPECT_GE(pair.depth_mm, 5.0 - 1e-9);
    EXPECT_LE(pair.depth_mm, 30.0 - nearest_plane + 1e-9);
  }
}

TEST(RadialHardCases, RaysThroughSeamAndPolesOfTheFixedMesh) {
  // The octasphere has vertices exactly on the poles and on the seam (-1, 0, 0): rays through
  // them pass through vertices shared by 4 triangles; each must be counted once, none missed.
  const TriMesh head = geometry::make_octasphere(Vec3::Zero(), 25.0, 4);
  std::vector<Vec3> vertices;
  for (const auto& v : head.vertices) vertices.push_back(v * 0.5);  // inside: FixedInsideMobile
  const auto expected = check_all(head, bare_points(vertices), Vec3::Zero(),
                                  RadialConfiguration::kFixedInsideMobile);
  ASSERT_EQ(expected.pairs.size(), vertices.size());
  for (const auto& pair : expected.pairs) EXPECT_NEAR(pair.depth_mm, 12.5, 1e-9);
}

TEST(RadialHardCases, VertexAtTheCentreHasNoRayAndNeverPenetrates) {
  const TriMesh socket = flipped(geometry::make_octasphere(Vec3(1, 1, 1), 25.0, 2));
  const TriMesh mobile = bare_points({Vec3(1, 1, 1), Vec3(1, 1, 40), Vec3(1, 1, 1), Vec3(1, -40, 1)});
  for (const auto configuration :
       {RadialConfiguration::kMobileInsideFixed, RadialConfiguration::kFixedInsideMobile}) {
    const auto expected = check_all(socket, mobile, Vec3(1, 1, 1), configuration);
    for (const auto& pair : expected.pairs) {
      EXPECT_NE(pair.mobile_vertex, 0);
      EXPECT_NE(pair.mobile_vertex, 2);
    }
    if (configuration == RadialConfiguration::kMobileInsideFixed) {
      EXPECT_EQ(expected.pairs.size(), 2u);
    }
  }
}

TEST(RadialHardCases, SliverAndZeroAreaTrianglesNeitherMissNorProduceNaN) {
  // Patch z = 10 over [-2, 2]^2 with: a zero-area triangle closing a T-junction on the diagonal
  // of one quad, a fan of slivers, and a fully collapsed triangle (three equal vertices).
  TriMesh mesh;
  mesh.vertices = {Vec3(-2, -2, 10), Vec3(2, -2, 10), Vec3(2, 2, 10), Vec3(-2, 2, 10),
                   Vec3(0, 0, 10)};  // 4 = midpoint of the diagonal 0-2
  // Quad split along 0-2 with the midpoint 4 on one side only (T-junction) and the zero-area
  // triangle (0, 4, 2) closing it. Winding: normals toward -z (facing O).
  mesh.triangles = {{0, 4, 1}, {4, 2, 1}, {0, 3, 2}, {0, 2, 4}};
  // Slivers: replace nothing, add a fan on a second patch z = 10 over [2, 4] x [-2, 2].
  const int base = static_cast<int>(mesh.vertices.size());
  mesh.vertices.push_back(Vec3(2, -2, 10));
  mesh.vertices.push_back(Vec3(4, -2, 10));
  mesh.vertices.push_back(Vec3(4, 2, 10));
  mesh.vertices.push_back(Vec3(2, 2, 10));
  constexpr int kSlivers = 50;
  // Fan from (2, -2) to the opposite sides: very thin triangles.
  std::vector<int> rim;
  for (int k = 0; k <= kSlivers; ++k) {
    mesh.vertices.push_back(Vec3(4, -2 + 4.0 * k / kSlivers, 10));
    rim.push_back(base + 4 + k);
  }
  for (int k = 0; k < kSlivers; ++k) mesh.triangles.push_back({base, rim[k + 1], rim[k]});
  mesh.triangles.push_back({base, rim.back(), base + 3});
  mesh.triangles.push_back({base + 1, base + 1, base + 1});  // collapsed
  // Mobile vertices beyond the patches, including exactly over the zero-area triangle's line
  // (the diagonal), the T-junction vertex, and the sliver fan's apex and spokes.
  std::vector<Vec3> vertices;
  for (int i = -15; i <= 15; ++i) {
    for (int j = -15; j <= 15; ++j) {
      vertices.push_back(Vec3(i * 0.25, j * 0.25, 20));  // x, y in [-3.75, 3.75] at twice 10
    }
  }
  vertices.push_back(Vec3(0, 0, 20));
  vertices.push_back(Vec3(4.0, -4.0, 20));  // through the fan's apex (2, -2)
  const auto expected =
      check_all(mesh, bare_points(vertices), Vec3::Zero(), RadialConfiguration::kMobileInsideFixed);
  // Closed form: a vertex v at z = 20 whose ray meets the patch (|x/2| <= 2, -2 <= y/2 <= 2,
  // x/2 <= 4) penetrates by |v| / 2 (the plane z = 10 halves the ray).
  std::size_t inside = 0;
  for (const auto& v : vertices) inside += (v.x() / 2 >= -2 && v.x() / 2 <= 4 && std::abs(v.y() / 2) <= 2);
  EXPECT_EQ(expected.pairs.size(), inside);
  for (const auto& pair : expected.pairs) {
    const Vec3& v = vertices[static_cast<std::size_t>(pair.mobile_vertex)];
    EXPECT_NEAR(pair.depth_mm, v.norm() / 2, 1e-12);  // exact arithmetic up to the sqrt
    EXPECT_NE(pair.fixed_triangle, 3);                 // the zero-area triangle is never chosen
  }
}

TEST(RadialHardCases, VertexExactlyOnTheSurfaceDoesNotPenetrate) {
  const TriMesh socket = patch(3, 10.0);
  // On the surface (plane z = 10, at a vertex, on an edge, inside a face), then just beyond it.
  const TriMesh mobile = bare_points({Vec3(1, 2, 10), Vec3(0.5, 0.5, 10), Vec3(0.25, 0.75, 10),
                                 Vec3(1, 2, 10.000001), Vec3(1, 2, 9.999999)});
  const auto expected =
      check_all(socket, mobile, Vec3::Zero(), RadialConfiguration::kMobileInsideFixed);
  ASSERT_EQ(expected.pairs.size(), 1u);
  EXPECT_EQ(expected.pairs[0].mobile_vertex, 3);
  // depth = |v| (1 - 10 / 10.000001) ~ 1e-6 |v| / 10: tiny but positive.
  EXPECT_NEAR(expected.pairs[0].depth_mm, mobile.vertices[3].norm() * (1 - 10 / 10.000001), 1e-12);
}

TEST(RadialHardCases, RaysThroughSharedEdgesAndVerticesAreCountedOnce) {
  const TriMesh socket = patch(3, 10.0);
  std::vector<Vec3> vertices;
  // Through every patch vertex (shared by up to 6 triangles) and edge midpoint: v = 2 P exactly.
  for (int j = -6; j <= 6; ++j) {
    for (int i = -6; i <= 6; ++i) vertices.push_back(Vec3(i * 0.5, j * 0.5, 10) * 2.0);
  }
  const auto expected =
      check_all(socket, bare_points(vertices), Vec3::Zero(), RadialConfiguration::kMobileInsideFixed);
  ASSERT_EQ(expected.pairs.size(), vertices.size());  // no miss (the rim is included)
  for (const auto& pair : expected.pairs) {
    EXPECT_NEAR(pair.depth_mm, vertices[static_cast<std::size_t>(pair.mobile_vertex)].norm() / 2,
                1e-12);
  }
}

TEST(RadialHardCases, OpenMeshWithHolesReportsOnlyWhereThereIsSurface) {
  TriMesh socket = patch(4, 10.0);
  // Cut a 2 x 2 hole around the centre: drop triangles whose centroid has |x|, |y| < 1.
  std::vector<geometry::Triangle> kept;
  for (const auto& t : socket.triangles) {
    const Vec3 centroid = (socket.vertices[t[0]] + socket.vertices[t[1]] + socket.vertices[t[2]]) / 3;
    if (std::abs(centroid.x()) < 1 && std::abs(centroid.y()) < 1) continue;
    kept.push_back(t);
  }
  socket.triangles = kept;
  std::vector<Vec3> vertices;
  for (int j = -10; j <= 10; ++j) {
    for (int i = -10; i <= 10; ++i) vertices.push_back(Vec3(i * 0.5, j * 0.5, 10) * 2.0);
  }
  const auto expected =
      check_all(socket, bare_points(vertices), Vec3::Zero(), RadialConfiguration::kMobileInsideFixed);
  // Closed form: the ray meets surface iff its patch point (x/2, y/2) is in [-4, 4]^2 and not in
  // the open hole (-1, 1)^2 (the hole's rim belongs to the kept triangles).
  std::size_t count = 0;
  for (const auto& v : vertices) {
    const double x = v.x() / 2, y = v.y() / 2;
    const bool on_patch = std::abs(x) <= 4 && std::abs(y) <= 4;
    const bool in_hole = std::abs(x) < 1 && std::abs(y) < 1;
    count += on_patch && !in_hole;
  }
  EXPECT_EQ(expected.pairs.size(), count);
}

TEST(RadialHardCases, TwoNestedLayersUseTheNormalsFig40) {
  // Two shells around O: layer 1 between r = 24 and 28, layer 2 between 32 and 36 (inner
  // surfaces inverted so every normal points out of its solid).
  TriMesh s24 = flipped(geometry::make_octasphere(Vec3::Zero(), 24.0, 4));
  TriMesh s28 = geometry::make_octasphere(Vec3::Zero(), 28.0, 4);
  TriMesh s32 = flipped(geometry::make_octasphere(Vec3::Zero(), 32.0, 4));
  TriMesh s36 = geometry::make_octasphere(Vec3::Zero(), 36.0, 4);
  const TriMesh layers = geometry::merge_meshes({&s24, &s28, &s32, &s36});
  const std::array<double, 5> radii = {23.0, 26.0, 30.0, 34.0, 38.0};
  std::vector<Vec3> vertices;
  const Vec3 direction = Vec3(0.3, -0.5, 0.8).normalized();
  for (const double r : radii) vertices.push_back(r * direction);
  const TriMesh mobile = bare_points(vertices);
  // Sag of a level-4 chord at radius R: R (1 - cos(pi / 64)) < 0.044 mm at R = 36.
  const double sag = 0.044;
  {
    const auto result =
        check_all(layers, mobile, Vec3::Zero(), RadialConfiguration::kMobileInsideFixed);
    // Inside layer 1 (26) and layer 2 (34) penetrate by ~2 mm past the inner surfaces; between
    // the layers (30: Fig. 40's vertex A) and outside (38) the adjacent crossing exits: no.
    ASSERT_EQ(result.pairs.size(), 2u);
    EXPECT_EQ(result.pairs[0].mobile_vertex, 1);
    EXPECT_EQ(result.pairs[1].mobile_vertex, 3);
    for (const auto& pair : result.pairs) {
      EXPECT_GE(pair.depth_mm, 2.0 - 1e-9);
      EXPECT_LE(pair.depth_mm, 2.0 + sag);
    }
  }
  {
    const auto result =
        check_all(layers, mobile, Vec3::Zero(), RadialConfiguration::kFixedInsideMobile);
    // Same two vertices, now measured outward to the outer surfaces 28 and 36.
    ASSERT_EQ(result.pairs.size(), 2u);
    EXPECT_EQ(result.pairs[0].mobile_vertex, 1);
    EXPECT_EQ(result.pairs[1].mobile_vertex, 3);
    for (const auto& pair : result.pairs) {
      EXPECT_GE(pair.depth_mm, 2.0 - sag);
      EXPECT_LE(pair.depth_mm, 2.0 + 1e-9);
    }
  }
}

// The centre on the fixed surface: triangles whose plane contains O (a box face through O, the
// fan around an octasphere vertex at O) cannot be binned by direction; they go to the always
// list, and crossings at O itself (t = 0) do not count.
TEST(RadialHardCases, TrianglesWhosePlanePassesThroughTheCentre) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  std::vector<Vec3> vertices;
  for (int i = 0; i < 400; ++i) vertices.push_back(15.0 * Vec3(g(rng), g(rng), g(rng)));
  const TriMesh mobile = bare_points(vertices);
  // O = (0, 0, 0) inside the face y = 0 of the box.
  const TriMesh box = geometry::make_box(Vec3(-10, 0, -10), Vec3(10, 20, 10), 3);
  const RadialTable table = build_radial_table(box, Vec3::Zero(), {RadialMapping::kCube, 500});
  EXPECT_FALSE(table.always_candidates.empty());
  std::size_t total = 0;
  for (const auto configuration :
       {RadialConfiguration::kMobileInsideFixed, RadialConfiguration::kFixedInsideMobile}) {
    total += check_all(box, mobile, Vec3::Zero(), configuration).pairs.size();
  }
  // O at a vertex of a sphere (the sphere's surface passes through O).
  const TriMesh sphere = geometry::make_octasphere(Vec3(0, 0, -20), 20.0, 3);
  for (const auto configuration :
       {RadialConfiguration::kMobileInsideFixed, RadialConfiguration::kFixedInsideMobile}) {
    total += check_all(sphere, mobile, Vec3::Zero(), configuration).pairs.size();
  }
  EXPECT_GT(total, 100u);
}

// Triangles whose plane passes (nearly) through O but which do not contain O (the revolved rim
// faces of cartilage and labrum): they are binned along the great-circle arc they cover, not
// checked for every vertex, and must still give exactly the oracle's answer, including for rays
// grazing their plane (points placed at the plane's height and a few multiples of it).
TEST(RadialHardCases, TrianglesNearlyInAPlaneThroughTheCentreAreBinned) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> across(-3.0, 3.0), x(0.0, 35.0), z(-15.0, 15.0);
  for (const double height : {0.0, 1e-9, 1e-5}) {  // plane distance of the face from O
    // Bottom face y = height; O = (0, 0, 0) lies outside every face (x >= 5).
    const TriMesh box = geometry::make_box(Vec3(5, height, -10), Vec3(25, 20 + height, 10), 3);
    std::vector<Vec3> vertices;
    for (int i = 0; i < 300; ++i) {
      const double px = x(rng), pz = z(rng);
      // On rays that graze the bottom face: y / x equal to height / x' for x' in the box.
      vertices.emplace_back(px, height * across(rng), pz);
      vertices.emplace_back(px, height, pz);
      vertices.emplace_back(px, 0.001 * across(rng) + height, pz);
    }
    const TriMesh mobile = bare_points(vertices);
    for (const auto mapping : kRadialMappings) {
      // 1e-6 x ~33 mm = 3.3e-5 mm: every bottom triangle is "nearly through O", but with the
      // centre >= 5 mm from each, the band half-width asin(h / d) is tiny: none stays always-checked.
      const RadialTable table = build_radial_table(box, Vec3::Zero(), {mapping, 5000});
      EXPECT_TRUE(table.always_candidates.empty()) << to_string(mapping) << " height " << height;
    }
    std::size_t total = 0;
    for (const auto configuration :
         {RadialConfiguration::kMobileInsideFixed, RadialConfiguration::kFixedInsideMobile}) {
      total += check_all(box, mobile, Vec3::Zero(), configuration).pairs.size();
    }
    EXPECT_GT(total, 50u) << "height " << height;
  }
}

TEST(RadialHardCases, CoordinatesFarFromTheOrigin) {
  const Vec3 far(1e4, -1e4, 1e4);
  // Exact case: integer patch moved by an integer offset: same closed form as near the origin.
  const TriMesh socket = patch(3, 10.0, far);
  std::vector<Vec3> vertices;
  for (int j = -8; j <= 8; ++j) {
    for (int i = -8; i <= 8; ++i) vertices.push_back(far + Vec3(i * 0.5, j * 0.5, 10) * 2.0);
  }
  vertices.push_back(far);  // at the centre
  const auto expected =
      check_all(socket, bare_points(vertices), far, RadialConfiguration::kMobileInsideFixed);
  std::size_t count = 0;
  for (int j = -8; j <= 8; ++j) {
    for (int i = -8; i <= 8; ++i) count += std::abs(i * 0.5) <= 3 && std::abs(j * 0.5) <= 3;
  }
  EXPECT_EQ(expected.pairs.size(), count);
  // Random case: perturbed nested spheres far away, both configurations.
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(-0.04, 0.04);
  TriMesh fixed = flipped(geometry::make_octasphere(far, 25.0, 3));
  TriMesh mobile = geometry::make_octasphere(far + Vec3(0.7, -0.4, 0.2), 24.5, 3);
  for (auto& v : fixed.vertices) v = far + (v - far) * (1 + u(rng));
  for (auto& v : mobile.vertices) v = far + (v - far) * (1 + u(rng));
  const Vec3 centre = far + Vec3(0.1, 0.2, -0.1);
  EXPECT_GT(check_all(fixed, mobile, centre, RadialConfiguration::kMobileInsideFixed).pairs.size(), 10u);
  check_all(fixed, mobile, centre, RadialConfiguration::kFixedInsideMobile);
}

}  // namespace
}  // namespace hipfai::contact
