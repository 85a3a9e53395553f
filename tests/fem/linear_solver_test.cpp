// The linear solvers of the contact problem (fem/linear_solver.h) agree on one active set, and
// the bordered low-rank update of the one-rank direct solver gives the solution of a fresh
// factorisation.
#include "fem/linear_solver.h"
#include "fem/cg_amg_linear_solver.h"
#include "fem/distributed_direct_solver.h"
#include "fem/serial_direct_solver.h"
#include "layer_fixture.h"

#include <gtest/gtest.h>

#include <iostream>

namespace hipfai::fem {
namespace {

// The layer pressed by the plate (0.1 mm gap) moved down by 0.15 and 0.2 mm: two translation sets.
struct PressedLayer : testing::LayerContact {
  std::vector<std::vector<dealii::Tensor<1, 3>>> translation_sets = {
      {{}, dealii::Tensor<1, 3>({0, 0, -0.15})}, {{}, dealii::Tensor<1, 3>({0, 0, -0.2})}};
  dealii::ConditionalOStream log{std::cout, false};
  dealii::TimerOutput timer{log, dealii::TimerOutput::never, dealii::TimerOutput::wall_times};

  PressedLayer() : LayerContact(0.1, 2) {}
  std::vector<dealii::Vector<double>> solve(ContactLinearSolver& solver,
                                            const std::vector<bool>& active) {
    std::vector<dealii::AffineConstraints<double>> sets;
    for (const auto& translations : translation_sets)
      sets.push_back(constraints.make(translations, nodes, active));
    return solver.solve({sets, translation_sets, nodes, active});
  }
};

double relative_difference(const dealii::Vector<double>& a, const dealii::Vector<double>& b) {
  dealii::Vector<double> difference = a;
  difference -= b;
  return difference.linfty_norm() / b.linfty_norm();
}

TEST(FemLinearSolver, AllSolversAgree) {
  PressedLayer layer;
  const std::vector<bool> active(layer.nodes.size(), true);
  CgAmgLinearSolver cg(*layer.system, layer.timer);
  DistributedDirectSolver distributed(*layer.system, layer.timer, layer.log);
  SerialDirectSolver serial(*layer.system, layer.constraints, layer.timer, layer.log);
  std::vector<std::vector<dealii::Vector<double>>> answers;
  for (ContactLinearSolver* solver :
       std::initializer_list<ContactLinearSolver*>{&serial, &distributed, &cg}) {
    solver->begin_run({});
    answers.push_back(layer.solve(*solver, active));
    EXPECT_FALSE(solver->statistics().failed);
    EXPECT_EQ(solver->statistics().linear_solves, 2u);
    solver->end_run();
  }
  EXPECT_EQ(serial.statistics().factorisations, 1u);
  EXPECT_EQ(distributed.statistics().factorisations, 1u);
  EXPECT_GT(cg.statistics().linear_iterations, 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_LT(relative_difference(answers[1][k], answers[0][k]), 1e-10);
    EXPECT_LT(relative_difference(answers[2][k], answers[0][k]), 1e-8);
  }
  // The contact constraints hold: the top follows the plate.
  const SlaveNode& node = layer.nodes.front();
  EXPECT_NEAR(answers[0][0][node.dofs[2]], -0.05, 1e-12);
  EXPECT_NEAR(answers[0][1][node.dofs[2]], -0.1, 1e-12);
}

TEST(FemLinearSolver, BorderedUpdateMatchesAFreshFactorisation) {
  PressedLayer layer;
  std::vector<bool> active(layer.nodes.size(), true);
  SerialDirectSolver updated(*layer.system, layer.constraints, layer.timer, layer.log);
  updated.begin_run({});
  layer.solve(updated, active);
  active[3] = false;  // release two nodes, the factor stays
  active[7] = false;
  const auto bordered = layer.solve(updated, active);
  EXPECT_EQ(updated.statistics().factorisations, 1u);
  EXPECT_EQ(updated.statistics().low_rank_updates, 1u);

  SerialDirectSolver fresh(*layer.system, layer.constraints, layer.timer, layer.log);
  LinearSolverSettings no_updates;
  no_updates.low_rank_updates = false;
  fresh.begin_run(no_updates);
  const auto direct = layer.solve(fresh, active);
  EXPECT_EQ(fresh.statistics().low_rank_updates, 0u);
  for (std::size_t k = 0; k < 2; ++k) EXPECT_LT(relative_difference(bordered[k], direct[k]), 1e-10);
}

TEST(FemLinearSolver, FactoryPicksTheSolverOfTheKind) {
  PressedLayer layer;
  const auto cg = make_contact_linear_solver(LinearSolver::kCgAmg, *layer.system, layer.constraints,
                                             layer.timer, layer.log);
  EXPECT_NE(dynamic_cast<CgAmgLinearSolver*>(cg.get()), nullptr);
  const auto direct = make_contact_linear_solver(LinearSolver::kDirect, *layer.system,
                                                 layer.constraints, layer.timer, layer.log);
  EXPECT_NE(dynamic_cast<SerialDirectSolver*>(direct.get()), nullptr);  // one rank
  EXPECT_STREQ(to_string(LinearSolver::kDirect), "direct");
  EXPECT_STREQ(to_string(LinearSolver::kCgAmg), "cg_amg");
}

}  // namespace
}  // namespace hipfai::fem
