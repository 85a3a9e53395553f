// fem::ContactConstraints: bonded and symmetry dofs, and the constraints of active contact nodes.
#include "fem/contact_constraints.h"
#include "fem/mortar_coupling.h"
#include "layer_fixture.h"

#include <gtest/gtest.h>

namespace hipfai::fem {
namespace {

using testing::layer_model;
using testing::layer_system;

TEST(FemContactConstraints, BondedDofsFollowTheBoneAndSymmetryDofsAreHeld) {
  ContactModel model = layer_model(0.0);
  model.bonded_boundaries[0].extra_displacement_mm = [](const dealii::Point<3>& x) {
    return dealii::Tensor<1, 3>({0.0, 0.0, 0.01 * x[0]});
  };
  const auto system = layer_system(model, 2);
  ContactConstraints constraints;
  constraints.collect_fixed_dofs(*system, model);
  EXPECT_FALSE(constraints.has_hanging_nodes());
  // The bottom: 5 x 5 support points, three components each, all bonded to rigid body 0.
  ASSERT_EQ(constraints.bonded_dofs().size(), 75u);
  const std::vector<dealii::Tensor<1, 3>> translations = {dealii::Tensor<1, 3>({0.1, 0.2, 0.3}),
                                                          {}};
  const dealii::AffineConstraints<double> c = constraints.make(translations, {}, {});
  for (const BondedDof& bonded : constraints.bonded_dofs()) {
    EXPECT_EQ(bonded.rigid_body, 0);
    EXPECT_TRUE(constraints.fixed_dofs()[bonded.dof]);
    const double x = system->support_points()[bonded.dof][0];
    const double expected =
        translations[0][bonded.component] + (bonded.component == 2 ? 0.01 * x : 0.0);
    EXPECT_NEAR(c.get_inhomogeneity(bonded.dof), expected, 1e-15);
  }
  // Symmetry: the x walls hold u_x, the y walls u_y; dofs on the bottom stay bonded.
  std::size_t held = 0;
  for (dealii::types::global_dof_index i = 0; i < system->dof_handler().n_dofs(); ++i) {
    if (!c.is_constrained(i)) continue;
    ++held;
    EXPECT_TRUE(constraints.fixed_dofs()[i]);
  }
  // Walls without the bottom row: x walls 2 x (5 x 4) u_x, y walls 2 x (5 x 4) u_y, the
  // vertical edges counted on both (u_x and u_y of their own).
  EXPECT_EQ(held, 75u + 40u + 40u);
}

TEST(FemContactConstraints, AnActiveNodeAgainstARigidPlaneIsClosed) {
  const testing::LayerContact layer(0.1, 1);
  const std::vector<SlaveNode>& nodes = layer.nodes;
  const ContactConstraints& constraints = layer.constraints;
  ASSERT_FALSE(nodes.empty());
  std::vector<bool> active(nodes.size(), true);
  const std::vector<dealii::Tensor<1, 3>> translations = {{}, dealii::Tensor<1, 3>({0, 0, -0.3})};
  const dealii::AffineConstraints<double> c = constraints.make(translations, nodes, active);
  for (const SlaveNode& node : nodes) {
    // Normal -z: u_z = -(gap) + t . n / n_z = -0.1 - 0.3 + ... , i.e. the top moves down by 0.2.
    const auto dof = node.dofs[node.constrained_component];
    ASSERT_TRUE(c.is_constrained(dof));
    EXPECT_EQ(node.constrained_component, 2u);
    EXPECT_NEAR(c.get_inhomogeneity(dof), -0.2, 1e-12);
  }
  // Inactive nodes carry no contact constraint.
  active.assign(nodes.size(), false);
  const dealii::AffineConstraints<double> open = constraints.make(translations, nodes, active);
  EXPECT_FALSE(open.is_constrained(nodes.front().dofs[2]));
}

}  // namespace
}  // namespace hipfai::fem
