#include "fem/contact_surfaces.h"

#include <deal.II/dofs/dof_accessor.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria_accessor.h>

#include <algorithm>
#include <cstddef>
#include <set>

namespace hipfai::fem {

namespace {

// The x-component dofs of the nodes on face `face_no` of a cell, in the cell's dof order.
std::vector<dealii::types::global_dof_index> face_support_dofs(
    const ElasticSystem& system, const dealii::DoFHandler<3>::active_cell_iterator& cell,
    unsigned int face_no, std::vector<dealii::types::global_dof_index>& scratch) {
  cell->get_dof_indices(scratch);
  std::vector<dealii::types::global_dof_index> dofs;
  for (unsigned int i = 0; i < scratch.size(); ++i) {
    if (system.support_on_face(face_no, i) && system.component_of(i) == 0) dofs.push_back(scratch[i]);
  }
  return dofs;
}

}  // namespace

ContactSurfaces::MadeFace ContactSurfaces::make(const ElasticSystem& system,
                                                const dealii::DoFHandler<3>::active_cell_iterator& cell,
                                                unsigned int face_no, const dealii::Tensor<2, 3>& rotation) {
  ++faces_made_;
  MadeFace face{FacePatch(system.mapping(), cell, face_no), rotation, {}, {}};
  std::vector<dealii::types::global_dof_index> scratch(system.fe().n_dofs_per_cell());
  face.support_dofs = face_support_dofs(system, cell, face_no, scratch);
  for (const auto dof : face.support_dofs) face.support_points.push_back(system.support_points()[dof]);
  return face;
}

void ContactSurfaces::update(const ElasticSystem& system, const ContactModel& model) {
  std::set<dealii::types::boundary_id> boundaries;
  for (const ContactPair& pair : model.contact_pairs) {
    boundaries.insert(pair.slave_boundary_id);
    if (pair.master_rigid_body < 0) boundaries.insert(pair.master_boundary_id);
  }
  // Support points agree to round-off when the mapping turns with the body.
  const double tolerance = 1e-10 * system.diameter();
  // A face is determined by its support points only if the element's nodes on it can carry the
  // mapping's polynomial.
  const bool checkable = system.mapping().get_degree() <= system.fe().degree;
  std::vector<dealii::types::global_dof_index> scratch(system.fe().n_dofs_per_cell());

  current_.clear();
  for (const dealii::types::boundary_id id : boundaries) {
    std::vector<MadeFace>& made = made_[id];
    std::vector<FacePatch>& current = current_[id];
    std::size_t index = 0;
    for (const auto& cell : system.dof_handler().active_cell_iterators()) {
      for (const unsigned int face_no : cell->face_indices()) {
        const auto face = cell->face(face_no);
        if (!face->at_boundary() || face->boundary_id() != id) continue;
        // The rotation and centre the cell's vertices were placed with.
        const auto [rotation, centre] = placement(model, cell->material_id());
        const bool known = index < made.size() && made[index].patch.cell == cell &&
                           made[index].patch.face_no == face_no;
        if (!known) {
          made.erase(made.begin() + static_cast<std::ptrdiff_t>(index), made.end());  // the rest: new faces
          made.push_back(make(system, cell, face_no, rotation));
          current.push_back(made.back().patch);
          ++index;
          continue;
        }
        MadeFace& old = made[index];
        const dealii::Tensor<2, 3> turn = rotation * dealii::transpose(old.rotation);
        // The same dofs (the patch carries its cell's, fem/face_patch.h) and the same shape.
        cell->get_dof_indices(scratch);
        bool same = checkable && scratch == old.patch.dofs;
        for (std::size_t k = 0; same && k < old.support_dofs.size(); ++k) {
          const dealii::Point<3> expected = centre + turn * (old.support_points[k] - centre);
          same = system.support_points()[old.support_dofs[k]].distance(expected) <= tolerance;
        }
        if (!same) {
          old = make(system, cell, face_no, rotation);
          current.push_back(old.patch);
        } else if (rotation == old.rotation) {
          current.push_back(old.patch);
        } else {
          current.push_back(old.patch.turned(turn, centre));
        }
        ++index;
      }
    }
    made.erase(made.begin() + static_cast<std::ptrdiff_t>(std::min(index, made.size())), made.end());
  }
}

std::pair<dealii::Tensor<2, 3>, dealii::Point<3>> ContactSurfaces::placement(
    const ContactModel& model, dealii::types::material_id material) {
  const int rigid = rigid_body_of_material(model, material);
  if (rigid < 0) return {dealii::unit_symmetric_tensor<3>(), dealii::Point<3>()};
  return {model.rigid_bodies[rigid].rotation, model.rigid_bodies[rigid].rotation_center_mm};
}

ContactSurfaces ContactSurfaces::predicted(const ContactModel& model) const {
  ContactSurfaces out;
  for (const auto& [id, made] : made_) {
    std::vector<FacePatch>& current = out.current_[id];
    for (const MadeFace& face : made) {
      const auto [rotation, centre] = placement(model, face.patch.cell->material_id());
      if (rotation == face.rotation)
        current.push_back(face.patch);
      else
        current.push_back(face.patch.turned(rotation * dealii::transpose(face.rotation), centre));
    }
  }
  return out;
}

bool ContactSurfaces::same_faces(const ContactSurfaces& other) const {
  if (current_.size() != other.current_.size()) return false;
  for (const auto& [id, faces] : current_) {
    const auto it = other.current_.find(id);
    if (it == other.current_.end() || it->second.size() != faces.size()) return false;
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (!faces[f].identical(it->second[f])) return false;
  }
  return true;
}

const std::vector<FacePatch>& ContactSurfaces::faces(dealii::types::boundary_id boundary_id) const {
  static const std::vector<FacePatch> kNone;
  const auto it = current_.find(boundary_id);
  return it == current_.end() ? kNone : it->second;
}

}  // namespace hipfai::fem
