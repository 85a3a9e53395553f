// hipfai — the two PETSc solvers behind the contact problem's linear solvers.
//
// CgAmgSolver: CG with PETSc's smoothed-aggregation AMG (GAMG) given the six rigid-body modes as
// its near null space: the elasticity-aware multigrid that plain scalar BoomerAMG is not (the
// latter coarsens the displacement components independently and needs many more CG iterations
// on thin or nearly incompressible layers). Falls back to BoomerAMG when the dofs are not
// numbered node by node (x, y, z of one support point consecutive), which the rigid modes need.
//
// CholeskySolve: MUMPS Cholesky of a symmetric positive definite matrix behind a KSP:
// factorised once, then every right-hand side is two triangular solves.
#pragma once

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/point.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include <petscksp.h>

#include <mpi.h>

#include <vector>

namespace hipfai::fem {

class CgAmgSolver {
 public:
  // Sets up the preconditioner of `matrix` (kept by reference); support_points of every dof.
  CgAmgSolver(const dealii::PETScWrappers::MPI::SparseMatrix& matrix,
              const std::vector<dealii::Point<3>>& support_points, const dealii::IndexSet& owned,
              MPI_Comm comm);
  ~CgAmgSolver();
  CgAmgSolver(const CgAmgSolver&) = delete;
  CgAmgSolver& operator=(const CgAmgSolver&) = delete;

  // Iterations, negated (minus one) when CG did not reach the tolerance.
  int solve(const dealii::PETScWrappers::MPI::Vector& rhs, dealii::PETScWrappers::MPI::Vector& x,
            double relative_tolerance, unsigned int max_iterations);

 private:
  KSP ksp_ = nullptr;
};

class CholeskySolve {
 public:
  CholeskySolve(MPI_Comm comm, Mat matrix);
  ~CholeskySolve();
  CholeskySolve(const CholeskySolve&) = delete;
  CholeskySolve& operator=(const CholeskySolve&) = delete;

  bool factorised() const { return factorised_; }
  void factorise();
  // False, with PETSc's reasons on `log`, when the factorisation or the solve failed.
  bool solve(Vec rhs, Vec x, dealii::ConditionalOStream& log);
  // k right-hand sides at once (one rank): rhs and x are n x k, column-major. MUMPS runs the
  // forward and backward substitutions on the block, which costs little more than one column:
  // the factor is read once instead of k times. A right-hand side block with at most 1 % nonzeros
  // is handed over sparse (MUMPS then prunes the forward substitution). False, with the reason
  // on `log`, when the factorisation or the solve failed.
  bool solve_block(PetscInt n, PetscInt k, double* rhs, double* x, dealii::ConditionalOStream& log);
  // MUMPS's blocking of many right-hand sides in one solve (ICNTL(27); its default, 32, is set
  // for a few): after factorise().
  void set_right_hand_side_blocking(PetscInt k);

 private:
  KSP ksp_ = nullptr;
  PC pc_ = nullptr;
  bool factorised_ = false;
};

}  // namespace hipfai::fem
