// fem::MortarSegmenter: segment-based integration of a slave surface against a non-matching
// master surface (coplanar blocks: the integrals are exact, the patch test holds).
#include "fem/mortar_segments.h"
#include "block_meshes.h"
#include "fem/boundary_projection.h"

#include <gtest/gtest.h>

namespace hipfai::fem {
namespace {

using dealii::Point;
using testing::Block;

// Master: the top of a 2 x 2 block [0,1]^2 x [0,1]; slave: the bottom of a 3 x 3 block above it.
struct StackedBlocks {
  Block master{Point<3>(0, 0, 0), Point<3>(1, 1, 1), 2};
  Block slave;
  BoundaryProjector projector{master.mapping(), master.dof_handler(), Block::kTopId};
  explicit StackedBlocks(double gap_mm) : slave(Point<3>(0, 0, 1 + gap_mm), Point<3>(1, 1, 2), 3) {}
};

TEST(FemMortarSegments, CoversTheSlaveSurfaceExactly) {
  const StackedBlocks blocks(0.0);
  MortarSegmentOptions options;
  options.search_radius_mm = 0.1;
  const MortarSegmenter segmenter(blocks.projector.faces(), options);
  double area = 0.0, moment_x = 0.0, moment_y = 0.0;
  for (const auto& [cell, face_no] : blocks.slave.faces(Block::kBottomId)) {
    const FacePatch slave(blocks.slave.mapping(), cell, face_no);
    EXPECT_TRUE(is_bilinear(slave));
    for (const MortarPoint& point : segmenter.integrate(slave)) {
      ASSERT_NE(point.master, nullptr);
      EXPECT_LT(point.master_point_mm.distance(point.slave_point_mm), 1e-10);  // coplanar
      EXPECT_NEAR(point.master_normal[2], 1.0, 1e-12);
      area += point.jxw;
      moment_x += point.jxw * point.slave_point_mm[0];
      moment_y += point.jxw * point.slave_point_mm[1];
    }
  }
  EXPECT_NEAR(area, 1.0, 1e-12);
  EXPECT_NEAR(moment_x, 0.5, 1e-12);  // the centroid of the unit square
  EXPECT_NEAR(moment_y, 0.5, 1e-12);
}

TEST(FemMortarSegments, MasterPointsLieOnTheMasterFaceTheyName) {
  const StackedBlocks blocks(0.05);
  MortarSegmentOptions options;
  options.search_radius_mm = 0.1;
  const MortarSegmenter segmenter(blocks.projector.faces(), options);
  std::size_t points = 0;
  for (const auto& [cell, face_no] : blocks.slave.faces(Block::kBottomId)) {
    const FacePatch slave(blocks.slave.mapping(), cell, face_no);
    for (const MortarPoint& point : segmenter.integrate(slave)) {
      ++points;
      // Along the slave normal (z) onto the master plane z = 1, inside the named master face.
      EXPECT_NEAR(point.master_point_mm[2], 1.0, 1e-12);
      EXPECT_NEAR(point.slave_point_mm[2] - point.master_point_mm[2], 0.05, 1e-12);
      EXPECT_NEAR(point.master_point_mm[0], point.slave_point_mm[0], 1e-12);
      for (unsigned int d = 0; d < 2; ++d) {
        EXPECT_GE(point.master_point_mm[d], point.master->box_min[d] - 1e-12);
        EXPECT_LE(point.master_point_mm[d], point.master->box_max[d] + 1e-12);
      }
    }
  }
  EXPECT_GT(points, 0u);
}

TEST(FemMortarSegments, IgnoresMastersBeyondTheSearchRadius) {
  const StackedBlocks blocks(0.5);
  MortarSegmentOptions options;
  options.search_radius_mm = 0.1;
  const MortarSegmenter segmenter(blocks.projector.faces(), options);
  for (const auto& [cell, face_no] : blocks.slave.faces(Block::kBottomId)) {
    const FacePatch slave(blocks.slave.mapping(), cell, face_no);
    EXPECT_TRUE(segmenter.integrate(slave).empty());
  }
}

}  // namespace
}  // namespace hipfai::fem
