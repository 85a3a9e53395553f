// hipfai — the fields of a contact solve to one .vtu file (collective: every rank calls it).
//
// Displacement (mm, on the run's configuration), material id, von Mises (MPa, largest over each
// cell's Gauss points) and, at the contact slave nodes, contact pressure (MPa), gap (mm) and the
// active flag (0 elsewhere). Patches of the element degree on the mapping, so their vertices are
// the nodes and show exact values.
#pragma once

#include "fem/elastic_system.h"
#include "fem/mortar_coupling.h"

#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace hipfai::fem {

// The nodal contact fields of write_contact_vtu, per node of `nodes`.
struct ContactFields {
  std::vector<double> pressure_mpa;  // 0 where inactive
  std::vector<double> gap_mm;        // negative: penetration
  std::vector<bool> active;          // in the final active set
};

// The contact fields on the displacement dofs, as write_contact_vtu shows them: at a node's x,
// y and z dofs its pressure, gap and active flag (0 away from the contact nodes). A node that is
// the slave of several pairs (the hip model's articular nodes face both the femoral cartilage and
// the femur's bone where the cartilage is absent) shows the sum of its pairs' pressures (its whole
// normal force over its area, which each pair takes over the same slave surface), the smallest of
// their gaps and 1 where any pair holds it active.
// Empty `fields` (no solve yet): zeros. Throws hipfai::Error when `fields` does not have one
// value per node or a dof is not below n_dofs.
dealii::Vector<double> contact_dof_fields(std::size_t n_dofs, const std::vector<SlaveNode>& nodes,
                                          const ContactFields& fields);

// Writes `file`. cell_von_mises: per active cell (not written when its size does not match).
void write_contact_vtu(const std::string& file, const ElasticSystem& system,
                       const dealii::Vector<double>& displacement,
                       const dealii::Vector<float>& cell_von_mises,
                       const std::vector<SlaveNode>& nodes, const ContactFields& fields);

}  // namespace hipfai::fem
