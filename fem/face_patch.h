// hipfai — one boundary face of a finite-element mesh as the polynomial patch its mapping makes.
//
// Contact geometry (closest-point projection, mortar segments) needs to evaluate a curved face
// and its tangents many times at arbitrary face parameters. A MappingQ of degree k makes every
// face a tensor-product polynomial of degree k; we sample it once on an equispaced grid of
// degree 4 (exact for any mapping up to degree 4) and interpolate, which is cheap and exact.
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>

#include <vector>

namespace hipfai::fem {

class FacePatch {
 public:
  static constexpr unsigned int kDegree = 4;

  FacePatch(const dealii::Mapping<3>& mapping,
            const dealii::DoFHandler<3>::active_cell_iterator& cell, unsigned int face_no);

  // Position and tangents at face parameters (s, t) (any values: outside [0,1]^2 the polynomial
  // is extended, which the segment clipping relies on).
  void evaluate(double s, double t, dealii::Point<3>& x, dealii::Tensor<1, 3>& ds,
                dealii::Tensor<1, 3>& dt) const;
  // Unit normal pointing out of the cell at (s, t).
  dealii::Tensor<1, 3> normal(double s, double t) const;
  // The same from the tangents evaluate() gave at (s, t).
  dealii::Tensor<1, 3> normal(const dealii::Tensor<1, 3>& ds, const dealii::Tensor<1, 3>& dt) const {
    const dealii::Tensor<1, 3> n = orientation_ * dealii::cross_product_3d(ds, dt);
    return n / n.norm();
  }
  // Reference-cell point of face parameters (s, t).
  dealii::Point<3> unit_cell_point(double s, double t) const;

  // Face parameters of the point closest to `query_mm` on the (extended) patch, by Gauss-Newton
  // from the face centre; false if it does not converge.
  bool project(const dealii::Point<3>& query_mm, double& s, double& t) const;
  // Intersection of the line x + lambda * direction with the (extended) patch; false if Newton
  // does not converge.
  bool intersect_line(const dealii::Point<3>& x, const dealii::Tensor<1, 3>& direction, double& s,
                      double& t, double& lambda) const;
  // The same from the starting (s, t, lambda) given (a neighbouring line's answer: fewer Newton
  // steps); from the face centre when that does not converge.
  bool intersect_line_from(const dealii::Point<3>& x, const dealii::Tensor<1, 3>& direction,
                           double& s, double& t, double& lambda) const;

  dealii::DoFHandler<3>::active_cell_iterator cell;
  unsigned int face_no = 0;
  dealii::Point<3> box_min, box_max;  // bounding box, padded for curvature
  dealii::Point<3> vertex(unsigned int i) const;  // corners in counter-clockwise (s, t) order
  // The patch's interpolation points: (kDegree+1)^2 on an equispaced grid of (s, t), s fastest.
  const std::vector<dealii::Point<3>>& samples() const { return samples_; }

 private:
  bool newton_intersect(const dealii::Point<3>& x, const dealii::Tensor<1, 3>& direction,
                        double& s, double& t, double& lambda) const;
  std::vector<dealii::Point<3>> samples_;  // (kDegree+1)^2, s fastest
  double orientation_ = 1.0;               // makes ds x dt point out of the cell
};

}  // namespace hipfai::fem
