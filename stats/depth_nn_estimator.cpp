#include "stats/depth_nn_estimator.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace hipfai::stats {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool finite_depths(const PenetrationDepths& d) {
  return d.curvilinear_mm.allFinite() && d.radial_mm.allFinite();
}

bool in_contact(const PenetrationDepths& d, Eigen::Index row, Eigen::Index step) {
  return d.curvilinear_mm(row, step) > 0.0 || d.radial_mm(row, step) > 0.0;
}

}  // namespace

std::vector<RegressionStep> depth_nn_estimate(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values,
                                              const PenetrationDepths& depths, const Eigen::VectorXd& target,
                                              const PenetrationDepths& target_depths, int components, int k) {
  const Eigen::Index m = values.rows(), p = values.cols();
  if (scores.rows() != m || target.size() != scores.cols() || depths.curvilinear_mm.rows() != m ||
      depths.curvilinear_mm.cols() != p || depths.radial_mm.rows() != m || depths.radial_mm.cols() != p ||
      target_depths.curvilinear_mm.rows() != 1 || target_depths.curvilinear_mm.cols() != p ||
      target_depths.radial_mm.rows() != 1 || target_depths.radial_mm.cols() != p) {
    throw_error("depth_nn: shapes differ (", m, " x ", p, " values, ", scores.rows(), " score rows, ",
                depths.curvilinear_mm.rows(), " x ", depths.curvilinear_mm.cols(), " training depths, ",
                target_depths.curvilinear_mm.cols(), " target steps)");
  }
  if (k < 1 || components < 1) throw_error("depth_nn: k = ", k, ", components = ", components);
  if (!finite_depths(depths) || !finite_depths(target_depths)) {
    throw_error("depth_nn: penetration depths unknown for some hip or step (the method needs both depths at "
                "every step)");
  }
  std::vector<RegressionStep> steps(static_cast<std::size_t>(p));
  if (p == 0) return steps;

  // Hips with a contact-free first step and a positive value there: the reference of their level.
  std::vector<bool> usable(static_cast<std::size_t>(m));
  for (Eigen::Index i = 0; i < m; ++i) {
    usable[static_cast<std::size_t>(i)] = std::isfinite(values(i, 0)) && values(i, 0) > 0.0 && !in_contact(depths, i, 0);
  }

  // Contact-free profile.
  Eigen::VectorXd profile = Eigen::VectorXd::Constant(p, kNaN);
  for (Eigen::Index j = 0; j < p; ++j) {
    double sum = 0.0;
    int count = 0;
    for (Eigen::Index i = 0; i < m; ++i) {
      if (!usable[static_cast<std::size_t>(i)] || !std::isfinite(values(i, j)) || in_contact(depths, i, j)) continue;
      sum += values(i, j) / values(i, 0);
      ++count;
    }
    if (count > 0) profile(j) = sum / count;
  }

  // Level: the k nearest usable hips on the first `components` scores.
  const Eigen::Index used = std::min<Eigen::Index>(components, scores.cols());
  std::vector<std::pair<double, Eigen::Index>> by_score;
  for (Eigen::Index i = 0; i < m; ++i) {
    if (usable[static_cast<std::size_t>(i)]) {
      by_score.emplace_back((scores.row(i).head(used).transpose() - target.head(used)).norm(), i);
    }
  }
  std::sort(by_score.begin(), by_score.end());
  by_score.resize(std::min<std::size_t>(by_score.size(), static_cast<std::size_t>(k)));
  double level = kNaN, level_low = kNaN, level_high = kNaN;
  if (!by_score.empty()) {
    double sum = 0.0;
    level_low = std::numeric_limits<double>::infinity();
    level_high = -level_low;
    for (const auto& [d, i] : by_score) {
      sum += values(i, 0);
      level_low = std::min(level_low, values(i, 0));
      level_high = std::max(level_high, values(i, 0));
    }
    level = sum / static_cast<double>(by_score.size());
  }

  // Impingement factors of the training (hip, step) pairs in contact.
  struct Pair {
    double curvilinear, radial, factor;
    Eigen::Index hip, step;
  };
  std::vector<Pair> pairs;
  for (Eigen::Index i = 0; i < m; ++i) {
    if (!usable[static_cast<std::size_t>(i)]) continue;
    for (Eigen::Index j = 0; j < p; ++j) {
      if (!in_contact(depths, i, j) || !std::isfinite(values(i, j)) || !std::isfinite(profile(j))) continue;
      pairs.push_back({depths.curvilinear_mm(i, j), depths.radial_mm(i, j), values(i, j) / (values(i, 0) * profile(j)),
                       i, j});
    }
  }

  for (Eigen::Index j = 0; j < p; ++j) {
    RegressionStep& step = steps[static_cast<std::size_t>(j)];
    step.estimate = step.low = step.high = kNaN;
    if (!std::isfinite(level) || !std::isfinite(profile(j))) continue;
    double factor = 1.0, factor_low = 1.0, factor_high = 1.0;
    if (in_contact(target_depths, 0, j)) {
      if (pairs.empty()) continue;
      const double c = target_depths.curvilinear_mm(0, j), r = target_depths.radial_mm(0, j);
      std::vector<std::tuple<double, Eigen::Index, Eigen::Index, double>> nearest;
      for (const Pair& pair : pairs) {
        nearest.emplace_back(std::hypot(pair.curvilinear - c, pair.radial - r), pair.hip, pair.step, pair.factor);
      }
      const auto count = std::min<std::size_t>(nearest.size(), static_cast<std::size_t>(k));
      std::partial_sort(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(count), nearest.end());
      double sum = 0.0;
      factor_low = std::numeric_limits<double>::infinity();
      factor_high = -factor_low;
      for (std::size_t n = 0; n < count; ++n) {
        const double f = std::get<3>(nearest[n]);
        sum += f;
        factor_low = std::min(factor_low, f);
        factor_high = std::max(factor_high, f);
      }
      factor = sum / static_cast<double>(count);
    }
    step.estimate = level * profile(j) * factor;
    step.low = level_low * profile(j) * factor_low;
    step.high = level_high * profile(j) * factor_high;
    step.defined = true;
  }
  return steps;
}

}  // namespace hipfai::stats
