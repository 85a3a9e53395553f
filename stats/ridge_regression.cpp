#include "stats/ridge_regression.h"

#include "core/error.h"
#include "core/numbers.h"

#include <Eigen/Cholesky>
#include <gsl/gsl_cdf.h>

#include <cmath>
#include <limits>

namespace hipfai::stats {

std::vector<RegressionStep> ridge_estimate(const Eigen::MatrixXd& scores, const Eigen::VectorXd& score_sd,
                                           const Eigen::MatrixXd& values, const Eigen::VectorXd& target,
                                           int components, std::vector<RidgeStepFit>* fits) {
  if (scores.rows() != values.rows() || target.size() != scores.cols() || score_sd.size() != scores.cols()) {
    throw_error("ridge: shapes differ (", scores.rows(), " x ", scores.cols(), " scores, ", values.rows(),
                " value rows, ", target.size(), " target scores, ", score_sd.size(), " deviations)");
  }
  if (components < 1) throw_error("ridge: components = ", components);
  using hipfai::kNaN;
  const Eigen::Index used = std::min<Eigen::Index>(components, scores.cols());
  Eigen::VectorXd sd = score_sd.head(used);
  for (Eigen::Index k = 0; k < used; ++k) {
    if (!(sd(k) > 0.0)) sd(k) = 1.0;
  }
  const Eigen::MatrixXd all = scores.leftCols(used).array().rowwise() / sd.transpose().array();
  const Eigen::VectorXd z0_raw = target.head(used).array() / sd.array();

  std::vector<RegressionStep> steps(static_cast<std::size_t>(values.cols()));
  if (fits) fits->assign(static_cast<std::size_t>(values.cols()), RidgeStepFit{});
  for (Eigen::Index j = 0; j < values.cols(); ++j) {
    RegressionStep& step = steps[static_cast<std::size_t>(j)];
    std::vector<Eigen::Index> rows;
    for (Eigen::Index i = 0; i < values.rows(); ++i) {
      if (std::isfinite(values(i, j))) rows.push_back(i);
    }
    const auto n = static_cast<Eigen::Index>(rows.size());
    if (n < 2) {
      step.estimate = step.low = step.high = kNaN;
      continue;
    }
    Eigen::MatrixXd z(n, used);
    Eigen::VectorXd y(n);
    for (Eigen::Index r = 0; r < n; ++r) {
      z.row(r) = all.row(rows[static_cast<std::size_t>(r)]);
      y(r) = values(rows[static_cast<std::size_t>(r)], j);
    }
    const Eigen::RowVectorXd z_mean = z.colwise().mean();
    const double y_mean = y.mean();
    z.rowwise() -= z_mean;
    y.array() -= y_mean;
    const Eigen::MatrixXd gram = z.transpose() * z;
    double best_error = std::numeric_limits<double>::infinity();
    double best_lambda = 1.0;
    for (int g = 0; g <= 12; ++g) {
      const double lambda = std::pow(10.0, -3.0 + 0.5 * g);
      const Eigen::LDLT<Eigen::MatrixXd> solver(gram + lambda * Eigen::MatrixXd::Identity(used, used));
      const Eigen::MatrixXd hat = z * solver.solve(z.transpose());
      const Eigen::VectorXd residual = y - hat * y;
      double error = 0.0;
      for (Eigen::Index r = 0; r < n; ++r) {
        // Centring makes each hat diagonal 1/n larger for the intercept.
        const double leverage = hat(r, r) + 1.0 / static_cast<double>(n);
        const double loo = leverage < 1.0 ? residual(r) / (1.0 - leverage) : residual(r);
        error += loo * loo;
      }
      if (error < best_error) {
        best_error = error;
        best_lambda = lambda;
      }
    }
    const Eigen::LDLT<Eigen::MatrixXd> solver(gram + best_lambda * Eigen::MatrixXd::Identity(used, used));
    const Eigen::VectorXd weights = solver.solve(z.transpose() * y);
    const Eigen::MatrixXd hat = z * solver.solve(z.transpose());
    const double df = hat.trace();
    const double rss = (y - z * weights).squaredNorm();
    const Eigen::VectorXd z0 = z0_raw - z_mean.transpose();
    step.estimate = y_mean + z0.dot(weights);
    step.defined = true;
    const double dof = static_cast<double>(n) - 1.0 - df;
    // Below one degree of freedom the t quantile is unbounded (and GSL's inverse does not converge).
    if (dof >= 1.0) {
      const double s2 = rss / dof;
      const double spread = std::sqrt(s2 * (1.0 + 1.0 / static_cast<double>(n) + z0.dot(solver.solve(z0))));
      const double t = gsl_cdf_tdist_Pinv(0.975, dof);
      step.low = step.estimate - t * spread;
      step.high = step.estimate + t * spread;
    } else {
      step.low = step.high = kNaN;
    }
    if (fits) (*fits)[static_cast<std::size_t>(j)] = {best_lambda, std::sqrt(best_error / static_cast<double>(n))};
  }
  return steps;
}

}  // namespace hipfai::stats
