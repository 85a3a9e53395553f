// hipfai — the direct linear solver of the contact problem on one rank, with bordered (low-rank)
// updates between active sets.
//
// K is assembled once per run (its sparsity pattern kept across runs while the dof layout stays
// the same). An active set is solved with the Cholesky factor of its reduced system
// (fem/reduced_system.h), the "base". A later active set that differs from the base in a few
// nodes is solved with the same factor and a bordered correction instead of a new reduction
// and factorisation: most motion steps change 1-8 of several hundred contact nodes and then
// only confirm.
//
// The correction: the base solves  min 1/2 u^T K u  over u = P v + g. The current active set
// releases some of the base's contact nodes (R) and adds others (N). With E the unit vectors of
// the released slave dofs and C_N u = h_N the added constraints, the current problem is
//   min over (v, delta) of 1/2 u^T K u,  u = P v + E delta + g,  subject to C_N u = h_N,
// whose optimality system borders the factorised A = P^T K P:
//   [ A    B ] [ v ]   [ -P^T K g       ]      B = [ P^T K E , P^T C_N^T ]
//   [ B^T  D ] [ y ] = [ -E^T K g ; h_N - C_N g ],  D = [ E^T K E , E^T C_N^T ; C_N E , 0 ],
// y = (delta, multipliers). With Z = A^-1 B (one solve per change) and S = D - B^T Z (dense,
// small): y = S^-1 (d - B^T A^-1 b), v = A^-1 b - Z y. Exact, as elimination would be; a new
// base is factorised instead when the change is large, when a released dof is named by a kept
// constraint (the base's closed constraints would have it substituted away), when there are
// hanging nodes, or when S is singular.
#pragma once

#include "fem/linear_solver.h"
#include "fem/reduced_system.h"

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

namespace hipfai::fem {

class SerialDirectSolver final : public ContactLinearSolver {
 public:
  SerialDirectSolver(const ElasticSystem& system, const ContactConstraints& constraints,
                     dealii::TimerOutput& timer, dealii::ConditionalOStream& log);
  void begin_run(const LinearSolverSettings& settings) override;
  void end_run() override;
  std::vector<dealii::Vector<double>> solve(const ActiveSetSystems& systems) override;

 private:
  void assemble_stiffness();
  std::vector<dealii::Vector<double>> solve_with_base(
      const std::vector<dealii::AffineConstraints<double>>& constraints);
  bool solve_low_rank(const ActiveSetSystems& systems,
                      std::vector<dealii::Vector<double>>& displacements);

  const ElasticSystem& system_;
  const ContactConstraints& constraints_;
  dealii::TimerOutput& timer_;
  dealii::ConditionalOStream& log_;
  // K as a serial matrix, its pattern kept across runs while the dof layout (the dof indices of
  // every cell, fingerprinted by ElasticSystem::dof_layout_key) stays the same; and a plain CSR copy of it.
  dealii::SparsityPattern pattern_;
  dealii::SparseMatrix<double> stiffness_;
  std::size_t pattern_key_ = 0;
  CsrMatrix stiffness_csr_;
  bool stiffness_assembled_ = false;  // in this run
  ReducedSystem base_;                // the factorised system of this run
  std::vector<bool> base_active_;     // the active set base_ was built for
};

}  // namespace hipfai::fem
