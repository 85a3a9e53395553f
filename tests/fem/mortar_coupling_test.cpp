// fem::collect_slave_nodes: contact nodes against a rigid plane and against a deformable master
// on a non-matching mesh (mortar weights).
#include "fem/mortar_coupling.h"
#include "core/error.h"
#include "fem/contact_constraints.h"
#include "layer_fixture.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/manifold_lib.h>

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

namespace hipfai::fem {
namespace {

using dealii::Point;

TEST(FemMortarCoupling, NodesAgainstARigidPlane) {
  const testing::LayerContact layer(0.1, 2);
  const std::vector<SlaveNode>& nodes = layer.nodes;
  ASSERT_EQ(nodes.size(), 25u);  // 5 x 5 Q2 nodes on the top
  double area = 0.0;
  for (const SlaveNode& node : nodes) {
    EXPECT_EQ(node.pair, 0u);
    EXPECT_EQ(node.rigid_body, 1);
    EXPECT_NEAR(node.initial_gap, 0.1, 1e-12);
    EXPECT_NEAR(node.normal[2], -1.0, 1e-12);
    EXPECT_EQ(node.constrained_component, 2u);
    EXPECT_NEAR(node.position[2], testing::kLayerThickness, 1e-12);
    area += node.area;
  }
  EXPECT_NEAR(area, testing::kLayerWidth * testing::kLayerWidth, 1e-10);
}

// Two blocks on non-matching meshes in one triangulation: [0,1]^2 x [0,1] (2 x 2 cells,
// material 0, top id 1) and [0,1]^2 x [1 + gap, 2] (3 x 3 cells, material 1, bottom id 2).
ContactModel stacked_blocks(ElasticSystem& system, double gap) {
  dealii::Triangulation<3> lower, upper;
  dealii::GridGenerator::subdivided_hyper_rectangle(lower, {2, 2, 1}, Point<3>(0, 0, 0),
                                                    Point<3>(1, 1, 1));
  dealii::GridGenerator::subdivided_hyper_rectangle(upper, {3, 3, 1}, Point<3>(0, 0, 1 + gap),
                                                    Point<3>(1, 1, 2));
  dealii::GridGenerator::merge_triangulations(lower, upper, system.triangulation());
  for (const auto& cell : system.triangulation().active_cell_iterators()) {
    cell->set_material_id(cell->center()[2] < 1.0 ? 0 : 1);
    for (const unsigned int f : cell->face_indices()) {
      if (!cell->face(f)->at_boundary()) continue;
      const double z = cell->face(f)->center()[2];
      cell->face(f)->set_boundary_id(std::abs(z - 1.0) < 1e-12         ? 1
                                     : std::abs(z - 1.0 - gap) < 1e-12 ? 2
                                                                       : 0);
    }
  }
  ContactModel model;
  model.bodies = {{"lower", 0, {10.0, 0.3}, -1}, {"upper", 1, {10.0, 0.3}, -1}};
  model.contact_pairs = {{2, -1, 1}};
  return model;
}

TEST(FemMortarCoupling, MortarWeightsAgainstANonMatchingMaster) {
  ensure_mpi_initialized();
  ElasticSystem system(MPI_COMM_WORLD, 2, 2);
  const ContactModel model = stacked_blocks(system, 0.05);
  system.setup(model);
  const std::vector<bool> fixed(system.dof_handler().n_dofs(), false);
  const std::vector<SlaveNode> nodes = collect_slave_nodes(system, model, fixed);
  ASSERT_EQ(nodes.size(), 49u);  // 7 x 7 Q2 nodes on the upper block's bottom
  double area = 0.0;
  for (const SlaveNode& node : nodes) {
    EXPECT_EQ(node.rigid_body, -1);
    EXPECT_NEAR(node.normal[2], 1.0, 1e-12);  // out of the master, into the slave
    EXPECT_NEAR(node.initial_gap, 0.05, 1e-12);
    EXPECT_EQ(node.constrained_component, 2u);
    for (unsigned int c = 0; c < 3; ++c) {
      // Covered nodes: the master shape functions integrate to D_s, the weights sum to one.
      double sum = 0.0;
      for (const auto& [dof, weight] : node.master[c]) sum += weight;
      EXPECT_NEAR(sum, 1.0, 1e-12);
    }
    area += node.area;
  }
  EXPECT_NEAR(area, 1.0, 1e-12);
}

// The upper block's bottom curved into a cylinder about the y axis (radius R) that touches the
// lower block's flat top along the line x = 1/3, a vertex line of the upper mesh: the true gap is
// R - sqrt(R^2 - (x - 1/3)^2) >= 0, zero on that line. A node's gap is a weighted average of
// the true gap around it: with the Q2 shape functions as weights, a vertex node's average is
// negative (a quadratic gap weighted by (1 - 2t)(1 - t) integrates to -h^2/60 per unit of its
// weight h/6), i.e. a spurious penetration of a surface that nowhere penetrates.
TEST(FemMortarCoupling, CurvedSlaveNeverGetsASpuriousPenetration) {
  ensure_mpi_initialized();
  constexpr double kRadius = 3.0;  // the gap stays inside the search radius (5 % of the size)
  constexpr double kTouch = 1.0 / 3.0;
  ElasticSystem system(MPI_COMM_WORLD, 2, 2);
  ContactModel model = stacked_blocks(system, 0.05);  // merged apart, then curved
  auto& triangulation = system.triangulation();
  std::vector<bool> moved(triangulation.n_vertices(), false);
  for (const auto& cell : triangulation.active_cell_iterators()) {
    if (cell->material_id() != 1) continue;
    for (const unsigned int f : cell->face_indices()) {
      if (cell->face(f)->boundary_id() != 2) continue;
      cell->face(f)->set_all_manifold_ids(5);
      for (const unsigned int v : cell->face(f)->vertex_indices()) {
        const unsigned int index = cell->face(f)->vertex_index(v);
        if (moved[index]) continue;
        moved[index] = true;
        Point<3>& x = cell->face(f)->vertex(v);
        x[2] = 1.0 + kRadius - std::sqrt(kRadius * kRadius - (x[0] - kTouch) * (x[0] - kTouch));
      }
    }
  }
  triangulation.set_manifold(
      5, dealii::CylindricalManifold<3>(dealii::Tensor<1, 3>({0.0, 1.0, 0.0}),
                                        Point<3>(kTouch, 0.0, 1.0 + kRadius)));
  system.setup(model);
  const std::vector<bool> fixed(system.dof_handler().n_dofs(), false);
  const std::vector<SlaveNode> nodes = collect_slave_nodes(system, model, fixed);
  ASSERT_EQ(nodes.size(), 49u);
  // A half-width a = h / 2 = 1/6 hat about the touching line averages the gap s^2 / (2R) to
  // a^2 / (12 R): the weights are the bilinear hats of the face's 2 x 2 sub-grid.
  const double half_width = 1.0 / 6.0;
  const double on_the_line = half_width * half_width / (12.0 * kRadius);
  const auto gap_at = [&](double x) {
    return kRadius - std::sqrt(kRadius * kRadius - (x - kTouch) * (x - kTouch));
  };
  unsigned int on_line = 0;
  for (const SlaveNode& node : nodes) {
    const double x = node.position[0];
    EXPECT_GE(node.initial_gap, 0.0) << "node at x = " << x;
    if (std::abs(x - kTouch) < 1e-9) {
      ++on_line;
      EXPECT_NEAR(node.initial_gap, on_the_line, 0.03 * on_the_line);
    } else {
      // Between the least and the largest true gap over the node's hat (half a cell either side,
      // inside the block); the gap is convex in x, so an interior node's average is not below
      // its own gap either.
      const double from = std::max(0.0, x - half_width), to = std::min(1.0, x + half_width);
      const double low = from <= kTouch && kTouch <= to ? 0.0 : std::min(gap_at(from), gap_at(to));
      const double high = std::max(gap_at(from), gap_at(to));
      EXPECT_GE(node.initial_gap, low - 1e-4) << "node at x = " << x;
      EXPECT_LE(node.initial_gap, high + 1e-4) << "node at x = " << x;
      if (x > from && x < to) {
        EXPECT_GE(node.initial_gap, gap_at(x) - 1e-4) << "node at x = " << x;
      }
    }
  }
  EXPECT_EQ(on_line, 7u);
}

TEST(FemMortarCoupling, RejectsEmptyBoundaries) {
  ensure_mpi_initialized();
  ElasticSystem system(MPI_COMM_WORLD, 2, 2);
  ContactModel model = stacked_blocks(system, 0.05);
  system.setup(model);
  const std::vector<bool> fixed(system.dof_handler().n_dofs(), false);
  model.contact_pairs = {{2, -1, 7}};  // no master faces
  EXPECT_THROW(collect_slave_nodes(system, model, fixed), Error);
  model.contact_pairs = {{7, -1, 1}};  // no slave faces
  EXPECT_THROW(collect_slave_nodes(system, model, fixed), Error);
}

}  // namespace
}  // namespace hipfai::fem
