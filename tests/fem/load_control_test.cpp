// fem::LoadControl and transmitted_force: the translation that balances a prescribed force, on
// synthetic states that are affine in the translation.
#include "fem/load_control.h"

#include <gtest/gtest.h>

namespace hipfai::fem {
namespace {

using dealii::Tensor;

// One contact node (dofs 0-2, normal +z) against rigid body 0 and one bonded dof (3, z) on it.
struct Spring {
  std::vector<SlaveNode> nodes;
  std::vector<BondedDof> bonded = {{3, 2, 0, 0.0}};
  std::vector<bool> active = {true};
  Spring() {
    SlaveNode node;
    node.dofs = {0, 1, 2};
    node.constrained_component = 2;
    node.normal = Tensor<1, 3>({0, 0, 1});
    node.rigid_body = 0;
    nodes.push_back(node);
  }
  // The state of a translation t_z: nodal force k t_z at the contact node, 0.5 k t_z at the
  // bonded dof (an affine model of two springs).
  Linearization state(double t_z, double k) const {
    Linearization out;
    out.displacement.reinit(4);
    out.displacement[2] = t_z;
    out.internal_force = {0.0, 0.0, k * t_z, 0.5 * k * t_z};
    return out;
  }
};

TEST(FemLoadControl, TransmittedForceSumsContactAndBondedReactions) {
  const Spring spring;
  const auto force =
      transmitted_force(1, spring.bonded, spring.nodes, spring.active, spring.state(2.0, 10.0));
  ASSERT_EQ(force.size(), 1u);
  EXPECT_DOUBLE_EQ(force[0][2], 20.0 + 10.0);
  // An inactive node transmits nothing through contact.
  const auto open =
      transmitted_force(1, spring.bonded, spring.nodes, {false}, spring.state(2.0, 10.0));
  EXPECT_DOUBLE_EQ(open[0][2], 10.0);
}

TEST(FemLoadControl, BalancesThePrescribedForce) {
  ContactModel model;
  RigidBody body;
  body.load_controlled = true;
  body.free_directions = {Tensor<1, 3>({0, 0, 2})};  // normalised by LoadControl
  body.force_n = Tensor<1, 3>({0, 0, 45.0});
  model.rigid_bodies = {body};
  const LoadControl control(model);
  ASSERT_FALSE(control.empty());
  std::vector<Tensor<1, 3>> translations = {Tensor<1, 3>({0, 0, 0.5})};
  const auto sets = control.probe_translations(translations);
  ASSERT_EQ(sets.size(), 2u);
  EXPECT_DOUBLE_EQ(sets[1][0][2], 1.5);  // moved by a unit step
  const Spring spring;
  std::vector<Linearization> probes = {spring.state(sets[0][0][2], 10.0),
                                       spring.state(sets[1][0][2], 10.0)};
  Linearization state;
  ASSERT_TRUE(control.balance(model, spring.bonded, spring.nodes, spring.active, probes,
                              translations, state));
  // 15 N per mm: 45 N at 3 mm.
  EXPECT_NEAR(translations[0][2], 3.0, 1e-12);
  EXPECT_NEAR(state.displacement[2], 3.0, 1e-12);
  EXPECT_NEAR(state.internal_force[2] + state.internal_force[3], 45.0, 1e-12);
}

TEST(FemLoadControl, NoSensitivityMeansNoContact) {
  ContactModel model;
  RigidBody body;
  body.load_controlled = true;
  body.free_directions = {Tensor<1, 3>({1, 0, 0})};
  model.rigid_bodies = {body};
  const LoadControl control(model);
  const Spring spring;
  std::vector<Tensor<1, 3>> translations = {Tensor<1, 3>()};
  std::vector<Linearization> probes = {spring.state(0.0, 10.0), spring.state(0.0, 10.0)};
  Linearization state;
  EXPECT_FALSE(control.balance(model, spring.bonded, spring.nodes, spring.active, probes,
                               translations, state));
  EXPECT_EQ(translations[0].norm(), 0.0);
  EXPECT_TRUE(LoadControl(ContactModel{}).empty());
}

}  // namespace
}  // namespace hipfai::fem
