// hipfai — load control of rigid bodies: the translation that balances a prescribed force.
//
// A rigid body may have free translation directions with a prescribed force (the femur under the
// joint reaction force). For a fixed active set the displacement is affine in the translation,
// so the translation that balances the force is found exactly from 1 + (number of free
// directions) linear solves: the state at the current translations and one probe per direction
// moved by a unit step; the sensitivity matrix of the transmitted forces then gives the step.
#pragma once

#include "fem/contact_constraints.h"
#include "fem/contact_model.h"
#include "fem/elastic_system.h"
#include "fem/mortar_coupling.h"

#include <deal.II/base/tensor.h>

#include <vector>

namespace hipfai::fem {

// Force each rigid body applies to the deformable bodies in `state`: through its contact surface
// (the active nodes against it) and through its bonded interfaces (the reactions at the bonded
// dofs).
std::vector<dealii::Tensor<1, 3>> transmitted_force(std::size_t n_rigid_bodies,
                                                    const std::vector<BondedDof>& bonded_dofs,
                                                    const std::vector<SlaveNode>& nodes,
                                                    const std::vector<bool>& active,
                                                    const Linearization& state);

class LoadControl {
 public:
  // The free directions of the model's load-controlled rigid bodies, normalised.
  explicit LoadControl(const ContactModel& model);

  // No load-controlled body: the translations are all prescribed.
  bool empty() const { return directions_.empty(); }
  // The translation sets to solve: `translations`, then one per free direction moved by a unit
  // step.
  std::vector<std::vector<dealii::Tensor<1, 3>>> probe_translations(
      const std::vector<dealii::Tensor<1, 3>>& translations) const;
  // From the states of probe_translations (in order): moves `translations` to the balance and
  // returns the state there (internal forces included, by linearity). False: the forces do not
  // depend on the translations (no contact), nothing is changed.
  bool balance(const ContactModel& model, const std::vector<BondedDof>& bonded_dofs,
               const std::vector<SlaveNode>& nodes, const std::vector<bool>& active,
               std::vector<Linearization>& probes, std::vector<dealii::Tensor<1, 3>>& translations,
               Linearization& state) const;

 private:
  // A unit direction a rigid body may translate in.
  struct FreeDirection {
    unsigned int body;               // index into ContactModel::rigid_bodies
    dealii::Tensor<1, 3> direction;  // unit vector
  };
  std::vector<FreeDirection> directions_;
};

}  // namespace hipfai::fem
