#include "fem/contact_constraints.h"

#include <deal.II/dofs/dof_tools.h>

namespace hipfai::fem {

using dealii::types::global_dof_index;

namespace {

// Calls visit(cell dofs, local index) for every dof with support on a boundary face with `id`.
template <class Visit>
void for_each_boundary_dof(const ElasticSystem& system, dealii::types::boundary_id id,
                           const Visit& visit) {
  std::vector<global_dof_index> dofs(system.fe().n_dofs_per_cell());
  for (const auto& cell : system.dof_handler().active_cell_iterators()) {
    cell->get_dof_indices(dofs);
    for (const unsigned int face_no : cell->face_indices()) {
      const auto face = cell->face(face_no);
      if (!face->at_boundary() || face->boundary_id() != id) continue;
      for (unsigned int i = 0; i < dofs.size(); ++i) {
        if (system.support_on_face(face_no, i)) visit(dofs[i], i);
      }
    }
  }
}

}  // namespace

void ContactConstraints::collect_fixed_dofs(const ElasticSystem& system,
                                            const ContactModel& model) {
  const dealii::DoFHandler<3>& dof_handler = system.dof_handler();
  all_dofs_ = system.all_dofs();
  fixed_dof_.assign(dof_handler.n_dofs(), false);
  bonded_dofs_.clear();
  symmetry_dofs_.clear();
  hanging_constraints_.clear();
  hanging_constraints_.reinit(all_dofs_);
  dealii::DoFTools::make_hanging_node_constraints(dof_handler, hanging_constraints_);
  hanging_constraints_.close();
  for (global_dof_index i = 0; i < dof_handler.n_dofs(); ++i) {
    if (hanging_constraints_.is_constrained(i)) fixed_dof_[i] = true;
  }
  for (const BondedBoundary& bonded : model.bonded_boundaries) {
    for_each_boundary_dof(system, bonded.boundary_id, [&](global_dof_index dof, unsigned int i) {
      if (fixed_dof_[dof]) return;
      const unsigned int component = system.component_of(i);
      double extra = 0.0;
      if (bonded.extra_displacement_mm)
        extra = bonded.extra_displacement_mm(system.support_points()[dof])[component];
      bonded_dofs_.push_back({dof, component, bonded.rigid_body, extra});
      fixed_dof_[dof] = true;
    });
  }
  for (const SymmetryBoundary& symmetry : model.symmetry_boundaries) {
    for_each_boundary_dof(system, symmetry.boundary_id, [&](global_dof_index dof, unsigned int i) {
      if (fixed_dof_[dof] || system.component_of(i) != symmetry.axis) return;
      symmetry_dofs_.push_back(dof);
      fixed_dof_[dof] = true;
    });
  }
}

dealii::AffineConstraints<double> ContactConstraints::make(
    const std::vector<dealii::Tensor<1, 3>>& translations, const std::vector<SlaveNode>& nodes,
    const std::vector<bool>& active) const {
  dealii::AffineConstraints<double> constraints(all_dofs_);
  constraints.merge(hanging_constraints_);
  for (const BondedDof& bonded : bonded_dofs_) {
    double value = bonded.extra;
    if (bonded.rigid_body >= 0) value += translations[bonded.rigid_body][bonded.component];
    constraints.add_line(bonded.dof);
    constraints.set_inhomogeneity(bonded.dof, value);
  }
  for (const global_dof_index dof : symmetry_dofs_) {
    constraints.add_line(dof);
    constraints.set_inhomogeneity(dof, 0.0);
  }
  // Active node: u_s . n = u_m . n - g0, solved for the slave component k.
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (!active[n]) continue;
    const SlaveNode& node = nodes[n];
    const unsigned int k = node.constrained_component;
    const double n_k = node.normal[k];
    const global_dof_index slave = node.dofs[k];
    constraints.add_line(slave);
    for (unsigned int c = 0; c < 3; ++c) {
      if (c != k && node.normal[c] != 0.0)
        constraints.add_entry(slave, node.dofs[c], -node.normal[c] / n_k);
    }
    double inhomogeneity = -node.initial_gap;
    if (node.rigid_body >= 0) {
      inhomogeneity += translations[node.rigid_body] * node.normal;
    } else {
      for (unsigned int c = 0; c < 3; ++c) {
        for (const auto& [dof, weight] : node.master[c])
          constraints.add_entry(slave, dof, weight * node.normal[c] / n_k);
      }
    }
    constraints.set_inhomogeneity(slave, inhomogeneity / n_k);
  }
  constraints.close();
  return constraints;
}

}  // namespace hipfai::fem
