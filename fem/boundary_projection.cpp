#include "fem/boundary_projection.h"

#include <deal.II/dofs/dof_accessor.h>
#include <deal.II/fe/fe.h>
#include <deal.II/grid/tria_accessor.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hipfai::fem {

BoundaryProjector::BoundaryProjector(const dealii::Mapping<3>& mapping,
                                     const dealii::DoFHandler<3>& dof_handler,
                                     dealii::types::boundary_id boundary_id)
    : fe_(&dof_handler.get_fe()) {
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    for (const unsigned int face_no : cell->face_indices()) {
      const auto face = cell->face(face_no);
      if (!face->at_boundary() || face->boundary_id() != boundary_id) continue;
      faces_.emplace_back(mapping, cell, face_no);
    }
  }
}

BoundaryProjection BoundaryProjector::closest(const dealii::Point<3>& query_mm,
                                              double search_radius_mm) const {
  const FacePatch* face = nullptr;
  double s = 0.0, t = 0.0;
  return closest(query_mm, search_radius_mm, face, s, t);
}

BoundaryProjection BoundaryProjector::closest(const dealii::Point<3>& query_mm,
                                              double search_radius_mm, const FacePatch*& best_face,
                                              double& best_s, double& best_t) const {
  BoundaryProjection best;
  best.distance_mm = std::numeric_limits<double>::max();
  best_s = best_t = 0.0;
  best_face = nullptr;

  for (const FacePatch& face : faces_) {
    bool inside = true;
    for (unsigned int d = 0; d < 3; ++d) {
      if (query_mm[d] < face.box_min[d] - search_radius_mm ||
          query_mm[d] > face.box_max[d] + search_radius_mm) {
        inside = false;
      }
    }
    if (!inside) continue;
    // Projected Gauss-Newton on the face parameters, clamped to the face.
    double s = 0.5, t = 0.5;
    dealii::Point<3> x;
    dealii::Tensor<1, 3> ds, dt;
    for (int iteration = 0; iteration < 30; ++iteration) {
      face.evaluate(s, t, x, ds, dt);
      const dealii::Tensor<1, 3> residual = x - query_mm;
      const double a = ds * ds, b = ds * dt, c = dt * dt;
      const double r1 = -(ds * residual), r2 = -(dt * residual);
      const double det = a * c - b * b;
      if (!(std::abs(det) > 0.0)) break;
      const double new_s = std::clamp(s + (c * r1 - b * r2) / det, 0.0, 1.0);
      const double new_t = std::clamp(t + (a * r2 - b * r1) / det, 0.0, 1.0);
      const double change = std::abs(new_s - s) + std::abs(new_t - t);
      s = new_s;
      t = new_t;
      if (change < 1e-14) break;
    }
    face.evaluate(s, t, x, ds, dt);
    const double distance = x.distance(query_mm);
    if (distance < best.distance_mm) {
      best.distance_mm = distance;
      best.point_mm = x;
      best_s = s;
      best_t = t;
      best_face = &face;
    }
  }
  if (best_face == nullptr) return best;
  best.found = true;
  best.normal = best_face->normal(best_s, best_t);
  return best;
}

BoundaryProjection BoundaryProjector::project(const dealii::Point<3>& query_mm,
                                              double search_radius_mm) const {
  const FacePatch* best_face = nullptr;
  double best_s = 0.0, best_t = 0.0;
  BoundaryProjection best = closest(query_mm, search_radius_mm, best_face, best_s, best_t);
  if (!best.found) return best;
  const dealii::FiniteElement<3>& fe = *fe_;
  const std::vector<dealii::types::global_dof_index>& dofs = best_face->dofs;
  const dealii::Point<3> unit_point = best_face->unit_cell_point(best_s, best_t);
  for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i) {
    const double value = fe.shape_value(i, unit_point);
    // Lagrange shape functions of nodes off this face vanish on it (to round-off).
    if (std::abs(value) < 1e-12) continue;
    best.weights[fe.system_to_component_index(i).first].emplace_back(dofs[i], value);
  }
  return best;
}

}  // namespace hipfai::fem
