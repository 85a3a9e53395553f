// hipfai — the iterative linear solver of the contact problem: the system condensed through the
// constraints of the active set, assembled with AffineConstraints::distribute_local_to_global,
// and solved by CG + GAMG (fem/petsc_solvers.h). The matrix and its preconditioner are set up
// once per active set; every translation set costs one right-hand side and one CG solve.
#pragma once

#include "fem/linear_solver.h"

namespace hipfai::fem {

class CgAmgLinearSolver final : public ContactLinearSolver {
 public:
  CgAmgLinearSolver(const ElasticSystem& system, dealii::TimerOutput& timer);
  std::vector<dealii::Vector<double>> solve(const ActiveSetSystems& systems) override;

 private:
  const ElasticSystem& system_;
  dealii::TimerOutput& timer_;
};

}  // namespace hipfai::fem
