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

// The inputs agree in shape, k and components are positive and every depth is known.
void check_shapes(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values, const PenetrationDepths& depths,
                  const Eigen::VectorXd& target, const PenetrationDepths& target_depths, int components, int k) {
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
}

// Contact-free profile: per step, the mean over usable hips out of contact of the value relative
// to the hip's first step.
Eigen::VectorXd contact_free_profile(const Eigen::MatrixXd& values, const PenetrationDepths& depths,
                                     const std::vector<bool>& usable) {
  const Eigen::Index m = values.rows(), p = values.cols();
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
  return profile;
}

// A mean with the range of what it averages (NaN when empty).
struct Spread {
  double mean = kNaN, low = kNaN, high = kNaN;
};

// Level: the first-step values of the k nearest usable hips on the first `components` scores.
Spread nearest_level(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values, const Eigen::VectorXd& target,
                     const std::vector<bool>& usable, int components, int k) {
  const Eigen::Index m = values.rows();
  const Eigen::Index used = std::min<Eigen::Index>(components, scores.cols());
  std::vector<std::pair<double, Eigen::Index>> by_score;
  for (Eigen::Index i = 0; i < m; ++i) {
    if (usable[static_cast<std::size_t>(i)]) {
      by_score.emplace_back((scores.row(i).head(used).transpose() - target.head(used)).norm(), i);
    }
  }
  std::sort(by_score.begin(), by_score.end());
  by_score.resize(std::min<std::size_t>(by_score.size(), static_cast<std::size_t>(k)));
  Spread level;
  if (!by_score.empty()) {
    double sum = 0.0;
    level.low = std::numeric_limits<double>::infinity();
    level.high = -level.low;
    for (const auto& [d, i] : by_score) {
      sum += values(i, 0);
      level.low = std::min(level.low, values(i, 0));
      level.high = std::max(level.high, values(i, 0));
    }
    level.mean = sum / static_cast<double>(by_score.size());
  }
  return level;
}

// Impingement factor of a training (hip, step) pair in contact: its value over the level and
// the profile's.
struct ContactPair {
  double curvilinear, radial, factor;
  Eigen::Index hip, step;
};

std::vector<ContactPair> contact_pairs(const Eigen::MatrixXd& values, const PenetrationDepths& depths,
                                       const std::vector<bool>& usable, const Eigen::VectorXd& profile) {
  const Eigen::Index m = values.rows(), p = values.cols();
  std::vector<ContactPair> pairs;
  for (Eigen::Index i = 0; i < m; ++i) {
    if (!usable[static_cast<std::size_t>(i)]) continue;
    for (Eigen::Index j = 0; j < p; ++j) {
      if (!in_contact(depths, i, j) || !std::isfinite(values(i, j)) || !std::isfinite(profile(j))) continue;
      pairs.push_back({depths.curvilinear_mm(i, j), depths.radial_mm(i, j), values(i, j) / (values(i, 0) * profile(j)),
                       i, j});
    }
  }
  return pairs;
}

// The mean factor of the k pairs nearest to the target's depths (c, r), and its range.
Spread nearest_factor(const std::vector<ContactPair>& pairs, double c, double r, int k) {
  std::vector<std::tuple<double, Eigen::Index, Eigen::Index, double>> nearest;
  for (const ContactPair& pair : pairs) {
    nearest.emplace_back(std::hypot(pair.curvilinear - c, pair.radial - r), pair.hip, pair.step, pair.factor);
  }
  const auto count = std::min<std::size_t>(nearest.size(), static_cast<std::size_t>(k));
  std::partial_sort(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(count), nearest.end());
  double sum = 0.0;
  Spread factor;
  factor.low = std::numeric_limits<double>::infinity();
  factor.high = -factor.low;
  for (std::size_t n = 0; n < count; ++n) {
    const double f = std::get<3>(nearest[n]);
    sum += f;
    factor.low = std::min(factor.low, f);
    factor.high = std::max(factor.high, f);
  }
  factor.mean = sum / static_cast<double>(count);
  return factor;
}

}  // namespace

std::vector<RegressionStep> depth_nn_estimate(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values,
                                              const PenetrationDepths& depths, const Eigen::VectorXd& target,
                                              const PenetrationDepths& target_depths, int components, int k) {
  check_shapes(scores, values, depths, target, target_depths, components, k);
  const Eigen::Index m = values.rows(), p = values.cols();
  std::vector<RegressionStep> steps(static_cast<std::size_t>(p));
  if (p == 0) return steps;

  // Hips with a contact-free first step and a positive value there: the reference of their level.
  std::vector<bool> usable(static_cast<std::size_t>(m));
  for (Eigen::Index i = 0; i < m; ++i) {
    usable[static_cast<std::size_t>(i)] = std::isfinite(values(i, 0)) && values(i, 0) > 0.0 && !in_contact(depths, i, 0);
  }
  const Eigen::VectorXd profile = contact_free_profile(values, depths, usable);
  const Spread level = nearest_level(scores, values, target, usable, components, k);
  const std::vector<ContactPair> pairs = contact_pairs(values, depths, usable, profile);

  for (Eigen::Index j = 0; j < p; ++j) {
    RegressionStep& step = steps[static_cast<std::size_t>(j)];
    step.estimate = step.low = step.high = kNaN;
    if (!std::isfinite(level.mean) || !std::isfinite(profile(j))) continue;
    Spread factor{1.0, 1.0, 1.0};
    if (in_contact(target_depths, 0, j)) {
      if (pairs.empty()) continue;
      factor = nearest_factor(pairs, target_depths.curvilinear_mm(0, j), target_depths.radial_mm(0, j), k);
    }
    step.estimate = level.mean * profile(j) * factor.mean;
    step.low = level.low * profile(j) * factor.low;
    step.high = level.high * profile(j) * factor.high;
    step.defined = true;
  }
  return steps;
}

}  // namespace hipfai::stats
