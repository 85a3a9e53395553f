// fem::ActiveSetStrategy and evaluate_nodes on synthetic contact nodes: the primal-dual update
// rule, one master per slave node, cycle detection and the warm start.
#include "fem/active_set_strategy.h"

#include <gtest/gtest.h>

#include <iostream>
#include <sstream>

namespace hipfai::fem {
namespace {

// A node of `pair` whose x, y, z dofs are 3 d, 3 d + 1, 3 d + 2, normal +z, against a rigid body.
SlaveNode node(unsigned int pair, dealii::types::global_dof_index d, double initial_gap) {
  SlaveNode out;
  out.pair = pair;
  out.dofs = {3 * d, 3 * d + 1, 3 * d + 2};
  out.constrained_component = 2;
  out.normal = dealii::Tensor<1, 3>({0, 0, 1});
  out.initial_gap = initial_gap;
  out.area = 1.0;
  out.rigid_body = 0;
  return out;
}

TEST(FemActiveSet, EvaluatesForcesAndGaps) {
  const std::vector<SlaveNode> nodes = {node(0, 0, 0.1)};
  Linearization state;
  state.displacement.reinit(3);
  state.displacement[2] = -0.05;  // the slave moves towards the master
  state.internal_force = {0.0, 0.0, 2.0};
  const std::vector<dealii::Tensor<1, 3>> translations = {dealii::Tensor<1, 3>({0, 0, 0.02})};
  std::vector<double> force, gap;
  evaluate_nodes(nodes, state, translations, force, gap);
  EXPECT_DOUBLE_EQ(force[0], 2.0);
  EXPECT_NEAR(gap[0], 0.1 - 0.05 - 0.02, 1e-15);
}

TEST(FemActiveSet, PrimalDualRule) {
  ActiveSetStrategy strategy;
  strategy.begin_run({}, 1e-12);
  const std::vector<SlaveNode> nodes = {node(0, 0, 0), node(0, 1, 0), node(0, 2, 0), node(0, 3, 0)};
  const std::vector<bool> active = {true, true, false, false};
  // Node 0: compressive, stays; node 1: tensile, leaves; node 2: penetrates, enters; node 3: open.
  const std::vector<double> force = {1.0, -1.0, 0.0, 0.0}, gap = {0.0, 0.0, -0.01, 0.01};
  dealii::ConditionalOStream log(std::cout, false);
  const std::vector<bool> next = strategy.next(2, false, nodes, active, force, gap, log);
  EXPECT_EQ(next, (std::vector<bool>{true, false, true, false}));
}

TEST(FemActiveSet, LoadControlEntersTheDeeperHalfFirst) {
  ActiveSetStrategy strategy;
  strategy.begin_run({}, 1e-12);
  const std::vector<SlaveNode> nodes = {node(0, 0, 0), node(0, 1, 0)};
  const std::vector<double> force = {0.0, 0.0}, gap = {-0.1, -0.04};
  dealii::ConditionalOStream log(std::cout, false);
  EXPECT_EQ(strategy.next(1, true, nodes, {false, false}, force, gap, log),
            (std::vector<bool>{true, false}));
  EXPECT_EQ(strategy.next(2, true, nodes, {false, false}, force, gap, log),
            (std::vector<bool>{true, true}));
}

TEST(FemActiveSet, OneMasterPerSlaveNode) {
  ActiveSetStrategy strategy;
  strategy.begin_run({}, 1e-12);
  // The same slave node (dofs 0-2) in two pairs.
  const std::vector<SlaveNode> nodes = {node(0, 0, 0), node(1, 0, 0)};
  std::vector<bool> set = {true, true};
  strategy.one_constraint_per_node(nodes, set, {-0.01, -0.02});
  EXPECT_EQ(set, (std::vector<bool>{false, true}));  // the deeper penetration holds it
  // Held by pair 0 now: kept (infinite switch margin) though pair 1 is penetrated more.
  set = {true, true};
  const std::vector<bool> current = {true, false};
  strategy.one_constraint_per_node(nodes, set, {-0.01, -0.02}, &current);
  EXPECT_EQ(set, (std::vector<bool>{true, false}));
  // A finite margin lets the node switch when the other master is penetrated by more than it.
  strategy.begin_run({0.005, true}, 1e-12);
  set = {true, true};
  strategy.one_constraint_per_node(nodes, set, {-0.01, -0.02}, &current);
  EXPECT_EQ(set, (std::vector<bool>{false, true}));
}

TEST(FemActiveSet, DetectsACycleAndChangesOneNodeAtATime) {
  ActiveSetStrategy strategy;
  strategy.begin_run({}, 1e-12);
  const std::vector<SlaveNode> nodes = {node(0, 0, 0), node(0, 1, 0)};
  dealii::ConditionalOStream log(std::cout, false);
  // From {} both nodes penetrate: enter both.
  const std::vector<bool> first =
      strategy.next(1, false, nodes, {false, false}, {0, 0}, {-1, -1}, log);
  EXPECT_EQ(first, (std::vector<bool>{true, true}));
  // From {0, 1} both are tensile: the plain rule returns to {}, a set already solved.
  const std::vector<bool> second = strategy.next(2, false, nodes, first, {-1, -1}, {0, 0}, log);
  EXPECT_EQ(second, (std::vector<bool>{false, true}));  // the least-index rule: one change
}

TEST(FemActiveSet, ConvergenceIsNoCycle) {
  ActiveSetStrategy strategy;
  strategy.begin_run({}, 1e-12);
  const std::vector<SlaveNode> nodes = {node(0, 0, 0), node(0, 1, 0)};
  std::ostringstream text;
  dealii::ConditionalOStream log(text, true);
  const std::vector<bool> active = {true, false};
  // Node 0 compressive, node 1 open: the set just solved comes back, unchanged and unflagged.
  EXPECT_EQ(strategy.next(1, false, nodes, active, {1, 0}, {0, 1}, log), active);
  EXPECT_EQ(text.str(), "");
}

TEST(FemActiveSet, WarmStartFromTheLastConvergedRun) {
  ActiveSetStrategy strategy;
  strategy.begin_run({}, 1e-12);
  const std::vector<SlaveNode> nodes = {node(0, 0, 0.1), node(0, 1, -0.1)};
  const std::vector<dealii::Tensor<1, 3>> translations = {dealii::Tensor<1, 3>()};
  // No history: the geometric overlap.
  EXPECT_EQ(strategy.initial(nodes, translations, 6), (std::vector<bool>{false, true}));
  // Converged with node 0 closed by a displacement of -0.1: predicted closed at the next start.
  dealii::Vector<double> displacement(6);
  displacement[2] = -0.1;
  strategy.remember_converged(nodes, {true, false}, displacement);
  EXPECT_EQ(strategy.initial(nodes, translations, 6), (std::vector<bool>{true, true}));
  // A different dof layout: no prediction, the last converged set.
  EXPECT_EQ(strategy.initial(nodes, translations, 9), (std::vector<bool>{true, false}));
  // Warm start off: the geometric overlap again.
  strategy.begin_run({std::numeric_limits<double>::infinity(), false}, 1e-12);
  EXPECT_EQ(strategy.initial(nodes, translations, 6), (std::vector<bool>{false, true}));
}

// A load needs a contact to be carried: with every node open the least open one starts closed
// (a body under a load with nothing closed has no equilibrium to solve for).
TEST(FemActiveSet, NeverStartsEmpty) {
  ActiveSetStrategy strategy;
  strategy.begin_run({}, 1e-12);
  const std::vector<SlaveNode> nodes = {node(0, 0, 0.3), node(0, 1, 0.1), node(0, 2, 0.2)};
  const std::vector<dealii::Tensor<1, 3>> translations = {dealii::Tensor<1, 3>()};
  EXPECT_EQ(strategy.initial(nodes, translations, 9), (std::vector<bool>{false, true, false}));
  EXPECT_TRUE(strategy.initial({}, translations, 0).empty());
}

}  // namespace
}  // namespace hipfai::fem
