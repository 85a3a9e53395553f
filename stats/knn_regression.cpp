#include "stats/knn_regression.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace hipfai::stats {

std::vector<RegressionStep> knn_estimate(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values,
                                         const Eigen::VectorXd& target, int components, int k) {
  if (scores.rows() != values.rows() || target.size() != scores.cols()) {
    throw_error("knn: shapes differ (", scores.rows(), " x ", scores.cols(), " scores, ", values.rows(),
                " value rows, ", target.size(), " target scores)");
  }
  if (k < 1 || components < 1) throw_error("knn: k = ", k, ", components = ", components);
  const Eigen::Index used = std::min<Eigen::Index>(components, scores.cols());
  std::vector<std::pair<double, int>> distance(static_cast<std::size_t>(scores.rows()));
  for (Eigen::Index i = 0; i < scores.rows(); ++i) {
    distance[static_cast<std::size_t>(i)] = {(scores.row(i).head(used).transpose() - target.head(used)).norm(),
                                             static_cast<int>(i)};
  }
  std::sort(distance.begin(), distance.end());
  std::vector<RegressionStep> steps(static_cast<std::size_t>(values.cols()));
  for (Eigen::Index j = 0; j < values.cols(); ++j) {
    RegressionStep& step = steps[static_cast<std::size_t>(j)];
    double sum = 0.0;
    int count = 0;
    step.low = std::numeric_limits<double>::infinity();
    step.high = -step.low;
    for (const auto& [d, row] : distance) {
      const double value = values(row, j);
      if (!std::isfinite(value)) continue;
      sum += value;
      step.low = std::min(step.low, value);
      step.high = std::max(step.high, value);
      if (++count == k) break;
    }
    step.defined = count > 0;
    if (!step.defined) step.estimate = step.low = step.high = std::numeric_limits<double>::quiet_NaN();
    else step.estimate = sum / count;
  }
  return steps;
}

}  // namespace hipfai::stats
