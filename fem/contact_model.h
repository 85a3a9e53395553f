// hipfai — the description of a contact model: deformable bodies, rigid bodies, and the
// boundaries that tie them together (bonded interfaces, symmetry planes, contact pairs).
//
// A plain value type: the caller fills it (fem/hip_fe_model.h, fem/verification_cases.h, tests)
// and hands it to fem::ContactProblem, which reads it on every run (a motion changes the moving
// rigid body's rotation, translation and load between runs). The deformable bodies live in one
// triangulation, told apart by their material id; the boundaries are named by boundary id.
// Units: mm, N, MPa.
#pragma once

#include "fem/elastic_material.h"
#include "fem/rigid_surface.h"

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace hipfai::fem {

// A deformable, linear elastic body: the cells of one material id.
struct Body {
  std::string name;                            // for reports ("femoral cartilage")
  dealii::types::material_id material_id = 0;  // its cells' material id
  ElasticMaterial material;                    // its elastic constants
  // Rigid body this body is bonded to (-1: none). Its cells follow that body's rotation: the
  // mesh is rotated rigidly before the solve, so a large rotation (the femur's flexion) costs no
  // strain in the small-strain model, and the contact search runs in the rotated configuration.
  int bonded_rigid_body = -1;
};

// A rigid body: its translation is either prescribed (translation_mm) or, when load_controlled,
// unknown along free_directions so that the contact force it transmits equals force_n.
// Its motion is x -> c + R (x - c) + t: the rotation R about c (the hip joint centre) is always
// prescribed (identity by default), t is prescribed or solved for.
struct RigidBody {
  std::string name;                             // for reports ("femur")
  std::shared_ptr<const RigidSurface> surface;  // null for a bone that is only bonded
  dealii::Tensor<1, 3> translation_mm;          // prescribed, or the starting guess
  bool load_controlled = false;                 // translation solved for along free_directions
  std::vector<dealii::Tensor<1, 3>> free_directions;  // nonzero; normalised by the solver
  dealii::Tensor<1, 3> force_n;  // force the body applies to the deformable bodies
  dealii::Tensor<2, 3> rotation = dealii::unit_symmetric_tensor<3>();  // R, proper orthogonal
  dealii::Point<3> rotation_center_mm;                                 // c
};

// Boundary bonded to bone: u = translation of rigid_body (if >= 0) + extra_displacement_mm(x).
struct BondedBoundary {
  dealii::types::boundary_id boundary_id = 0;  // the bonded faces
  int rigid_body = -1;                         // whose translation the faces follow (-1: none)
  // Additional prescribed displacement at a reference point (empty: none).
  std::function<dealii::Tensor<1, 3>(const dealii::Point<3>&)> extra_displacement_mm;
};

// Frictionless symmetry plane (or frictionless wall) normal to a coordinate axis: u[axis] = 0.
struct SymmetryBoundary {
  dealii::types::boundary_id boundary_id = 0;  // the faces on the plane
  unsigned int axis = 0;                       // the displacement component held at 0
};

// Slave surface (a boundary id) against either a rigid body's surface or a deformable boundary.
struct ContactPair {
  dealii::types::boundary_id slave_boundary_id = 0;   // the slave faces
  int master_rigid_body = -1;                         // >= 0: rigid master
  dealii::types::boundary_id master_boundary_id = 0;  // used when master_rigid_body < 0
};

// The whole model; indices into rigid_bodies name rigid bodies everywhere.
struct ContactModel {
  std::vector<Body> bodies;                           // every cell belongs to one of them
  std::vector<RigidBody> rigid_bodies;                // bones and indenters
  std::vector<BondedBoundary> bonded_boundaries;      // applied before symmetry boundaries
  std::vector<SymmetryBoundary> symmetry_boundaries;  // frictionless planes
  std::vector<ContactPair> contact_pairs;             // ContactNode::pair indexes these
};

// Throws hipfai::Error for a reference to a rigid body that does not exist (from a body, a
// bonded boundary or a contact pair), a rigid master without a surface, or a zero free
// direction of a load-controlled rigid body. The mesh-dependent checks (material ids, empty
// boundaries) are made by the stages that use the mesh.
void check_references(const ContactModel& model);

// The rigid body the cells of `material` are bonded to (the last body of that material decides),
// -1 for none: the bone a cell turns with when the mesh is placed.
int rigid_body_of_material(const ContactModel& model, dealii::types::material_id material);

}  // namespace hipfai::fem
