#include "fem/contact_output.h"

#include <deal.II/numerics/data_out.h>

namespace hipfai::fem {

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
  dealii::Vector<double> contact(dof_handler.n_dofs());
  for (std::size_t n = 0; n < nodes.size() && n < fields.pressure_mpa.size(); ++n) {
    contact[nodes[n].dofs[0]] = fields.pressure_mpa[n];
    contact[nodes[n].dofs[1]] = fields.gap_mm[n];
    contact[nodes[n].dofs[2]] = fields.active[n] ? 1.0 : 0.0;
  }
  const std::vector<std::string> contact_names{"contact_pressure_mpa", "contact_gap_mm",
                                               "contact_active"};
  const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> scalars(
      3, dealii::DataComponentInterpretation::component_is_scalar);
  data_out.add_data_vector(contact, contact_names, dealii::DataOut<3>::type_dof_data, scalars);
  data_out.build_patches(system.mapping(), system.fe().degree);
  data_out.write_vtu_in_parallel(file, system.communicator());
}

}  // namespace hipfai::fem
