// hipfai — one boundary face of a finite-element mesh as the polynomial patch its mapping makes.
//
// Contact geometry (closest-point projection, mortar segments) needs to evaluate a curved face
// and its tangents many times at arbitrary face parameters. A MappingQ of degree k makes every
// face a tensor-product polynomial of degree k: the patch samples it once on an equispaced grid of
// that degree and interpolates, which is exact (a mapping of unknown degree is sampled at degree
// 4). A second grid of degree 4 is kept for the face's bounds (samples()), the same whatever the
// mapping. Evaluation is the contact search's innermost call: at degree 2 it sums 9 terms, not 25.
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>

#include <vector>

namespace hipfai::fem {

class FacePatch {
 public:
  static constexpr unsigned int kDegree = 4;  // the bounds' grid, and the largest degree evaluated

  FacePatch(const dealii::Mapping<3>& mapping,
            const dealii::DoFHandler<3>::active_cell_iterator& cell, unsigned int face_no);

  // The same face after its body turned by `rotation` about `centre` (a proper rotation): every
  // point of the patch turned, bounds and orientation following.
  FacePatch turned(const dealii::Tensor<2, 3>& rotation, const dealii::Point<3>& centre) const;

  // The same patch bit for bit: the same face, interpolation nodes and bounds' grid.
  bool identical(const FacePatch& other) const {
    return cell == other.cell && face_no == other.face_no && dofs == other.dofs &&
           degree_ == other.degree_ && orientation_ == other.orientation_ && nodes_ == other.nodes_ &&
           samples_ == other.samples_;
  }

  // Degree of the interpolating polynomial (the mapping's, or kDegree).
  unsigned int degree() const { return degree_; }

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

  // Position, tangents and second derivatives at (s, t).
  void evaluate(double s, double t, dealii::Point<3>& x, dealii::Tensor<1, 3>& ds, dealii::Tensor<1, 3>& dt,
                dealii::Tensor<1, 3>& dss, dealii::Tensor<1, 3>& dst, dealii::Tensor<1, 3>& dtt) const;

  // Face parameters of the point closest to `query_mm` on the (extended) patch, from the face
  // centre: Gauss-Newton, which converges to the nearest foot, until its steps are small, then
  // Newton with the patch's second derivatives, which converges quadratically to that same foot
  // (from the centre it could find other stationary points of the distance on the extension).
  // False if it does not converge.
  bool project(const dealii::Point<3>& query_mm, double& s, double& t) const;
  // Intersection of the line x + lambda * direction with the (extended) patch; false if Newton
  // does not converge.
  bool intersect_line(const dealii::Point<3>& x, const dealii::Tensor<1, 3>& direction, double& s,
                      double& t, double& lambda) const;
  // The same from the starting (s, t, lambda) given (a neighbouring line's answer: fewer Newton
  // steps); from the face centre when that does not converge.
  bool intersect_line_from(const dealii::Point<3>& x, const dealii::Tensor<1, 3>& direction,
                           double& s, double& t, double& lambda) const;
  // The same, also giving the patch's position and tangents where Newton stopped: at the
  // parameters before its last step, which was below 1e-13 (so within round-off of (s, t)).
  bool intersect_line_from(const dealii::Point<3>& x, const dealii::Tensor<1, 3>& direction,
                           double& s, double& t, double& lambda, dealii::Point<3>& at,
                           dealii::Tensor<1, 3>& ds_at, dealii::Tensor<1, 3>& dt_at) const;

  dealii::DoFHandler<3>::active_cell_iterator cell;
  unsigned int face_no = 0;
  // The cell's dofs when the patch was made: what the contact search reads instead of the DoF
  // handler, so that it never touches the mesh (which another thread may be renumbering).
  std::vector<dealii::types::global_dof_index> dofs;
  dealii::Point<3> box_min, box_max;  // bounding box, padded for curvature
  dealii::Point<3> vertex(unsigned int i) const;  // corners in counter-clockwise (s, t) order
  // Points of the face on the equispaced (kDegree+1)^2 grid of (s, t), s fastest: its bounds.
  const std::vector<dealii::Point<3>>& samples() const { return samples_; }

 private:
  FacePatch() = default;
  bool newton_intersect(const dealii::Point<3>& x, const dealii::Tensor<1, 3>& direction,
                        double& s, double& t, double& lambda, dealii::Point<3>& at,
                        dealii::Tensor<1, 3>& ds_at, dealii::Tensor<1, 3>& dt_at) const;
  void set_box();
  std::vector<dealii::Point<3>> samples_;  // (kDegree+1)^2, s fastest
  std::vector<dealii::Point<3>> nodes_;    // (degree_+1)^2 interpolation nodes, s fastest
  unsigned int degree_ = kDegree;
  double orientation_ = 1.0;               // makes ds x dt point out of the cell
};

}  // namespace hipfai::fem
