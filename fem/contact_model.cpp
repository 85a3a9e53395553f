#include "fem/contact_model.h"

#include "core/error.h"

namespace hipfai::fem {

void check_references(const ContactModel& model) {
  const int n_rigid = static_cast<int>(model.rigid_bodies.size());
  for (const Body& body : model.bodies) {
    if (body.bonded_rigid_body >= n_rigid) {
      throw_error("fem model: body ", body.name, " is bonded to rigid body ",
                  body.bonded_rigid_body, " which does not exist");
    }
  }
  for (const BondedBoundary& bonded : model.bonded_boundaries) {
    if (bonded.rigid_body >= n_rigid) {
      throw_error("fem model: bonded boundary ", static_cast<int>(bonded.boundary_id),
                  " refers to rigid body ", bonded.rigid_body, " which does not exist");
    }
  }
  for (unsigned int p = 0; p < model.contact_pairs.size(); ++p) {
    const ContactPair& pair = model.contact_pairs[p];
    if (pair.master_rigid_body >= 0 && (pair.master_rigid_body >= n_rigid ||
                                        !model.rigid_bodies[pair.master_rigid_body].surface)) {
      throw_error("fem model: contact pair ", p, ": rigid body ", pair.master_rigid_body,
                  " does not exist or has no surface");
    }
  }
  for (const RigidBody& body : model.rigid_bodies) {
    if (!body.load_controlled) continue;
    for (const dealii::Tensor<1, 3>& direction : body.free_directions) {
      if (!(direction.norm() > 0.0))
        throw_error("fem model: rigid body ", body.name, ": zero free direction");
    }
  }
}

int rigid_body_of_material(const ContactModel& model, dealii::types::material_id material) {
  int rigid = -1;
  for (const Body& body : model.bodies)
    if (body.material_id == material) rigid = body.bonded_rigid_body;
  return rigid;
}

}  // namespace hipfai::fem
