#include "fem/distributed_direct_solver.h"

#include "core/error.h"
#include "fem/petsc_solvers.h"

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/sparsity_tools.h>

#include <petscmat.h>

#include <limits>
#include <optional>

namespace hipfai::fem {

using dealii::types::global_dof_index;

DistributedDirectSolver::DistributedDirectSolver(const ElasticSystem& system,
                                                 dealii::TimerOutput& timer,
                                                 dealii::ConditionalOStream& log)
    : system_(system), timer_(timer), log_(log) {}

void DistributedDirectSolver::begin_run(const LinearSolverSettings& settings) {
  ContactLinearSolver::begin_run(settings);
  stiffness_assembled_ = false;
}

void DistributedDirectSolver::assemble_stiffness() {
  const MPI_Comm comm = system_.communicator();
  const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);
  const dealii::DoFHandler<3>& dof_handler = system_.dof_handler();
  dealii::DynamicSparsityPattern pattern(system_.all_dofs());
  dealii::DoFTools::make_sparsity_pattern(dof_handler, pattern, dealii::AffineConstraints<double>(),
                                          true, rank);
  dealii::SparsityTools::distribute_sparsity_pattern(pattern, system_.owned_dofs(), comm,
                                                     system_.all_dofs());
  stiffness_.reinit(system_.owned_dofs(), system_.owned_dofs(), pattern, comm);
  std::vector<global_dof_index> dofs(system_.fe().n_dofs_per_cell());
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    cell->get_dof_indices(dofs);
    stiffness_.add(dofs, system_.cell_matrix(cell->active_cell_index()));
  }
  stiffness_.compress(dealii::VectorOperation::add);
  stiffness_assembled_ = true;
}

std::vector<dealii::Vector<double>> DistributedDirectSolver::solve(
    const ActiveSetSystems& systems) {
  const MPI_Comm comm = system_.communicator();
  const dealii::IndexSet& owned_dofs = system_.owned_dofs();
  dealii::TimerOutput::Scope assembly_scope(timer_, "assembly");
  if (!stiffness_assembled_) assemble_stiffness();
  const dealii::AffineConstraints<double>& c0 = systems.constraints.front();
  const global_dof_index n_dofs = system_.dof_handler().n_dofs();
  // Reduced index of every free dof (every rank knows all constraints: the same numbering).
  constexpr global_dof_index kConstrained = std::numeric_limits<global_dof_index>::max();
  std::vector<global_dof_index> reduced(n_dofs, kConstrained);
  global_dof_index n_free = 0;
  for (global_dof_index i = 0; i < n_dofs; ++i) {
    if (!c0.is_constrained(i)) reduced[i] = n_free++;
  }
  // Owned rows of P are the owned dofs; owned columns the free ones among them (the owned range
  // is contiguous and ordered by rank, so the reduced owned range is too).
  if (!owned_dofs.is_contiguous()) {
    // The shared triangulation numbers each rank's dofs contiguously; the reduced numbering
    // below relies on it.
    throw_error("fem: direct solver needs contiguous locally owned dofs on every rank");
  }
  const global_dof_index first = owned_dofs.is_empty() ? 0 : owned_dofs.nth_index_in_set(0);
  const global_dof_index n_owned = owned_dofs.n_elements();
  global_dof_index first_free = kConstrained, n_owned_free = 0;
  for (global_dof_index i = first; i < first + n_owned; ++i) {
    if (reduced[i] == kConstrained) continue;
    if (first_free == kConstrained) first_free = reduced[i];
    ++n_owned_free;
  }
  if (first_free == kConstrained) first_free = 0;
  std::vector<PetscInt> diagonal_count(n_owned, 0), off_diagonal_count(n_owned, 0);
  auto is_owned_column = [&](global_dof_index column) {
    return column >= first_free && column < first_free + n_owned_free;
  };
  for (global_dof_index r = 0; r < n_owned; ++r) {
    const global_dof_index i = first + r;
    if (reduced[i] != kConstrained) {
      ++diagonal_count[r];
      continue;
    }
    if (const auto* entries = c0.get_constraint_entries(i)) {
      for (const auto& [j, weight] : *entries) {
        if (weight == 0.0) continue;
        (is_owned_column(reduced[j]) ? diagonal_count[r] : off_diagonal_count[r])++;
      }
    }
  }
  Mat prolongation;
  // MPIAIJ on one rank too: deal.II's K is MPIAIJ, and PtAP needs matching types.
  MatCreate(comm, &prolongation);
  MatSetSizes(prolongation, static_cast<PetscInt>(n_owned), static_cast<PetscInt>(n_owned_free),
              static_cast<PetscInt>(n_dofs), static_cast<PetscInt>(n_free));
  MatSetType(prolongation, MATMPIAIJ);
  MatMPIAIJSetPreallocation(prolongation, 0, diagonal_count.data(), 0, off_diagonal_count.data());
  for (global_dof_index r = 0; r < n_owned; ++r) {
    const global_dof_index i = first + r;
    const PetscInt row = static_cast<PetscInt>(i);
    if (reduced[i] != kConstrained) {
      MatSetValue(prolongation, row, static_cast<PetscInt>(reduced[i]), 1.0, ADD_VALUES);
      continue;
    }
    if (const auto* entries = c0.get_constraint_entries(i)) {
      for (const auto& [j, weight] : *entries) {
        if (weight == 0.0) continue;
        MatSetValue(prolongation, row, static_cast<PetscInt>(reduced[j]), weight, ADD_VALUES);
      }
    }
  }
  MatAssemblyBegin(prolongation, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(prolongation, MAT_FINAL_ASSEMBLY);
  Mat reduced_matrix;
  MatPtAP(stiffness_.petsc_matrix(), prolongation, MAT_INITIAL_MATRIX, 2.0, &reduced_matrix);
  MatSetOption(reduced_matrix, MAT_SPD, PETSC_TRUE);
  assembly_scope.stop();

  std::optional<CholeskySolve> cholesky(std::in_place, comm, reduced_matrix);
  std::vector<dealii::Vector<double>> displacements;
  for (const dealii::AffineConstraints<double>& constraint : systems.constraints) {
    // g: the inhomogeneities on the constrained rows.
    dealii::PETScWrappers::MPI::Vector g(owned_dofs, comm), kg(owned_dofs, comm),
        u(owned_dofs, comm);
    for (global_dof_index i = first; i < first + n_owned; ++i) {
      if (reduced[i] == kConstrained && constraint.is_inhomogeneously_constrained(i)) {
        g(i) = constraint.get_inhomogeneity(i);
      }
    }
    g.compress(dealii::VectorOperation::insert);
    stiffness_.vmult(kg, g);
    kg *= -1.0;
    Vec rhs, v;
    MatCreateVecs(reduced_matrix, &v, &rhs);
    MatMultTranspose(prolongation, kg, rhs);
    PetscReal rhs_norm = 0.0;
    VecNorm(rhs, NORM_2, &rhs_norm);
    ++statistics_.linear_solves;
    if (rhs_norm > 0.0) {
      if (!cholesky->factorised()) {
        dealii::TimerOutput::Scope scope(timer_, "solver setup");
        cholesky->factorise();
        ++statistics_.factorisations;
      }
      dealii::TimerOutput::Scope scope(timer_, "linear solves");
      if (!cholesky->solve(rhs, v, log_)) statistics_.failed = true;
      ++statistics_.linear_iterations;
    } else {
      VecSet(v, 0.0);
    }
    MatMult(prolongation, v, u);  // u = P v
    u += g;
    VecDestroy(&rhs);
    VecDestroy(&v);
    dealii::Vector<double> displacement(u);
    constraint.distribute(displacement);
    displacements.push_back(std::move(displacement));
  }
  cholesky.reset();
  MatDestroy(&reduced_matrix);
  MatDestroy(&prolongation);
  return displacements;
}

}  // namespace hipfai::fem
