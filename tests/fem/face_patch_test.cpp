// fem::FacePatch: evaluation, normals, projection and line intersection on the flat faces of a
// block (the patch interpolates the Q2 mapping exactly there).
#include "fem/face_patch.h"
#include "block_meshes.h"

#include <gtest/gtest.h>

namespace hipfai::fem {
namespace {

using dealii::Point;
using dealii::Tensor;
using testing::Block;

TEST(FemFacePatch, EvaluatesTheTopFaceOfACube) {
  const Block block(Point<3>(0, 0, 0), Point<3>(1, 1, 1), 1);
  const auto top = block.faces(Block::kTopId);
  ASSERT_EQ(top.size(), 1u);
  const FacePatch patch(block.mapping(), top[0].first, top[0].second);
  Point<3> x;
  Tensor<1, 3> ds, dt;
  patch.evaluate(0.5, 0.5, x, ds, dt);
  EXPECT_LT(x.distance(Point<3>(0.5, 0.5, 1.0)), 1e-12);
  EXPECT_NEAR(ds.norm(), 1.0, 1e-12);  // the unit face: tangents of length 1
  EXPECT_NEAR(dt.norm(), 1.0, 1e-12);
  const Tensor<1, 3> normal = patch.normal(0.3, 0.8);
  EXPECT_NEAR(normal[2], 1.0, 1e-12);  // out of the cell
  for (unsigned int i = 0; i < 4; ++i) EXPECT_NEAR(patch.vertex(i)[2], 1.0, 1e-12);
  EXPECT_LE(patch.box_min[2], 1.0);
  EXPECT_GE(patch.box_max[2], 1.0);
}

TEST(FemFacePatch, BottomNormalPointsOutOfTheCell) {
  const Block block(Point<3>(0, 0, 0), Point<3>(2, 2, 1), 1);
  const auto bottom = block.faces(Block::kBottomId);
  ASSERT_EQ(bottom.size(), 1u);
  const FacePatch patch(block.mapping(), bottom[0].first, bottom[0].second);
  EXPECT_NEAR(patch.normal(0.5, 0.5)[2], -1.0, 1e-12);
}

TEST(FemFacePatch, ProjectsAndIntersectsALine) {
  const Block block(Point<3>(0, 0, 0), Point<3>(2, 2, 1), 1);
  const auto top = block.faces(Block::kTopId);
  const FacePatch patch(block.mapping(), top[0].first, top[0].second);
  double s = 0.0, t = 0.0;
  ASSERT_TRUE(patch.project(Point<3>(0.6, 1.4, 3.0), s, t));
  Point<3> x;
  Tensor<1, 3> ds, dt;
  patch.evaluate(s, t, x, ds, dt);
  EXPECT_LT(x.distance(Point<3>(0.6, 1.4, 1.0)), 1e-10);
  // The reference-cell point of (s, t) lies on the cell's top face (unit z = 1).
  EXPECT_NEAR(patch.unit_cell_point(s, t)[2], 1.0, 1e-12);

  double lambda = 0.0;
  ASSERT_TRUE(
      patch.intersect_line(Point<3>(0.5, 0.5, 2.0), Tensor<1, 3>({0.5, 0.0, -1.0}), s, t, lambda));
  patch.evaluate(s, t, x, ds, dt);
  EXPECT_NEAR(lambda, 1.0, 1e-10);
  EXPECT_LT(x.distance(Point<3>(1.0, 0.5, 1.0)), 1e-10);
}

TEST(FemFacePatch, ExtendsBeyondTheFace) {
  const Block block(Point<3>(0, 0, 0), Point<3>(1, 1, 1), 1);
  const auto top = block.faces(Block::kTopId);
  const FacePatch patch(block.mapping(), top[0].first, top[0].second);
  double s = 0.0, t = 0.0;
  ASSERT_TRUE(patch.project(Point<3>(1.5, 0.5, 1.2), s, t));  // past the face's edge
  EXPECT_TRUE(s > 1.0 || s < 0.0 || t > 1.0 || t < 0.0);
  Point<3> x;
  Tensor<1, 3> ds, dt;
  patch.evaluate(s, t, x, ds, dt);
  EXPECT_LT(x.distance(Point<3>(1.5, 0.5, 1.0)), 1e-10);
}

}  // namespace
}  // namespace hipfai::fem
