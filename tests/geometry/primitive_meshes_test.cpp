#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hipfai::geometry {
namespace {

TEST(Octasphere, VertexCountsMatchThesisTable2) {
  const int expected[] = {6, 18, 66, 258, 1026, 4098};
  for (int level = 0; level < 6; ++level) {
    EXPECT_EQ(make_octasphere(Vec3::Zero(), 1.0, level).num_vertices(),
              static_cast<std::size_t>(expected[level]));
  }
}

// An inscribed polyhedron's volume approaches 4/3 pi r^3 from below.
TEST(Octasphere, ClosedOutwardAndConvergingVolume) {
  const auto mesh = make_octasphere(Vec3(1, 2, 3), 10.0, 5);
  const double exact = 4.0 / 3.0 * std::numbers::pi * 1000.0;
  const double volume = signed_volume(make_octasphere(Vec3::Zero(), 10.0, 5));
  EXPECT_GT(volume, 0.99 * exact);
  EXPECT_LT(volume, exact);
  for (const Vec3& p : mesh.vertices) EXPECT_NEAR((p - Vec3(1, 2, 3)).norm(), 10.0, 1e-12);
}

TEST(Box, VolumeAndAreaAreExact) {
  const auto box = make_box(Vec3(0, 0, 0), Vec3(1, 2, 3), 4);
  EXPECT_NEAR(signed_volume(box), 6.0, 1e-12);
  EXPECT_NEAR(surface_area(box), 2.0 * (2 + 3 + 6), 1e-12);
  EXPECT_EQ(box.num_vertices(), 6u * 4 * 4 + 2);  // V = 6 n^2 + 2 for a closed box grid
}

// Inscribed n-gons lose a fraction ~ (2 pi / n)^2 / 6 of the area: 0.16 % for the 64-gon
// section, 0.04 % for the 128-gon ring, so 0.2 % below Pappus' 2 pi^2 R r^2; 0.3 % allowed.
TEST(Torus, VolumeApproachesPappus) {
  const auto torus = make_torus(Vec3::Zero(), 10.0, 3.0, 128, 64);
  const double exact = 2.0 * std::numbers::pi * std::numbers::pi * 10.0 * 9.0;
  EXPECT_NEAR(signed_volume(torus) / exact, 1.0, 3e-3);
  EXPECT_LT(signed_volume(torus), exact);
}

}  // namespace
}  // namespace hipfai::geometry
