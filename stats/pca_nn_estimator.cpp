#include "stats/pca_nn_estimator.h"

#include "core/error.h"
#include "core/numbers.h"
#include "stats/pearson.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace hipfai::stats {

namespace {

using hipfai::kNaN;

void check_shapes(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values) {
  if (scores.rows() != values.rows()) {
    throw_error("estimator: ", scores.rows(), " score rows but ", values.rows(), " value rows");
  }
  if (!scores.allFinite()) throw_error("estimator: a training score is not finite");
}

}  // namespace

Eigen::MatrixXd score_value_correlations(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values) {
  check_shapes(scores, values);
  Eigen::MatrixXd correlations(scores.cols(), values.cols());
  std::vector<double> x, y;
  for (Eigen::Index j = 0; j < values.cols(); ++j) {
    for (Eigen::Index k = 0; k < scores.cols(); ++k) {
      x.clear();
      y.clear();
      for (Eigen::Index i = 0; i < values.rows(); ++i) {
        if (!std::isfinite(values(i, j))) continue;
        x.push_back(scores(i, k));
        y.push_back(values(i, j));
      }
      const PearsonResult r = pearson(x, y);
      correlations(k, j) = r.defined ? r.r : kNaN;
    }
  }
  return correlations;
}

std::vector<int> highest_correlated(const Eigen::VectorXd& correlations_at_step, int e_prime) {
  const int e = static_cast<int>(correlations_at_step.size());
  std::vector<int> order(static_cast<std::size_t>(e));
  std::iota(order.begin(), order.end(), 0);
  const auto strength = [&](int k) {
    const double r = correlations_at_step(k);
    return std::isfinite(r) ? std::abs(r) : -1.0;
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return strength(a) > strength(b); });
  order.resize(static_cast<std::size_t>(std::clamp(e_prime, 0, e)));
  return order;
}

int closest_set(const Eigen::MatrixXd& scores, const std::vector<int>& candidates,
                const Eigen::VectorXd& target, int k, int nearest) {
  if (candidates.empty()) throw_error("estimator: no training hip to choose from");
  struct Candidate {
    int row;
    double dist1, dist2;
  };
  std::vector<Candidate> ranked;
  ranked.reserve(candidates.size());
  for (const int i : candidates) {
    const Eigen::VectorXd diff = scores.row(i).transpose() - target;
    const double dist2 = std::abs(diff(k));
    const double dist1 = std::sqrt(std::max(0.0, diff.squaredNorm() - dist2 * dist2));
    ranked.push_back({i, dist1, dist2});
  }
  // Ties by row index so the choice does not depend on the order hips were listed in.
  std::sort(ranked.begin(), ranked.end(), [](const Candidate& a, const Candidate& b) {
    return a.dist1 != b.dist1 ? a.dist1 < b.dist1 : a.row < b.row;
  });
  ranked.resize(std::min<std::size_t>(ranked.size(), static_cast<std::size_t>(std::max(nearest, 1))));
  const auto best = std::min_element(ranked.begin(), ranked.end(), [](const Candidate& a, const Candidate& b) {
    return a.dist2 != b.dist2 ? a.dist2 < b.dist2 : a.row < b.row;
  });
  return best->row;
}

std::vector<PcaNnStep> pca_nn_estimate(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values,
                                       const Eigen::MatrixXd& correlations, const Eigen::VectorXd& target,
                                       const PcaNnOptions& options) {
  check_shapes(scores, values);
  if (target.size() != scores.cols()) {
    throw_error("estimator: target has ", target.size(), " scores, the training ", scores.cols());
  }
  if (!target.allFinite()) throw_error("estimator: a target score is not finite");
  if (options.e_prime < 1) throw_error("estimator: e' = ", options.e_prime, "; need at least 1");
  if (correlations.rows() != scores.cols() || correlations.cols() != values.cols()) {
    throw_error("estimator: correlation matrix is ", correlations.rows(), " x ", correlations.cols(),
                ", expected ", scores.cols(), " x ", values.cols());
  }
  std::vector<PcaNnStep> steps(static_cast<std::size_t>(values.cols()));
  std::vector<int> candidates;
  for (Eigen::Index j = 0; j < values.cols(); ++j) {
    PcaNnStep& step = steps[static_cast<std::size_t>(j)];
    candidates.clear();
    for (Eigen::Index i = 0; i < values.rows(); ++i) {
      if (std::isfinite(values(i, j))) candidates.push_back(static_cast<int>(i));
    }
    if (candidates.empty()) {
      step.estimate = step.low = step.high = kNaN;
      continue;
    }
    step.defined = true;
    step.components = highest_correlated(correlations.col(j), options.e_prime);
    double weighted = 0.0, total_weight = 0.0, plain = 0.0;
    step.low = std::numeric_limits<double>::infinity();
    step.high = -step.low;
    for (const int k : step.components) {
      const int hip = closest_set(scores, candidates, target, k, options.nearest);
      const double r = correlations(k, j);
      const double weight = std::isfinite(r) ? std::abs(r) : 0.0;
      const double value = values(hip, j);
      step.chosen_hips.push_back(hip);
      step.weights.push_back(weight);
      weighted += weight * value;
      total_weight += weight;
      plain += value;
      step.low = std::min(step.low, value);
      step.high = std::max(step.high, value);
    }
    step.estimate = total_weight > 0.0 ? weighted / total_weight
                                       : plain / static_cast<double>(step.components.size());
  }
  return steps;
}

}  // namespace hipfai::stats
