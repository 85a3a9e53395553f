#include "fem/cg_amg_linear_solver.h"

#include "fem/petsc_solvers.h"

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/sparsity_tools.h>

#include <cstdlib>
#include <memory>

namespace hipfai::fem {

using dealii::types::global_dof_index;

CgAmgLinearSolver::CgAmgLinearSolver(const ElasticSystem& system, dealii::TimerOutput& timer)
    : system_(system), timer_(timer) {}

std::vector<dealii::Vector<double>> CgAmgLinearSolver::solve(const ActiveSetSystems& systems) {
  const std::vector<dealii::AffineConstraints<double>>& constraints = systems.constraints;
  const MPI_Comm comm = system_.communicator();
  const dealii::IndexSet& owned_dofs = system_.owned_dofs();
  const dealii::DoFHandler<3>& dof_handler = system_.dof_handler();
  dealii::PETScWrappers::MPI::SparseMatrix matrix;
  std::vector<dealii::PETScWrappers::MPI::Vector> rhs(constraints.size());
  {
    dealii::TimerOutput::Scope scope(timer_, "assembly");
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);
    dealii::DynamicSparsityPattern pattern(system_.all_dofs());
    dealii::DoFTools::make_sparsity_pattern(dof_handler, pattern, constraints[0], false, rank);
    dealii::SparsityTools::distribute_sparsity_pattern(pattern, owned_dofs, comm,
                                                       system_.all_dofs());
    matrix.reinit(owned_dofs, owned_dofs, pattern, comm);
    for (auto& vector : rhs) vector.reinit(owned_dofs, comm);
    const unsigned int n = system_.fe().n_dofs_per_cell();
    dealii::Vector<double> cell_rhs(n);  // no body forces: loads enter through the constraints
    std::vector<global_dof_index> dofs(n);
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      if (!cell->is_locally_owned()) continue;
      const dealii::FullMatrix<double>& cell_matrix =
          system_.cell_matrix(cell->active_cell_index());
      cell->get_dof_indices(dofs);
      constraints[0].distribute_local_to_global(cell_matrix, cell_rhs, dofs, matrix, rhs[0]);
      for (std::size_t k = 1; k < constraints.size(); ++k) {
        constraints[k].distribute_local_to_global(cell_rhs, dofs, rhs[k], cell_matrix);
      }
    }
    matrix.compress(dealii::VectorOperation::add);
    for (auto& vector : rhs) vector.compress(dealii::VectorOperation::add);
  }

  std::vector<dealii::Vector<double>> displacements;
  std::unique_ptr<CgAmgSolver> solver;
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    dealii::PETScWrappers::MPI::Vector x(owned_dofs, comm);
    const double rhs_norm = rhs[k].l2_norm();
    ++statistics_.linear_solves;
    if (rhs_norm > 0.0) {
      if (!solver) {
        dealii::TimerOutput::Scope scope(timer_, "solver setup");
        solver = std::make_unique<CgAmgSolver>(matrix, system_.support_points(), owned_dofs, comm);
      }
      dealii::TimerOutput::Scope scope(timer_, "linear solves");
      const int iterations =
          solver->solve(rhs[k], x, settings_.relative_tolerance, settings_.max_iterations);
      if (iterations < 0) statistics_.failed = true;
      statistics_.linear_iterations += static_cast<unsigned int>(std::abs(iterations));
    }
    dealii::Vector<double> displacement(x);
    constraints[k].distribute(displacement);
    displacements.push_back(std::move(displacement));
  }
  return displacements;
}

}  // namespace hipfai::fem
