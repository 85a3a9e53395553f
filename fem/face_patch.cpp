#include "fem/face_patch.h"

#include <deal.II/dofs/dof_accessor.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/tria_accessor.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hipfai::fem {

namespace {

// Lagrange polynomials on the equispaced nodes i/(N-1) and their first and second derivatives at
// u. The constant denominators prod_{m != i} (x_i - x_m) are tabulated once per degree.
template <unsigned int N>
struct LagrangeDenominators {
  std::array<double, N> inverse{};
  LagrangeDenominators() {
    for (unsigned int i = 0; i < N; ++i) {
      double product = 1.0;
      for (unsigned int m = 0; m < N; ++m) {
        if (m != i) product *= double(i) / (N - 1) - double(m) / (N - 1);
      }
      inverse[i] = 1.0 / product;
    }
  }
};

template <unsigned int N, bool kSecond>
void lagrange_basis(double u, std::array<double, N>& value, std::array<double, N>& slope,
                    std::array<double, N>& curvature) {
  static const LagrangeDenominators<N> denominators;
  std::array<double, N> d;
  for (unsigned int m = 0; m < N; ++m) d[m] = u - double(m) / (N - 1);
  for (unsigned int i = 0; i < N; ++i) {
    // The product of the factors (u - x_m), m != i, and its derivatives by the product rule.
    double v = 1.0, dv = 0.0, d2v = 0.0;
    for (unsigned int m = 0; m < N; ++m) {
      if (m == i) continue;
      if constexpr (kSecond) d2v = d2v * d[m] + 2.0 * dv;
      dv = dv * d[m] + v;
      v *= d[m];
    }
    value[i] = v * denominators.inverse[i];
    slope[i] = dv * denominators.inverse[i];
    if constexpr (kSecond) curvature[i] = d2v * denominators.inverse[i];
  }
}

// The patch through `nodes` (N x N, s fastest) at (s, t): position and tangents, and with
// kSecond the second derivatives. Sum factorisation: contract over i (the s direction) once per
// row j, then over j.
template <unsigned int N, bool kSecond>
void evaluate_patch(const std::vector<dealii::Point<3>>& nodes, double s, double t, double* x,
                    double* ds, double* dt, double* dss, double* dst, double* dtt) {
  std::array<double, N> vs, ss, cs, vt, st, ct;
  lagrange_basis<N, kSecond>(s, vs, ss, cs);
  lagrange_basis<N, kSecond>(t, vt, st, ct);
  for (unsigned int d = 0; d < 3; ++d) {
    x[d] = ds[d] = dt[d] = 0.0;
    if constexpr (kSecond) dss[d] = dst[d] = dtt[d] = 0.0;
  }
  for (unsigned int j = 0; j < N; ++j) {
    double row[3] = {0, 0, 0}, row_s[3] = {0, 0, 0}, row_ss[3] = {0, 0, 0};
    for (unsigned int i = 0; i < N; ++i) {
      const dealii::Point<3>& p = nodes[j * N + i];
      for (unsigned int d = 0; d < 3; ++d) {
        row[d] += vs[i] * p[d];
        row_s[d] += ss[i] * p[d];
        if constexpr (kSecond) row_ss[d] += cs[i] * p[d];
      }
    }
    for (unsigned int d = 0; d < 3; ++d) {
      x[d] += vt[j] * row[d];
      ds[d] += vt[j] * row_s[d];
      dt[d] += st[j] * row[d];
      if constexpr (kSecond) {
        dss[d] += vt[j] * row_ss[d];
        dst[d] += st[j] * row_s[d];
        dtt[d] += ct[j] * row[d];
      }
    }
  }
}

template <bool kSecond>
void evaluate_degree(unsigned int degree, const std::vector<dealii::Point<3>>& nodes, double s,
                     double t, double* x, double* ds, double* dt, double* dss, double* dst, double* dtt) {
  switch (degree) {
    case 1: evaluate_patch<2, kSecond>(nodes, s, t, x, ds, dt, dss, dst, dtt); return;
    case 2: evaluate_patch<3, kSecond>(nodes, s, t, x, ds, dt, dss, dst, dtt); return;
    case 3: evaluate_patch<4, kSecond>(nodes, s, t, x, ds, dt, dss, dst, dtt); return;
    default: evaluate_patch<5, kSecond>(nodes, s, t, x, ds, dt, dss, dst, dtt); return;
  }
}

dealii::Point<3> point_of(const double* x) { return dealii::Point<3>(x[0], x[1], x[2]); }
dealii::Tensor<1, 3> tensor_of(const double* x) { return dealii::Tensor<1, 3>({x[0], x[1], x[2]}); }

}  // namespace

dealii::Point<3> FacePatch::unit_cell_point(double s, double t) const {
  // The parameter order need not match deal.II's face orientation: any parametrization will do.
  const unsigned int axis = face_no / 2;
  dealii::Point<3> point;
  point[axis] = static_cast<double>(face_no % 2);
  point[(axis + 1) % 3] = s;
  point[(axis + 2) % 3] = t;
  return point;
}

FacePatch::FacePatch(const dealii::Mapping<3>& mapping,
                     const dealii::DoFHandler<3>::active_cell_iterator& cell_in,
                     unsigned int face_no_in)
    : cell(cell_in), face_no(face_no_in), dofs(cell_in->get_fe().n_dofs_per_cell()) {
  cell->get_dof_indices(dofs);
  const auto grid = [&](unsigned int degree) {
    std::vector<dealii::Point<3>> points;
    for (unsigned int j = 0; j <= degree; ++j) {
      for (unsigned int i = 0; i <= degree; ++i) {
        points.push_back(mapping.transform_unit_to_real_cell(
            cell, unit_cell_point(double(i) / degree, double(j) / degree)));
      }
    }
    return points;
  };
  samples_ = grid(kDegree);
  if (const auto* q = dynamic_cast<const dealii::MappingQ<3>*>(&mapping)) {
    degree_ = std::clamp(q->get_degree(), 1u, kDegree);
  }
  if (degree_ == kDegree) {
    nodes_ = samples_;
  } else {
    // The grid of degree k is a subset of the grid of degree 4 only for k = 1, 2, 4.
    if (kDegree % degree_ == 0) {
      const unsigned int stride = kDegree / degree_;
      for (unsigned int j = 0; j <= kDegree; j += stride) {
        for (unsigned int i = 0; i <= kDegree; i += stride) nodes_.push_back(samples_[j * (kDegree + 1) + i]);
      }
    } else {
      nodes_ = grid(degree_);
    }
  }
  set_box();
  dealii::Point<3> x;
  dealii::Tensor<1, 3> ds, dt;
  evaluate(0.5, 0.5, x, ds, dt);
  dealii::Point<3> inner = unit_cell_point(0.5, 0.5);
  inner[face_no / 2] = (face_no % 2 == 0) ? 0.25 : 0.75;
  if ((mapping.transform_unit_to_real_cell(cell, inner) - x) * dealii::cross_product_3d(ds, dt) > 0) {
    orientation_ = -1.0;
  }
}

FacePatch FacePatch::turned(const dealii::Tensor<2, 3>& rotation, const dealii::Point<3>& centre) const {
  FacePatch out;
  out.cell = cell;
  out.face_no = face_no;
  out.dofs = dofs;
  out.degree_ = degree_;
  out.orientation_ = orientation_;  // a proper rotation keeps ds x dt on the same side
  const auto turn = [&](const std::vector<dealii::Point<3>>& points) {
    std::vector<dealii::Point<3>> result;
    result.reserve(points.size());
    for (const dealii::Point<3>& p : points) result.push_back(centre + rotation * (p - centre));
    return result;
  };
  out.samples_ = turn(samples_);
  out.nodes_ = turn(nodes_);
  out.set_box();
  return out;
}

void FacePatch::set_box() {
  for (unsigned int d = 0; d < 3; ++d) {
    box_min[d] = std::numeric_limits<double>::max();
    box_max[d] = std::numeric_limits<double>::lowest();
  }
  for (const dealii::Point<3>& p : samples_) {
    for (unsigned int d = 0; d < 3; ++d) {
      box_min[d] = std::min(box_min[d], p[d]);
      box_max[d] = std::max(box_max[d], p[d]);
    }
  }
  // The samples bound the face up to its curvature between them: pad by a tenth of the size.
  const double pad = 0.1 * box_min.distance(box_max);
  for (unsigned int d = 0; d < 3; ++d) {
    box_min[d] -= pad;
    box_max[d] += pad;
  }
}

void FacePatch::evaluate(double s, double t, dealii::Point<3>& x, dealii::Tensor<1, 3>& ds,
                         dealii::Tensor<1, 3>& dt) const {
  double px[3], ps[3], pt[3];
  evaluate_degree<false>(degree_, nodes_, s, t, px, ps, pt, nullptr, nullptr, nullptr);
  x = point_of(px);
  ds = tensor_of(ps);
  dt = tensor_of(pt);
}

void FacePatch::evaluate(double s, double t, dealii::Point<3>& x, dealii::Tensor<1, 3>& ds,
                         dealii::Tensor<1, 3>& dt, dealii::Tensor<1, 3>& dss, dealii::Tensor<1, 3>& dst,
                         dealii::Tensor<1, 3>& dtt) const {
  double px[3], ps[3], pt[3], pss[3], pst[3], ptt[3];
  evaluate_degree<true>(degree_, nodes_, s, t, px, ps, pt, pss, pst, ptt);
  x = point_of(px);
  ds = tensor_of(ps);
  dt = tensor_of(pt);
  dss = tensor_of(pss);
  dst = tensor_of(pst);
  dtt = tensor_of(ptt);
}

dealii::Tensor<1, 3> FacePatch::normal(double s, double t) const {
  dealii::Point<3> x;
  dealii::Tensor<1, 3> ds, dt;
  evaluate(s, t, x, ds, dt);
  return normal(ds, dt);
}

dealii::Point<3> FacePatch::vertex(unsigned int i) const {
  static constexpr double kS[4] = {0, 1, 1, 0}, kT[4] = {0, 0, 1, 1};
  dealii::Point<3> x;
  dealii::Tensor<1, 3> ds, dt;
  evaluate(kS[i], kT[i], x, ds, dt);
  return x;
}

bool FacePatch::project(const dealii::Point<3>& query_mm, double& s, double& t) const {
  // Gauss-Newton's rate is about distance / radius of curvature; once its steps are below this,
  // the foot it converges to is the nearest root of Newton's equations, which Newton reaches in
  // two or three steps.
  constexpr double kNewtonFrom = 1e-3;
  s = 0.5;
  t = 0.5;
  double last_step = 1.0;
  bool newton = false;
  dealii::Point<3> x;
  dealii::Tensor<1, 3> ds, dt, dss, dst, dtt;
  for (int iteration = 0; iteration < 30; ++iteration) {
    if (newton) {
      evaluate(s, t, x, ds, dt, dss, dst, dtt);
    } else {
      evaluate(s, t, x, ds, dt);
    }
    const dealii::Tensor<1, 3> residual = x - query_mm;
    double a = ds * ds, b = ds * dt, c = dt * dt;
    if (newton) {
      const double na = a + dss * residual, nb = b + dst * residual, nc = c + dtt * residual;
      if (na > 0.0 && na * nc - nb * nb > 0.0) {  // a minimum of the distance: Newton's step
        a = na;
        b = nb;
        c = nc;
      }
    }
    const double r1 = -(ds * residual), r2 = -(dt * residual);
    const double det = a * c - b * b;
    if (!(std::abs(det) > 0.0)) return false;
    const double step_s = (c * r1 - b * r2) / det, step_t = (a * r2 - b * r1) / det;
    s += step_s;
    t += step_t;
    if (std::abs(s) > 10.0 || std::abs(t) > 10.0) return false;  // far off this face
    // Converged to round-off of the parameters (the extended patch's evaluation is noisier
    // than 1e-14 outside [0,1]^2).
    if (std::abs(step_s) + std::abs(step_t) < 1e-13) return true;
    last_step = std::abs(step_s) + std::abs(step_t);
    if (last_step < kNewtonFrom) newton = true;
  }
  return last_step < 1e-9;
}

bool FacePatch::intersect_line(const dealii::Point<3>& x0, const dealii::Tensor<1, 3>& direction,
                               double& s, double& t, double& lambda) const {
  s = 0.5;
  t = 0.5;
  lambda = 0.0;
  dealii::Point<3> x;
  dealii::Tensor<1, 3> ds, dt;
  return newton_intersect(x0, direction, s, t, lambda, x, ds, dt);
}

bool FacePatch::intersect_line_from(const dealii::Point<3>& x0,
                                    const dealii::Tensor<1, 3>& direction, double& s, double& t,
                                    double& lambda) const {
  dealii::Point<3> x;
  dealii::Tensor<1, 3> ds, dt;
  return intersect_line_from(x0, direction, s, t, lambda, x, ds, dt);
}

bool FacePatch::intersect_line_from(const dealii::Point<3>& x0, const dealii::Tensor<1, 3>& direction,
                                    double& s, double& t, double& lambda, dealii::Point<3>& at,
                                    dealii::Tensor<1, 3>& ds_at, dealii::Tensor<1, 3>& dt_at) const {
  if (newton_intersect(x0, direction, s, t, lambda, at, ds_at, dt_at)) return true;
  s = 0.5;
  t = 0.5;
  lambda = 0.0;
  return newton_intersect(x0, direction, s, t, lambda, at, ds_at, dt_at);
}

bool FacePatch::newton_intersect(const dealii::Point<3>& x0, const dealii::Tensor<1, 3>& direction,
                                 double& s, double& t, double& lambda, dealii::Point<3>& x,
                                 dealii::Tensor<1, 3>& ds, dealii::Tensor<1, 3>& dt) const {
  double last_step = 1.0;
  for (int iteration = 0; iteration < 30; ++iteration) {
    evaluate(s, t, x, ds, dt);
    // F(s, t, lambda) = x(s, t) - x0 - lambda d = 0; Cramer's rule on [ds dt -d].
    const dealii::Tensor<1, 3> residual = x - x0 - lambda * direction;
    const dealii::Tensor<1, 3> minus_d = -direction;
    const double det = dealii::cross_product_3d(ds, dt) * minus_d;
    if (!(std::abs(det) > 0.0)) return false;
    const double step_s = -(dealii::cross_product_3d(residual, dt) * minus_d) / det;
    const double step_t = -(dealii::cross_product_3d(ds, residual) * minus_d) / det;
    const double step_l = -(dealii::cross_product_3d(ds, dt) * residual) / det;
    s += step_s;
    t += step_t;
    lambda += step_l;
    if (std::abs(s) > 10.0 || std::abs(t) > 10.0) return false;
    // Converged to round-off of the parameters (the extended patch's evaluation is noisier
    // than 1e-14 outside [0,1]^2).
    if (std::abs(step_s) + std::abs(step_t) < 1e-13) return true;
    last_step = std::abs(step_s) + std::abs(step_t);
  }
  return last_step < 1e-9;
}

}  // namespace hipfai::fem
