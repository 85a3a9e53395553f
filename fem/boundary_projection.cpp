#include "fem/boundary_projection.h"

#include <deal.II/fe/fe.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/dofs/dof_accessor.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hipfai::fem {

namespace {

// Reference-cell point on face `face_no` at face parameters (s, t) in [0,1]^2. The parameter
// order need not match deal.II's face orientation: we only need some parametrization.
dealii::Point<3> face_to_cell_point(unsigned int face_no, double s, double t) {
  const unsigned int axis = face_no / 2;
  dealii::Point<3> point;
  point[axis] = static_cast<double>(face_no % 2);
  point[(axis + 1) % 3] = s;
  point[(axis + 2) % 3] = t;
  return point;
}

}  // namespace

BoundaryProjector::BoundaryProjector(const dealii::Mapping<3>& mapping,
                                     const dealii::DoFHandler<3>& dof_handler,
                                     dealii::types::boundary_id boundary_id)
    : mapping_(mapping), dof_handler_(dof_handler) {
  // A MappingQ of degree k makes every face a polynomial of degree k in each parameter; a
  // plain (affine/trilinear) mapping has degree 1. Degree 4 is exact for anything up to it.
  degree_ = 4;
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    for (const unsigned int face_no : cell->face_indices()) {
      const auto face = cell->face(face_no);
      if (!face->at_boundary() || face->boundary_id() != boundary_id) continue;
      Face entry{cell, face_no, {}, {}, {}, 1.0};
      // The box of the vertices, padded by a quarter of the face diameter for curved faces.
      for (unsigned int d = 0; d < 3; ++d) {
        entry.box_min[d] = std::numeric_limits<double>::max();
        entry.box_max[d] = std::numeric_limits<double>::lowest();
      }
      for (unsigned int v = 0; v < face->n_vertices(); ++v) {
        for (unsigned int d = 0; d < 3; ++d) {
          entry.box_min[d] = std::min(entry.box_min[d], face->vertex(v)[d]);
          entry.box_max[d] = std::max(entry.box_max[d], face->vertex(v)[d]);
        }
      }
      const double pad = 0.25 * face->diameter();
      for (unsigned int d = 0; d < 3; ++d) {
        entry.box_min[d] -= pad;
        entry.box_max[d] += pad;
      }
      for (unsigned int j = 0; j <= degree_; ++j) {
        for (unsigned int i = 0; i <= degree_; ++i) {
          entry.samples.push_back(mapping.transform_unit_to_real_cell(
              cell, face_to_cell_point(face_no, double(i) / degree_, double(j) / degree_)));
        }
      }
      {
        dealii::Point<3> x;
        dealii::Tensor<1, 3> ds, dt;
        evaluate(entry, 0.5, 0.5, x, ds, dt);
        const dealii::Tensor<1, 3> normal = dealii::cross_product_3d(ds, dt);
        dealii::Point<3> inner = face_to_cell_point(face_no, 0.5, 0.5);
        inner[face_no / 2] = (face_no % 2 == 0) ? 0.25 : 0.75;
        if ((mapping.transform_unit_to_real_cell(cell, inner) - x) * normal > 0) entry.orientation = -1.0;
      }
      faces_.push_back(entry);
    }
  }
}

void BoundaryProjector::evaluate(const Face& face, double s, double t, dealii::Point<3>& x,
                                 dealii::Tensor<1, 3>& ds, dealii::Tensor<1, 3>& dt) const {
  // Lagrange polynomials on equispaced nodes i/k and their derivatives.
  const unsigned int k = degree_;
  const auto basis = [k](double u, std::vector<double>& value, std::vector<double>& slope) {
    value.assign(k + 1, 1.0);
    slope.assign(k + 1, 0.0);
    for (unsigned int i = 0; i <= k; ++i) {
      const double xi = double(i) / k;
      for (unsigned int m = 0; m <= k; ++m) {
        if (m == i) continue;
        const double xm = double(m) / k;
        slope[i] = slope[i] * (u - xm) / (xi - xm) + value[i] / (xi - xm);
        value[i] *= (u - xm) / (xi - xm);
      }
    }
  };
  std::vector<double> vs, ss, vt, st;
  basis(s, vs, ss);
  basis(t, vt, st);
  x = dealii::Point<3>();
  ds = dealii::Tensor<1, 3>();
  dt = dealii::Tensor<1, 3>();
  for (unsigned int j = 0; j <= k; ++j) {
    for (unsigned int i = 0; i <= k; ++i) {
      const dealii::Tensor<1, 3> p = face.samples[j * (k + 1) + i];
      x += vs[i] * vt[j] * p;
      ds += ss[i] * vt[j] * p;
      dt += vs[i] * st[j] * p;
    }
  }
}

BoundaryProjection BoundaryProjector::project(const dealii::Point<3>& query_mm,
                                              double search_radius_mm) const {
  BoundaryProjection best;
  best.distance_mm = std::numeric_limits<double>::max();
  double best_s = 0.0, best_t = 0.0;
  const Face* best_face = nullptr;

  for (const Face& face : faces_) {
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
      evaluate(face, s, t, x, ds, dt);
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
    evaluate(face, s, t, x, ds, dt);
    const double distance = x.distance(query_mm);
    if (distance < best.distance_mm) {
      best.distance_mm = distance;
      best.point_mm = x;
      best.normal = face.orientation * dealii::cross_product_3d(ds, dt);
      best.normal /= best.normal.norm();
      best_s = s;
      best_t = t;
      best_face = &face;
    }
  }
  if (best_face == nullptr) return best;
  best.found = true;

  const dealii::FiniteElement<3>& fe = dof_handler_.get_fe();
  std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell());
  best_face->cell->get_dof_indices(dofs);
  const dealii::Point<3> unit_point = face_to_cell_point(best_face->face_no, best_s, best_t);
  for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i) {
    const double value = fe.shape_value(i, unit_point);
    // Lagrange shape functions of nodes off this face vanish on it (to round-off).
    if (std::abs(value) < 1e-12) continue;
    best.weights[fe.system_to_component_index(i).first].emplace_back(dofs[i], value);
  }
  return best;
}

}  // namespace hipfai::fem
