// hipfai — the reduced system P^T K P of one set of constraints on one rank, with its MUMPS
// Cholesky factor.
//
// With the closed constraints u = P v + g (v: the unconstrained dofs, P: identity on them and the
// constraint weights on the constrained rows, g: the inhomogeneities), reduced row j is K's row
// j, plus the rows of the constrained dofs whose constraint names j (scaled by its weight), with
// every column mapped through P: a free column to its reduced index, a constrained one to the
// columns its constraint names, a Dirichlet one dropped. Built row by row from a CSR copy of K
// (PETSc's general triple product spent ~3 s per active set on the 54 k dof hip, 10x the rest of
// the reduction); only the upper triangle is kept (the Cholesky factorisation reads no more).
#pragma once

#include "fem/linear_solver.h"
#include "fem/petsc_solvers.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/types.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <petscmat.h>

#include <memory>
#include <utility>
#include <vector>

namespace hipfai::fem {

// A square sparse matrix in compressed rows (each row: the diagonal first, then ascending columns,
// as deal.II's SparseMatrix stores them).
struct CsrMatrix {
  std::vector<std::size_t> row_start;                    // n + 1 offsets into columns and values
  std::vector<dealii::types::global_dof_index> columns;  // column of each entry
  std::vector<double> values;                            // value of each entry
};

class ReducedSystem {
 public:
  ReducedSystem() = default;
  ~ReducedSystem() { reset(); }
  ReducedSystem(const ReducedSystem&) = delete;
  ReducedSystem& operator=(const ReducedSystem&) = delete;

  // P^T K P for the closed constraints c; `n_threads` build the rows. Throws hipfai::Error for a
  // constraint that names a constrained dof (c not closed).
  void build(const CsrMatrix& k, const dealii::AffineConstraints<double>& c, std::size_t n_threads);
  // Frees the matrix and its factor; valid() is false until the next build.
  void reset();
  bool valid() const { return valid_; }

  std::size_t n_free() const { return free_dofs_.size(); }
  // The unconstrained dofs, in reduced order.
  const std::vector<dealii::types::global_dof_index>& free_dofs() const { return free_dofs_; }
  // P^T (-K g) for g the inhomogeneities of `constraint` on the rows P constrains; g and kg = K g
  // are returned too.
  void right_hand_side(const dealii::AffineConstraints<double>& constraint,
                       const dealii::SparseMatrix<double>& k, dealii::Vector<double>& g,
                       dealii::Vector<double>& kg, std::vector<double>& rhs) const;
  // y += value * (row `dof` of P), i.e. P^T applied to value * e_dof.
  void add_transposed_row(dealii::types::global_dof_index dof, double value,
                          std::vector<double>& y) const;
  // Solves every right-hand side with the factor (factorised on first use), the nonzero ones in
  // one block; x[i] answers rhs[i]. False when the factorisation or a solve failed.
  bool solve(const std::vector<std::vector<double>>& rhs, std::vector<std::vector<double>>& x,
             LinearSolverStatistics& statistics, dealii::TimerOutput& timer,
             dealii::ConditionalOStream& log);

 private:
  static constexpr PetscInt kDirichlet = -1, kExpanded = -2;
  // One term of a constraint's expansion: a reduced column and its weight.
  struct Term {
    PetscInt column;  // reduced index of a free dof the constraint names
    double weight;    // its weight in the constraint
  };
  void map_columns(const dealii::AffineConstraints<double>& c,
                   dealii::types::global_dof_index n_dofs);
  void build_rows(const CsrMatrix& k, std::size_t n_threads);

  bool valid_ = false;
  // Column map through P: >= 0 a free dof's reduced index, kDirichlet a dof fixed to its
  // inhomogeneity, <= kExpanded - e the e-th constrained dof whose constraint names free dofs.
  std::vector<PetscInt> mapped_;
  std::vector<dealii::types::global_dof_index> free_dofs_;
  std::vector<std::size_t> expansion_begin_;  // per expanded dof, into expansion_
  std::vector<Term> expansion_;
  std::vector<PetscInt> expansion_last_;  // largest column of each expansion
  // Rows scattered into each reduced row: the constrained dofs whose constraint names it.
  std::vector<std::vector<std::pair<dealii::types::global_dof_index, double>>> incoming_;
  std::vector<PetscInt> row_start_, columns_;  // upper triangle of P^T K P (CSR), kept for matrix_
  std::vector<double> values_;
  Mat matrix_ = nullptr;
  std::unique_ptr<CholeskySolve> cholesky_;
};

}  // namespace hipfai::fem
