// hipfai — the faces of the contact surfaces as polynomial patches, kept across the runs of a
// motion.
//
// The contact search integrates every slave face against the master faces (fem/mortar_segments.h)
// and needs each face as the polynomial patch its mapping makes (fem/face_patch.h); making one
// from the curved mapping costs some thirty mapping evaluations. Between the steps of a motion the
// faces do not change shape: the acetabular side does not move, and the femoral side turns
// rigidly with its bone about the rotation centre (ElasticSystem::place_bodies). So a face made
// once is turned with its body on later runs instead of being made again. That is exact only if
// the mapping turns with the body (a manifold centred on the rotation centre, or none): the
// turned face is therefore checked against the face's support points, which the system computes
// from the mapping on every run and which determine the face when the mapping's degree is at most
// the element's; a face that fails the check, or whose body's dofs changed, is made anew.
#pragma once

#include "fem/contact_model.h"
#include "fem/elastic_system.h"
#include "fem/face_patch.h"

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>

#include <map>
#include <vector>

namespace hipfai::fem {

class ContactSurfaces {
 public:
  // Brings the faces of every boundary the model's contact pairs name (slave surfaces and
  // deformable masters) to the system's current placement (after ElasticSystem::setup).
  void update(const ElasticSystem& system, const ContactModel& model);

  // The faces of `boundary_id` in the system's order (active cells, then their faces); empty for a
  // boundary no pair names or that has no faces.
  const std::vector<FacePatch>& faces(dealii::types::boundary_id boundary_id) const;

  // The faces update() would give for `model`'s placement if every face passed its check: the
  // faces as made, turned with their bones to the model's rotations. Reads neither the system nor
  // the mesh, so it can be made while the mesh is in another placement (a search ahead).
  ContactSurfaces predicted(const ContactModel& model) const;
  // True when both hold the same boundaries with bit-for-bit the same faces.
  bool same_faces(const ContactSurfaces& other) const;

  // Faces made from the mapping since construction; the others were reused or turned.
  std::size_t faces_made() const { return faces_made_; }

 private:
  // A face as made from the mapping, with what it was made in.
  struct MadeFace {
    FacePatch patch;
    dealii::Tensor<2, 3> rotation;  // of its body's bone when made (identity: not bonded)
    std::vector<dealii::types::global_dof_index> support_dofs;  // x-component dofs on the face
    std::vector<dealii::Point<3>> support_points;               // their support points then
  };
  MadeFace make(const ElasticSystem& system, const dealii::DoFHandler<3>::active_cell_iterator& cell,
                unsigned int face_no, const dealii::Tensor<2, 3>& rotation);

  // The rotation and centre a cell's body is placed with in `model` (identity: not bonded).
  static std::pair<dealii::Tensor<2, 3>, dealii::Point<3>> placement(
      const ContactModel& model, dealii::types::material_id material);

  std::map<dealii::types::boundary_id, std::vector<MadeFace>> made_;
  std::map<dealii::types::boundary_id, std::vector<FacePatch>> current_;
  std::size_t faces_made_ = 0;
};

}  // namespace hipfai::fem
