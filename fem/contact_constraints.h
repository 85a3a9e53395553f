// hipfai — the constraints of the elastic system: hanging nodes, bonded interfaces, symmetry
// planes and the contact constraints of the active nodes, as one deal.II AffineConstraints.
//
// Bonded and symmetry dofs are found once per run (collect_fixed_dofs); the constraints are then
// rebuilt for every active set and rigid translation (make), since the translations enter the
// inhomogeneities of the bonded dofs and of the contact constraints against rigid masters.
//
// An active contact node carries the exact constraint g = 0, written as an affine constraint on
// its slave component k with the largest normal share (fem/mortar_coupling.h):
//   u_k = -sum_{c != k} (n_c / n_k) u_c + sum_c (n_c / n_k) sum_j w_cj u_j + (t . n - g0) / n_k
// (the master sum for a deformable master, t . n for a rigid one). Eliminating u_k keeps the
// condensed system symmetric positive definite.
#pragma once

#include "fem/contact_model.h"
#include "fem/elastic_system.h"
#include "fem/mortar_coupling.h"

#include <deal.II/base/index_set.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>
#include <deal.II/lac/affine_constraints.h>

#include <utility>
#include <vector>

namespace hipfai::fem {

// A dof on a bonded boundary: u[dof] = translation[rigid_body][component] + extra.
struct BondedDof {
  dealii::types::global_dof_index dof = 0;  // the constrained dof
  unsigned int component = 0;               // its displacement component
  int rigid_body = -1;                      // whose translation it follows (-1: none)
  double extra = 0.0;                       // extra_displacement_mm at its support point (mm)
};

class ContactConstraints {
 public:
  // Hanging-node constraints, then the bonded dofs (a dof on a bonded and a symmetry boundary
  // follows the bone), then the symmetry dofs of the model on the system's dofs.
  void collect_fixed_dofs(const ElasticSystem& system, const ContactModel& model);

  // Hanging, bonded or symmetry: never a contact slave dof.
  const std::vector<bool>& fixed_dofs() const { return fixed_dof_; }
  const std::vector<BondedDof>& bonded_dofs() const { return bonded_dofs_; }
  bool has_hanging_nodes() const { return hanging_constraints_.n_constraints() > 0; }

  // The closed constraints for rigid translations `translations` (one per rigid body) and the
  // contact constraints of the nodes with active[n].
  dealii::AffineConstraints<double> make(const std::vector<dealii::Tensor<1, 3>>& translations,
                                         const std::vector<SlaveNode>& nodes,
                                         const std::vector<bool>& active) const;

 private:
  dealii::IndexSet all_dofs_;
  std::vector<bool> fixed_dof_;
  std::vector<BondedDof> bonded_dofs_;
  std::vector<dealii::types::global_dof_index> symmetry_dofs_;  // held at 0
  dealii::AffineConstraints<double> hanging_constraints_;
};

}  // namespace hipfai::fem
