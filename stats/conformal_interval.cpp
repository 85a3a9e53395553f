#include "stats/conformal_interval.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hipfai::stats {

ConformalCalibration calibrate_conformal(const std::vector<ConformalRow>& rows, int groups, double nominal) {
  if (!(nominal > 0.0 && nominal < 1.0)) throw_error("conformal calibration: nominal coverage ", nominal, " is not in (0, 1)");
  if (groups < 1) throw_error("conformal calibration: ", groups, " groups; at least 1");
  std::vector<std::vector<double>> scores(static_cast<std::size_t>(groups));
  for (const ConformalRow& row : rows) {
    if (row.group < 0 || row.group >= groups) {
      throw_error("conformal calibration: row group ", row.group, " outside 0..", groups - 1);
    }
    if (!std::isfinite(row.prediction) || !std::isfinite(row.truth) || row.prediction == 0.0) continue;
    scores[static_cast<std::size_t>(row.group)].push_back(std::abs(row.truth - row.prediction) / std::abs(row.prediction));
  }
  ConformalCalibration calibration;
  calibration.nominal = nominal;
  for (auto& group : scores) {
    const std::size_t n = group.size();
    calibration.rows.push_back(n);
    // k = ceil((n + 1) * nominal), 1-based; computed in integers where (n + 1) * nominal is whole.
    const double exact_k = static_cast<double>(n + 1) * nominal;
    std::size_t k = static_cast<std::size_t>(std::ceil(exact_k - 1e-12 * exact_k));
    if (n == 0 || k > n) {
      calibration.half_width.push_back(std::numeric_limits<double>::infinity());
      continue;
    }
    k = std::max<std::size_t>(k, 1);
    std::nth_element(group.begin(), group.begin() + static_cast<std::ptrdiff_t>(k - 1), group.end());
    calibration.half_width.push_back(group[k - 1]);
  }
  return calibration;
}

ConformalInterval conformal_interval(const ConformalCalibration& calibration, double prediction, int group) {
  if (group < 0 || group >= static_cast<int>(calibration.half_width.size())) {
    throw_error("conformal interval: group ", group, " outside the calibration's 0..",
                static_cast<int>(calibration.half_width.size()) - 1);
  }
  ConformalInterval interval;
  interval.relative_half_width = calibration.half_width[static_cast<std::size_t>(group)];
  const double half = interval.relative_half_width * std::abs(prediction);
  interval.lower = prediction - half;
  interval.upper = prediction + half;
  if (std::isinf(interval.relative_half_width)) {
    interval.lower = -std::numeric_limits<double>::infinity();
    interval.upper = std::numeric_limits<double>::infinity();
  }
  return interval;
}

}  // namespace hipfai::stats
