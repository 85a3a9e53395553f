// fem::BoundaryProjector: closest points on a deformable boundary, its normal and the master
// interpolation weights, and the search radius.
#include "fem/boundary_projection.h"
#include "block_meshes.h"

#include <gtest/gtest.h>

namespace hipfai::fem {
namespace {

using dealii::Point;
using testing::Block;

TEST(FemBoundaryProjection, FindsTheClosestPointOnTheTopFaces) {
  const Block block(Point<3>(0, 0, 0), Point<3>(2, 2, 1), 2);
  const BoundaryProjector projector(block.mapping(), block.dof_handler(), Block::kTopId);
  EXPECT_EQ(projector.n_faces(), 4u);
  EXPECT_EQ(projector.faces().size(), 4u);
  const BoundaryProjection projection = projector.project(Point<3>(0.3, 1.7, 1.5), 1.0);
  ASSERT_TRUE(projection.found);
  EXPECT_LT(projection.point_mm.distance(Point<3>(0.3, 1.7, 1.0)), 1e-10);
  EXPECT_NEAR(projection.distance_mm, 0.5, 1e-10);
  EXPECT_NEAR(projection.normal[2], 1.0, 1e-12);  // out of the master body
}

TEST(FemBoundaryProjection, WeightsInterpolateEachComponent) {
  const Block block(Point<3>(0, 0, 0), Point<3>(2, 2, 1), 2);
  const BoundaryProjector projector(block.mapping(), block.dof_handler(), Block::kTopId);
  const BoundaryProjection projection = projector.project(Point<3>(1.3, 0.4, 1.2), 1.0);
  ASSERT_TRUE(projection.found);
  for (unsigned int c = 0; c < 3; ++c) {
    // Lagrange shape functions form a partition of unity: a translation is reproduced.
    double sum = 0.0;
    for (const auto& [dof, weight] : projection.weights[c]) sum += weight;
    EXPECT_NEAR(sum, 1.0, 1e-12) << c;
    EXPECT_FALSE(projection.weights[c].empty());
  }
}

TEST(FemBoundaryProjection, ClampsToTheBoundaryAndHonoursTheSearchRadius) {
  const Block block(Point<3>(0, 0, 0), Point<3>(1, 1, 1), 1);
  const BoundaryProjector projector(block.mapping(), block.dof_handler(), Block::kTopId);
  // Past the edge: the closest point is on the edge.
  const BoundaryProjection edge = projector.project(Point<3>(1.5, 0.5, 1.0), 1.0);
  ASSERT_TRUE(edge.found);
  EXPECT_LT(edge.point_mm.distance(Point<3>(1.0, 0.5, 1.0)), 1e-10);
  EXPECT_NEAR(edge.distance_mm, 0.5, 1e-10);
  // Farther from every face's box than the radius: nothing found.
  EXPECT_FALSE(projector.project(Point<3>(0.5, 0.5, 3.0), 0.5).found);
  // No faces with that id at all.
  const BoundaryProjector none(block.mapping(), block.dof_handler(), 9);
  EXPECT_EQ(none.n_faces(), 0u);
  EXPECT_FALSE(none.project(Point<3>(0.5, 0.5, 1.0), 10.0).found);
}

}  // namespace
}  // namespace hipfai::fem
