#include "fem/serial_direct_solver.h"

#include "fem/thread_chunks.h"

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>

#include <cmath>

namespace hipfai::fem {

using dealii::types::global_dof_index;

SerialDirectSolver::SerialDirectSolver(const ElasticSystem& system,
                                       const ContactConstraints& constraints,
                                       dealii::TimerOutput& timer, dealii::ConditionalOStream& log)
    : system_(system), constraints_(constraints), timer_(timer), log_(log) {}

void SerialDirectSolver::begin_run(const LinearSolverSettings& settings) {
  ContactLinearSolver::begin_run(settings);
  stiffness_assembled_ = false;
  base_.reset();
}

void SerialDirectSolver::end_run() { base_.reset(); }  // K changes with the next run's pose

void SerialDirectSolver::assemble_stiffness() {
  const dealii::DoFHandler<3>& dof_handler = system_.dof_handler();
  const global_dof_index n_dofs = dof_handler.n_dofs();
  const std::size_t key = system_.dof_layout_key();
  if (key != pattern_key_ || pattern_.n_rows() != n_dofs) {
    stiffness_.clear();
    dealii::DynamicSparsityPattern pattern(n_dofs);
    dealii::DoFTools::make_sparsity_pattern(dof_handler, pattern);
    pattern_.copy_from(pattern);
    stiffness_.reinit(pattern_);
    pattern_key_ = key;
  }
  stiffness_ = 0;
  std::vector<global_dof_index> dofs(system_.fe().n_dofs_per_cell());
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    cell->get_dof_indices(dofs);
    stiffness_.add(dofs, system_.cell_matrix(cell->active_cell_index()));
  }
  // A plain CSR copy for the row-by-row reduction (no iterator layers in its loops).
  CsrMatrix& csr = stiffness_csr_;
  csr.row_start.assign(n_dofs + 1, 0);
  csr.columns.clear();
  csr.values.clear();
  csr.columns.reserve(stiffness_.n_nonzero_elements());
  csr.values.reserve(stiffness_.n_nonzero_elements());
  for (global_dof_index i = 0; i < n_dofs; ++i) {
    for (auto entry = stiffness_.begin(i); entry != stiffness_.end(i); ++entry) {
      csr.columns.push_back(entry->column());
      csr.values.push_back(entry->value());
    }
    csr.row_start[i + 1] = csr.columns.size();
  }
  stiffness_assembled_ = true;
}

std::vector<dealii::Vector<double>> SerialDirectSolver::solve(const ActiveSetSystems& systems) {
  if (!stiffness_assembled_) {
    dealii::TimerOutput::Scope scope(timer_, "assembly");
    assemble_stiffness();
  }
  if (settings_.low_rank_updates && base_.valid()) {
    std::vector<dealii::Vector<double>> displacements;
    if (solve_low_rank(systems, displacements)) return displacements;
  }
  {
    dealii::TimerOutput::Scope scope(timer_, "assembly");
    base_.build(stiffness_csr_, systems.constraints.front(),
                threads_per_rank(system_.communicator()));
    base_active_ = systems.active;
  }
  return solve_with_base(systems.constraints);
}

std::vector<dealii::Vector<double>> SerialDirectSolver::solve_with_base(
    const std::vector<dealii::AffineConstraints<double>>& constraints) {
  const global_dof_index n_dofs = system_.dof_handler().n_dofs();
  const std::size_t n_free = base_.n_free();
  dealii::Vector<double> g(n_dofs), kg(n_dofs);
  std::vector<std::vector<double>> rhs(constraints.size(), std::vector<double>(n_free)), v;
  for (std::size_t k = 0; k < constraints.size(); ++k)
    base_.right_hand_side(constraints[k], stiffness_, g, kg, rhs[k]);
  statistics_.linear_solves += static_cast<unsigned int>(constraints.size());
  if (!base_.solve(rhs, v, statistics_, timer_, log_)) statistics_.failed = true;
  std::vector<dealii::Vector<double>> displacements;
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    // u = P v + g: the free dofs from v, the constrained ones from their constraints.
    dealii::Vector<double> displacement(n_dofs);
    for (std::size_t r = 0; r < n_free; ++r) displacement(base_.free_dofs()[r]) = v[k][r];
    constraints[k].distribute(displacement);
    displacements.push_back(std::move(displacement));
  }
  return displacements;
}

bool SerialDirectSolver::solve_low_rank(const ActiveSetSystems& systems,
                                        std::vector<dealii::Vector<double>>& displacements) {
  // See the header for the bordered system solved here.
  constexpr std::size_t kMaxChanges = 32;  // ~ the solves one factorisation costs at default
  const std::vector<bool>& active = systems.active;
  const std::vector<SlaveNode>& nodes = systems.nodes;
  const std::vector<dealii::AffineConstraints<double>>& constraints = systems.constraints;
  if (base_active_.size() != active.size() || constraints_.has_hanging_nodes()) return false;
  std::vector<std::size_t> released, added;
  for (std::size_t n = 0; n < active.size(); ++n) {
    if (base_active_[n] && !active[n]) released.push_back(n);
    if (!base_active_[n] && active[n]) added.push_back(n);
  }
  const std::size_t n_released = released.size(), m = released.size() + added.size();
  if (m > kMaxChanges) return false;
  const global_dof_index n_dofs = system_.dof_handler().n_dofs();
  std::vector<char> is_released(n_dofs, 0);
  std::vector<global_dof_index> slave(m);
  for (std::size_t i = 0; i < m; ++i) {
    const SlaveNode& node = nodes[i < n_released ? released[i] : added[i - n_released]];
    slave[i] = node.dofs[node.constrained_component];
    if (i < n_released) is_released[slave[i]] = 1;
  }
  for (std::size_t n = 0; n < active.size(); ++n) {
    if (!base_active_[n] || !active[n]) continue;
    const SlaveNode& node = nodes[n];
    for (unsigned int c = 0; c < 3; ++c) {
      if (c != node.constrained_component && is_released[node.dofs[c]]) return false;
      for (const auto& entry : node.master[c]) {
        if (is_released[entry.first]) return false;
      }
    }
  }
  // The base's constraints with the current translations.
  std::vector<dealii::AffineConstraints<double>> base_constraints;
  for (const auto& translations : systems.translation_sets) {
    base_constraints.push_back(constraints_.make(translations, nodes, base_active_));
  }
  const std::size_t n_free = base_.n_free();
  std::vector<std::vector<double>> border(m, std::vector<double>(n_free, 0.0));
  dealii::FullMatrix<double> schur(m, m);
  const CsrMatrix& k_csr = stiffness_csr_;
  for (std::size_t i = 0; i < n_released; ++i) {
    for (std::size_t e = k_csr.row_start[slave[i]]; e < k_csr.row_start[slave[i] + 1]; ++e) {
      base_.add_transposed_row(k_csr.columns[e], k_csr.values[e],
                               border[i]);  // K is symmetric: row = column
    }
    for (std::size_t j = 0; j < n_released; ++j) schur(i, j) = stiffness_.el(slave[i], slave[j]);
  }
  // Added constraints as rows c_n = e_s - sum_c a_c e_c (their closed lines: the same for every
  // translation set, only the inhomogeneities differ).
  const dealii::AffineConstraints<double>& c0 = constraints.front();
  std::vector<std::vector<std::pair<global_dof_index, double>>> rows(added.size());
  for (std::size_t a = 0; a < added.size(); ++a) {
    const global_dof_index s = slave[n_released + a];
    if (!c0.is_constrained(s)) return false;
    rows[a].emplace_back(s, 1.0);
    if (const auto* entries = c0.get_constraint_entries(s)) {
      for (const auto& [dof, weight] : *entries) rows[a].emplace_back(dof, -weight);
    }
    for (const auto& [dof, value] : rows[a]) {
      base_.add_transposed_row(dof, value, border[n_released + a]);
      for (std::size_t i = 0; i < n_released; ++i) {
        if (dof != slave[i]) continue;
        schur(i, n_released + a) += value;
        schur(n_released + a, i) += value;
      }
    }
  }
  // Every solve with the base's factor in one block: the m border columns (Z = A^-1 B) and the
  // right-hand sides of the translation sets.
  const std::size_t n_sets = constraints.size();
  dealii::Vector<double> g(n_dofs), kg(n_dofs);
  std::vector<std::vector<double>> block(border);
  std::vector<dealii::Vector<double>> d_sets(n_sets, dealii::Vector<double>(m));
  for (std::size_t k = 0; k < n_sets; ++k) {
    std::vector<double> rhs_values(n_free);
    base_.right_hand_side(base_constraints[k], stiffness_, g, kg, rhs_values);
    block.push_back(std::move(rhs_values));
    for (std::size_t i = 0; i < n_released; ++i) d_sets[k][i] = -kg(slave[i]);
    for (std::size_t a = 0; a < added.size(); ++a) {
      double row_g = 0.0;
      for (const auto& [dof, value] : rows[a]) row_g += value * g(dof);
      d_sets[k][n_released + a] = constraints[k].get_inhomogeneity(slave[n_released + a]) - row_g;
    }
  }
  std::vector<std::vector<double>> solved;
  statistics_.linear_solves += static_cast<unsigned int>(block.size());
  if (!base_.solve(block, solved, statistics_, timer_, log_)) return false;
  block.clear();
  dealii::TimerOutput::Scope scope(timer_, "linear solves");
  const std::vector<std::vector<double>>& z = solved;  // z[i] = A^-1 border[i], i < m
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = 0; j < m; ++j) {
      double product = 0.0;
      for (std::size_t r = 0; r < n_free; ++r) product += border[i][r] * z[j][r];
      schur(i, j) -= product;
    }
  }
  if (m > 0) schur.gauss_jordan();
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = 0; j < m; ++j) {
      if (!std::isfinite(schur(i, j))) return false;
    }
  }
  dealii::Vector<double> y(m);
  std::vector<dealii::Vector<double>> result;
  for (std::size_t k = 0; k < n_sets; ++k) {
    std::vector<double>& v_values = solved[m + k];
    dealii::Vector<double>& d = d_sets[k];
    for (std::size_t i = 0; i < m; ++i) {
      for (std::size_t r = 0; r < n_free; ++r) d[i] -= border[i][r] * v_values[r];
    }
    schur.vmult(y, d);
    for (std::size_t i = 0; i < m; ++i) {
      for (std::size_t r = 0; r < n_free; ++r) v_values[r] -= z[i][r] * y[i];
    }
    dealii::Vector<double> displacement(n_dofs);
    for (std::size_t r = 0; r < n_free; ++r) displacement(base_.free_dofs()[r]) = v_values[r];
    base_constraints[k].distribute(displacement);
    for (std::size_t i = 0; i < n_released; ++i) displacement(slave[i]) += y[i];
    // The added constraints hold to round-off unless S was (nearly) singular.
    const double scale = displacement.linfty_norm();
    for (std::size_t a = 0; a < added.size(); ++a) {
      double residual = -constraints[k].get_inhomogeneity(slave[n_released + a]);
      for (const auto& [dof, value] : rows[a]) residual += value * displacement(dof);
      if (!(std::abs(residual) <= 1e-9 * scale + 1e-300)) return false;
    }
    result.push_back(std::move(displacement));
  }
  ++statistics_.low_rank_updates;
  displacements = std::move(result);
  return true;
}

}  // namespace hipfai::fem
