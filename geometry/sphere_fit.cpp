#include "geometry/sphere_fit.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace hipfai::geometry {
namespace {

// Centroid and the extent of the points; flat when the smallest principal spread is below 1e-6
// of the largest (coplanar or collinear).
struct Spread {
  Vec3 centroid = Vec3::Zero();
  double extent_mm = 0.0;
  bool flat = true;
};

Spread spread_of(const std::vector<const Vec3*>& points) {
  Spread s;
  if (points.empty()) return s;
  for (const Vec3* p : points) s.centroid += *p;
  s.centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3* p : points) {
    const Vec3 d = *p - s.centroid;
    covariance += d * d.transpose();
  }
  covariance /= static_cast<double>(points.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance);
  const Eigen::Vector3d values = eig.eigenvalues().cwiseMax(0.0);
  s.extent_mm = 2.0 * std::sqrt(values(2));
  s.flat = !(values(2) > 0.0) || std::sqrt(values(0)) < 1e-6 * std::sqrt(values(2));
  return s;
}

// Kasa's algebraic fit in coordinates relative to `origin`: |q|^2 = 2 c.q + k, r^2 = k + |c|^2.
bool algebraic_fit(const std::vector<const Vec3*>& points, const Vec3& origin, Vec3& centre,
                   double& radius) {
  Eigen::MatrixXd a(points.size(), 4);
  Eigen::VectorXd b(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 q = *points[i] - origin;
    a.row(static_cast<Eigen::Index>(i)) << 2.0 * q.x(), 2.0 * q.y(), 2.0 * q.z(), 1.0;
    b(static_cast<Eigen::Index>(i)) = q.squaredNorm();
  }
  const Eigen::Vector4d x = a.colPivHouseholderQr().solve(b);
  if (!x.allFinite()) return false;
  centre = origin + x.head<3>();
  const double r2 = x(3) + x.head<3>().squaredNorm();
  if (!(r2 > 0.0)) return false;
  radius = std::sqrt(r2);
  return true;
}

// Levenberg-Marquardt on (c, r_0 .. r_{m-1}); `set[i]` is the radius index of point i.
// Residual |p_i - c| - r_set(i).
int levenberg_marquardt(const std::vector<const Vec3*>& points, const std::vector<int>& set,
                        int num_radii, Vec3& centre, std::vector<double>& radii,
                        const SphereFitOptions& options, bool& converged) {
  const int n = 3 + num_radii;
  auto cost_of = [&](const Vec3& c, const std::vector<double>& r) {
    double cost = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double e = (*points[i] - c).norm() - r[set[i]];
      cost += e * e;
    }
    return cost;
  };
  double lambda = 1e-3;
  double cost = cost_of(centre, radii);
  converged = false;
  int iteration = 0;
  for (; iteration < options.max_iterations; ++iteration) {
    Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd jtr = Eigen::VectorXd::Zero(n);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Vec3 d = *points[i] - centre;
      const double distance = d.norm();
      if (!(distance > 0.0)) continue;
      Eigen::VectorXd row = Eigen::VectorXd::Zero(n);
      row.head<3>() = -d / distance;
      row(3 + set[i]) = -1.0;
      const double e = distance - radii[set[i]];
      jtj.noalias() += row * row.transpose();
      jtr.noalias() += row * e;
    }
    bool improved = false;
    for (int attempt = 0; attempt < 30 && !improved; ++attempt) {
      Eigen::MatrixXd damped = jtj;
      for (int k = 0; k < n; ++k) damped(k, k) += lambda * std::max(jtj(k, k), 1e-12);
      const Eigen::VectorXd step = damped.ldlt().solve(-jtr);
      if (!step.allFinite()) break;
      const Vec3 trial_centre = centre + step.head<3>();
      std::vector<double> trial_radii = radii;
      for (int k = 0; k < num_radii; ++k) trial_radii[k] += step(3 + k);
      const double trial_cost = cost_of(trial_centre, trial_radii);
      if (trial_cost <= cost) {
        const double moved = step.head<3>().norm();
        centre = trial_centre;
        radii = trial_radii;
        const double old_cost = cost;
        cost = trial_cost;
        lambda = std::max(lambda * 0.1, 1e-15);
        improved = true;
        if (moved < options.tolerance_mm || old_cost - cost <= 1e-30 * std::max(1.0, old_cost)) {
          converged = true;
          return iteration + 1;
        }
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) {  // no descent left: at the minimum to round-off
      converged = true;
      return iteration + 1;
    }
  }
  return iteration;
}

void residual_stats(const std::vector<const Vec3*>& points, const std::vector<int>& set,
                    const Vec3& c, const std::vector<double>& r, double& rms, double& max_abs,
                    int only_set = -1) {
  double sum = 0.0;
  std::size_t count = 0;
  max_abs = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (only_set >= 0 && set[i] != only_set) continue;
    const double e = (*points[i] - c).norm() - r[set[i]];
    sum += e * e;
    max_abs = std::max(max_abs, std::abs(e));
    ++count;
  }
  rms = count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

// Sets the flat status on `fit` when the points span no sphere; true if so.
template <typename Fit>
bool reject_flat(const Spread& spread, Fit& fit) {
  if (!spread.flat) return false;
  fit.status = FitStatus::kFlat;
  fit.message = "the points are coplanar or collinear: no sphere fits them";
  return true;
}

}  // namespace

const char* to_string(FitStatus status) {
  switch (status) {
    case FitStatus::kOk: return "ok";
    case FitStatus::kTooFewPoints: return "too few points";
    case FitStatus::kFlat: return "flat";
    case FitStatus::kNotConverged: return "not converged";
  }
  return "unknown";
}

SphereFit fit_sphere(const std::vector<Vec3>& points, const SphereFitOptions& options) {
  SphereFit fit;
  fit.points = points.size();
  if (points.size() < 4) {
    fit.message = "a sphere needs at least 4 points, got " + std::to_string(points.size());
    return fit;
  }
  std::vector<const Vec3*> refs;
  refs.reserve(points.size());
  for (const Vec3& p : points) refs.push_back(&p);
  const Spread spread = spread_of(refs);
  if (reject_flat(spread, fit)) return fit;
  std::vector<double> radii(1, 0.0);
  if (!algebraic_fit(refs, spread.centroid, fit.center_mm, radii[0])) {
    fit.status = FitStatus::kFlat;
    fit.message = "the algebraic sphere fit is singular";
    return fit;
  }
  const std::vector<int> set(points.size(), 0);
  bool converged = true;
  if (options.geometric) {
    fit.iterations = levenberg_marquardt(refs, set, 1, fit.center_mm, radii, options, converged);
  }
  fit.radius_mm = radii[0];
  residual_stats(refs, set, fit.center_mm, radii, fit.rms_mm, fit.max_abs_mm);
  if (!(fit.radius_mm < 1000.0 * spread.extent_mm) || !fit.center_mm.allFinite()) {
    fit.status = FitStatus::kFlat;
    fit.message = "the points are nearly flat: fitted radius " + std::to_string(fit.radius_mm) +
                  " mm over an extent of " + std::to_string(spread.extent_mm) + " mm";
    return fit;
  }
  fit.status = converged ? FitStatus::kOk : FitStatus::kNotConverged;
  if (!converged) fit.message = "Levenberg-Marquardt did not converge";
  return fit;
}

ConcentricSphereFit fit_concentric_spheres(const std::vector<Vec3>& points_a,
                                           const std::vector<Vec3>& points_b,
                                           const SphereFitOptions& options) {
  ConcentricSphereFit fit;
  if (points_a.size() < 2 || points_b.size() < 2 || points_a.size() + points_b.size() < 5) {
    fit.message = "two concentric spheres need at least 5 points, 2 per set";
    return fit;
  }
  std::vector<const Vec3*> refs;
  std::vector<int> set;
  for (const Vec3& p : points_a) { refs.push_back(&p); set.push_back(0); }
  for (const Vec3& p : points_b) { refs.push_back(&p); set.push_back(1); }
  const Spread spread = spread_of(refs);
  if (reject_flat(spread, fit)) return fit;
  // Start: the single-sphere fits of each set when they exist, else the fit of both together.
  std::vector<double> radii(2, 0.0);
  const SphereFit fit_a = fit_sphere(points_a, options);
  const SphereFit fit_b = fit_sphere(points_b, options);
  if (fit_a.ok() && fit_b.ok()) {
    const double wa = static_cast<double>(points_a.size()), wb = static_cast<double>(points_b.size());
    fit.center_mm = (wa * fit_a.center_mm + wb * fit_b.center_mm) / (wa + wb);
  } else {
    double r = 0.0;
    if (!algebraic_fit(refs, spread.centroid, fit.center_mm, r)) {
      fit.status = FitStatus::kFlat;
      fit.message = "the algebraic sphere fit is singular";
      return fit;
    }
  }
  for (int k = 0; k < 2; ++k) {
    double sum = 0.0;
    int count = 0;
    for (std::size_t i = 0; i < refs.size(); ++i) {
      if (set[i] != k) continue;
      sum += (*refs[i] - fit.center_mm).norm();
      ++count;
    }
    radii[k] = sum / count;
  }
  bool converged = true;
  fit.iterations = levenberg_marquardt(refs, set, 2, fit.center_mm, radii, options, converged);
  fit.radius_a_mm = radii[0];
  fit.radius_b_mm = radii[1];
  residual_stats(refs, set, fit.center_mm, radii, fit.rms_mm, fit.max_abs_mm);
  double unused = 0.0;
  residual_stats(refs, set, fit.center_mm, radii, fit.rms_a_mm, unused, 0);
  residual_stats(refs, set, fit.center_mm, radii, fit.rms_b_mm, unused, 1);
  if (!(std::max(radii[0], radii[1]) < 1000.0 * spread.extent_mm) || !fit.center_mm.allFinite()) {
    fit.status = FitStatus::kFlat;
    fit.message = "the points are nearly flat: no concentric spheres fit them";
    return fit;
  }
  fit.status = converged ? FitStatus::kOk : FitStatus::kNotConverged;
  if (!converged) fit.message = "Levenberg-Marquardt did not converge";
  return fit;
}

}  // namespace hipfai::geometry
