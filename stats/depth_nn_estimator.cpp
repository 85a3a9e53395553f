#include "stats/depth_nn_estimator.h"

#include "core/error.h"
#include "core/numbers.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace hipfai::stats {

namespace {

using hipfai::kNaN;

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

// Hips with a contact-free first step and a positive value there: the reference of their level.
std::vector<bool> usable_hips(const Eigen::MatrixXd& values, const PenetrationDepths& depths) {
  std::vector<bool> usable(static_cast<std::size_t>(values.rows()));
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    usable[static_cast<std::size_t>(i)] = std::isfinite(values(i, 0)) && values(i, 0) > 0.0 && !in_contact(depths, i, 0);
  }
  return usable;
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

// The k hips of `eligible` nearest the target on the first `components` scores (ties: lowest row).
std::vector<Eigen::Index> nearest_hips(const Eigen::MatrixXd& scores, const Eigen::VectorXd& target,
                                       const std::vector<bool>& eligible, int components, int k) {
  const Eigen::Index used = std::min<Eigen::Index>(components, scores.cols());
  std::vector<std::pair<double, Eigen::Index>> by_score;
  for (Eigen::Index i = 0; i < scores.rows(); ++i) {
    if (eligible[static_cast<std::size_t>(i)]) {
      by_score.emplace_back((scores.row(i).head(used).transpose() - target.head(used)).norm(), i);
    }
  }
  std::sort(by_score.begin(), by_score.end());
  by_score.resize(std::min<std::size_t>(by_score.size(), static_cast<std::size_t>(k)));
  std::vector<Eigen::Index> hips;
  for (const auto& [d, i] : by_score) hips.push_back(i);
  return hips;
}

// Mean and range of a list (NaN when empty).
Spread spread_of(const std::vector<double>& xs) {
  Spread out;
  if (xs.empty()) return out;
  out.low = *std::min_element(xs.begin(), xs.end());
  out.high = *std::max_element(xs.begin(), xs.end());
  double sum = 0.0;
  for (const double x : xs) sum += x;
  out.mean = sum / static_cast<double>(xs.size());
  return out;
}

// Level: the first-step values of the given hips.
Spread first_step_level(const Eigen::MatrixXd& values, const std::vector<Eigen::Index>& hips) {
  std::vector<double> firsts;
  for (const Eigen::Index i : hips) firsts.push_back(values(i, 0));
  return spread_of(firsts);
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

// One step of a hip's path through the (curvilinear, radial) depth plane, with its factor.
struct PathPoint {
  double curvilinear, radial, factor;
};

// A usable hip's steps in order (those with a value and a profile), each with its factor.
std::vector<PathPoint> depth_path(const Eigen::MatrixXd& values, const PenetrationDepths& depths,
                                  const Eigen::VectorXd& profile, Eigen::Index hip) {
  std::vector<PathPoint> path;
  for (Eigen::Index j = 0; j < values.cols(); ++j) {
    if (!std::isfinite(values(hip, j)) || !std::isfinite(profile(j))) continue;
    path.push_back({depths.curvilinear_mm(hip, j), depths.radial_mm(hip, j), values(hip, j) / (values(hip, 0) * profile(j))});
  }
  return path;
}

// The factor at the point of the path nearest to (c, r), linear along its segment (ties: the
// earlier segment); a one-point path is that point's factor. The path is not empty.
double path_factor(const std::vector<PathPoint>& path, double c, double r) {
  if (path.size() == 1) return path.front().factor;
  double best_distance = std::numeric_limits<double>::infinity(), best_factor = path.front().factor;
  for (std::size_t s = 0; s + 1 < path.size(); ++s) {
    const PathPoint& a = path[s];
    const PathPoint& b = path[s + 1];
    const double dc = b.curvilinear - a.curvilinear, dr = b.radial - a.radial;
    const double length2 = dc * dc + dr * dr;
    const double t =
        length2 > 0.0 ? std::clamp(((c - a.curvilinear) * dc + (r - a.radial) * dr) / length2, 0.0, 1.0) : 0.0;
    const double distance = std::hypot(c - (a.curvilinear + t * dc), r - (a.radial + t * dr));
    if (distance < best_distance) {
      best_distance = distance;
      best_factor = a.factor + t * (b.factor - a.factor);
    }
  }
  return best_factor;
}

// What both methods start from: the hips usable for training, the course of a step free of
// contact, the k usable hips nearest the target and their first-step level.
struct Basis {
  std::vector<bool> usable;
  Eigen::VectorXd profile;
  std::vector<Eigen::Index> level_hips;
  Spread level;
};

Basis basis_of(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values, const PenetrationDepths& depths,
               const Eigen::VectorXd& target, int components, int k) {
  Basis basis;
  basis.usable = usable_hips(values, depths);
  basis.profile = contact_free_profile(values, depths, basis.usable);
  basis.level_hips = nearest_hips(scores, target, basis.usable, components, k);
  basis.level = first_step_level(values, basis.level_hips);
  return basis;
}

// A step's estimate and interval: the level, carried along the contact-free course, times the
// contact factor.
void set_scaled(RegressionStep& step, const Spread& level, double profile, const Spread& factor) {
  step.estimate = level.mean * profile * factor.mean;
  step.low = level.low * profile * factor.low;
  step.high = level.high * profile * factor.high;
}

}  // namespace

std::vector<RegressionStep> depth_nn_estimate(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values,
                                              const PenetrationDepths& depths, const Eigen::VectorXd& target,
                                              const PenetrationDepths& target_depths, int components, int k) {
  check_shapes(scores, values, depths, target, target_depths, components, k);
  const Eigen::Index p = values.cols();
  std::vector<RegressionStep> steps(static_cast<std::size_t>(p));
  if (p == 0) return steps;

  const Basis basis = basis_of(scores, values, depths, target, components, k);
  const Eigen::VectorXd& profile = basis.profile;
  const Spread& level = basis.level;
  const std::vector<ContactPair> pairs = contact_pairs(values, depths, basis.usable, profile);

  for (Eigen::Index j = 0; j < p; ++j) {
    RegressionStep& step = steps[static_cast<std::size_t>(j)];
    step.estimate = step.low = step.high = kNaN;
    if (!std::isfinite(level.mean) || !std::isfinite(profile(j))) continue;
    Spread factor{1.0, 1.0, 1.0};
    if (in_contact(target_depths, 0, j)) {
      if (pairs.empty()) continue;
      factor = nearest_factor(pairs, target_depths.curvilinear_mm(0, j), target_depths.radial_mm(0, j), k);
    }
    set_scaled(step, level, profile(j), factor);
    step.defined = true;
  }
  return steps;
}

std::vector<RegressionStep> depth_aligned_estimate(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values,
                                                   const PenetrationDepths& depths, const Eigen::VectorXd& target,
                                                   const PenetrationDepths& target_depths, int components, int k) {
  check_shapes(scores, values, depths, target, target_depths, components, k);
  const Eigen::Index p = values.cols();
  std::vector<RegressionStep> steps(static_cast<std::size_t>(p));
  if (p == 0) return steps;

  const Basis basis = basis_of(scores, values, depths, target, components, k);
  const Eigen::VectorXd& profile = basis.profile;
  const Spread& level = basis.level;

  // The hips with a factor at some step (depth_nn's contact pairs), and the k nearest of them.
  std::vector<bool> penetrating(static_cast<std::size_t>(values.rows()), false);
  for (const ContactPair& pair : contact_pairs(values, depths, basis.usable, profile)) {
    penetrating[static_cast<std::size_t>(pair.hip)] = true;
  }
  std::vector<std::vector<PathPoint>> paths;
  for (const Eigen::Index i : nearest_hips(scores, target, penetrating, components, k)) {
    paths.push_back(depth_path(values, depths, profile, i));
  }

  for (Eigen::Index j = 0; j < p; ++j) {
    RegressionStep& step = steps[static_cast<std::size_t>(j)];
    step.estimate = step.low = step.high = kNaN;
    if (!in_contact(target_depths, 0, j)) {
      std::vector<double> products;
      for (const Eigen::Index i : basis.level_hips) {
        const bool own = std::isfinite(values(i, j)) && !in_contact(depths, i, j);
        const double course = own ? values(i, j) / values(i, 0) : profile(j);
        if (std::isfinite(course)) products.push_back(values(i, 0) * course);
      }
      const Spread free = spread_of(products);
      if (!std::isfinite(free.mean)) continue;
      step.estimate = free.mean;
      step.low = free.low;
      step.high = free.high;
    } else {
      if (!std::isfinite(level.mean) || !std::isfinite(profile(j)) || paths.empty()) continue;
      std::vector<double> factors;
      for (const std::vector<PathPoint>& path : paths) {
        factors.push_back(path_factor(path, target_depths.curvilinear_mm(0, j), target_depths.radial_mm(0, j)));
      }
      set_scaled(step, level, profile(j), spread_of(factors));
    }
    step.defined = true;
  }
  return steps;
}

}  // namespace hipfai::stats
