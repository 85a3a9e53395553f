// hipfai — closest-point projection onto a deformable boundary of a finite-element mesh.
//
// Used by the mortar contact on non-matching meshes (fem/mortar_coupling.h): a slave node is
// projected onto the closest point of the master boundary (the faces with one boundary id,
// curved as the mapping makes them); the projection tells whether anything lies opposite the
// node and gives the master normal there, along which the mortar gap is measured. It also
// reports the interpolation weights of the master degrees of freedom at that point. The master
// faces, as polynomial patches, are what the mortar segments are cut from (faces()).
#pragma once

#include "fem/face_patch.h"

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>

#include <array>
#include <utility>
#include <vector>

namespace hipfai::fem {

struct BoundaryProjection {
  bool found = false;
  dealii::Point<3> point_mm;
  dealii::Tensor<1, 3> normal;  // outward normal of the master body at point_mm
  double distance_mm = 0.0;
  // For each displacement component: (global dof, shape-function weight) pairs whose sum
  // interpolates that component of the master displacement at point_mm.
  std::array<std::vector<std::pair<dealii::types::global_dof_index, double>>, 3> weights;
};

class BoundaryProjector {
 public:
  // Collects the faces with `boundary_id` on every cell known to this rank (all cells for a
  // shared triangulation). The DoF handler must use an FESystem of 3 equal scalar elements.
  BoundaryProjector(const dealii::Mapping<3>& mapping, const dealii::DoFHandler<3>& dof_handler,
                    dealii::types::boundary_id boundary_id);
  // The same from the boundary's faces already made (fem/contact_surfaces.h), of a mesh with
  // element `fe`. Reads nothing of the mesh afterwards (the faces carry their dofs).
  BoundaryProjector(const dealii::FiniteElement<3>& fe, std::vector<FacePatch> faces)
      : fe_(&fe), faces_(std::move(faces)) {}

  std::size_t n_faces() const { return faces_.size(); }
  const std::vector<FacePatch>& faces() const { return faces_; }

  // Closest point on the boundary to `query_mm`, searching faces whose bounding box, grown by
  // `search_radius_mm`, contains the query. found = false when none does.
  BoundaryProjection project(const dealii::Point<3>& query_mm, double search_radius_mm) const;
  // The same without the interpolation weights (found, point, normal and distance): what the
  // contact search needs, at a fraction of the cost.
  BoundaryProjection closest(const dealii::Point<3>& query_mm, double search_radius_mm) const;

 private:
  // closest() and the face and parameters of its point (null face: none found).
  BoundaryProjection closest(const dealii::Point<3>& query_mm, double search_radius_mm,
                             const FacePatch*& face, double& s, double& t) const;

  const dealii::FiniteElement<3>* fe_;
  // Faces with their bounding boxes padded for curvature.
  std::vector<FacePatch> faces_;
};

}  // namespace hipfai::fem
