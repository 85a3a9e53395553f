// hipfai — the direct linear solver of the contact problem on several ranks.
//
// The unconstrained stiffness K is assembled once per run; each active set only changes the
// constraints u = P v + g (v: the unconstrained dofs, P: identity on them and the closed
// constraint weights on the constrained rows, g: the inhomogeneities), so the reduced matrix
// P^T K P comes from one sparse triple product (PETSc MatPtAP) instead of a condensing
// re-assembly, and is factorised once (MUMPS Cholesky) for all right-hand sides P^T (-K g).
// Same equations as the condensed assembly of fem/cg_amg_linear_solver.h, only without the
// constrained rows that carry no information.
#pragma once

#include "fem/linear_solver.h"

#include <deal.II/lac/petsc_sparse_matrix.h>

namespace hipfai::fem {

class DistributedDirectSolver final : public ContactLinearSolver {
 public:
  DistributedDirectSolver(const ElasticSystem& system, dealii::TimerOutput& timer,
                          dealii::ConditionalOStream& log);
  void begin_run(const LinearSolverSettings& settings) override;
  std::vector<dealii::Vector<double>> solve(const ActiveSetSystems& systems) override;

 private:
  void assemble_stiffness();

  const ElasticSystem& system_;
  dealii::TimerOutput& timer_;
  dealii::ConditionalOStream& log_;
  dealii::PETScWrappers::MPI::SparseMatrix stiffness_;  // K of this run, assembled on first use
  bool stiffness_assembled_ = false;
};

}  // namespace hipfai::fem
