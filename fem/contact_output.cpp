#include "fem/contact_output.h"

#include "core/error.h"

#include <deal.II/numerics/data_out.h>

#include <algorithm>

namespace hipfai::fem {

dealii::Vector<double> contact_dof_fields(std::size_t n_dofs, const std::vector<SlaveNode>& nodes,
                                          const ContactFields& fields) {
  dealii::Vector<double> contact(n_dofs);
  const bool solved = !fields.pressure_mpa.empty() || !fields.gap_mm.empty() || !fields.active.empty();
  if (!solved) return contact;  // no solve yet: no contact values
  if (fields.pressure_mpa.size() != nodes.size() || fields.gap_mm.size() != nodes.size() ||
      fields.active.size() != nodes.size()) {
    throw_error("fem output: contact fields for ", fields.pressure_mpa.size(), " / ", fields.gap_mm.size(), " / ",
                fields.active.size(), " nodes (pressure / gap / active), the solve has ", nodes.size());
  }
  std::vector<bool> seen(n_dofs, false);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const auto& dofs = nodes[n].dofs;
    for (const auto dof : dofs) {
      if (dof >= n_dofs) throw_error("fem output: contact node ", n, " has dof ", dof, " of ", n_dofs);
    }
    if (!seen[dofs[0]]) {
      seen[dofs[0]] = true;
      contact[dofs[1]] = fields.gap_mm[n];
    } else {
      contact[dofs[1]] = std::min(contact[dofs[1]], fields.gap_mm[n]);
    }
    contact[dofs[0]] += fields.pressure_mpa[n];
    if (fields.active[n]) contact[dofs[2]] = 1.0;
  }
  return contact;
}

void write_contact_vtu(const std::string& file, const ElasticSystem& system,
                       const dealii::Vector<double>& displacement,
                       const dealii::Vector<float>& cell_von_mises,
                       const std::vector<SlaveNode>& nodes, const ContactFields& fields) {
  const dealii::DoFHandler<3>& dof_handler = system.dof_handler();
  const auto& triangulation = system.triangulation();
  dealii::DataOut<3> data_out;
  data_out.attach_dof_handler(dof_handler);
  const std::vector<std::string> names(3, "displacement_mm");
  const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation>
      interpretation(3, dealii::DataComponentInterpretation::component_is_part_of_vector);
  data_out.add_data_vector(displacement, names, dealii::DataOut<3>::type_dof_data, interpretation);
  dealii::Vector<float> material(triangulation.n_active_cells());
  for (const auto& cell : triangulation.active_cell_iterators()) {
    material[cell->active_cell_index()] = static_cast<float>(cell->material_id());
  }
  data_out.add_data_vector(material, "material_id");
  if (cell_von_mises.size() == triangulation.n_active_cells()) {
    data_out.add_data_vector(cell_von_mises, "von_mises_cell_max_mpa");
  }
  // Contact quantities live on the slave nodes: carried as the three scalar components of one
  // nodal vector (x: pressure, y: gap, z: active), zero away from the contact surfaces.
  const dealii::Vector<double> contact = contact_dof_fields(dof_handler.n_dofs(), nodes, fields);
  const std::vector<std::string> contact_names{"contact_pressure_mpa", "contact_gap_mm",
                                               "contact_active"};
  const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> scalars(
      3, dealii::DataComponentInterpretation::component_is_scalar);
  data_out.add_data_vector(contact, contact_names, dealii::DataOut<3>::type_dof_data, scalars);
  data_out.build_patches(system.mapping(), system.fe().degree);
  data_out.write_vtu_in_parallel(file, system.communicator());
}

}  // namespace hipfai::fem
