#include "stats/interval_coverage.h"

#include "core/error.h"

#include <gsl/gsl_cdf.h>

#include <cmath>
#include <limits>

namespace hipfai::stats {

CoverageResult interval_coverage(const std::vector<IntervalRow>& rows, double relative_error_threshold) {
  if (!std::isfinite(relative_error_threshold) || relative_error_threshold < 0.0) {
    throw_error("interval coverage: relative error threshold ", relative_error_threshold,
                " must be finite and not negative");
  }
  CoverageResult result;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const IntervalRow& row = rows[i];
    if (!std::isfinite(row.prediction) || !std::isfinite(row.truth)) {
      ++result.skipped;
      continue;
    }
    if (!std::isfinite(row.lower) || !std::isfinite(row.upper) || row.lower > row.upper) {
      throw_error("interval coverage: row ", i + 1, " has interval [", row.lower, ", ", row.upper,
                  "]; lower must not exceed upper, both finite");
    }
    ++result.rows;
    result.covered += row.lower <= row.truth && row.truth <= row.upper;
    result.flagged += row.flagged;
    const double error = std::abs(row.prediction - row.truth);
    const double relative = row.truth != 0.0 ? error / std::abs(row.truth)
                                             : (error == 0.0 ? 0.0 : std::numeric_limits<double>::infinity());
    if (relative > relative_error_threshold) {
      ++result.large_error;
      result.large_error_flagged += row.flagged;
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  result.coverage = result.rows > 0 ? static_cast<double>(result.covered) / static_cast<double>(result.rows) : nan;
  result.flag_recall = result.large_error > 0 ? static_cast<double>(result.large_error_flagged) /
                                                    static_cast<double>(result.large_error)
                                              : nan;
  return result;
}

CountInterval binomial_acceptance_interval(double nominal, std::size_t n, double alpha) {
  if (!(nominal > 0.0 && nominal < 1.0)) throw_error("binomial acceptance interval: nominal ", nominal, " must be in (0, 1)");
  if (!(alpha > 0.0 && alpha < 1.0)) throw_error("binomial acceptance interval: alpha ", alpha, " must be in (0, 1)");
  if (n == 0) throw_error("binomial acceptance interval: no rows");
  const auto trials = static_cast<unsigned>(n);
  CountInterval interval;
  // low: the first count with P(X <= low) > alpha/2, so P(X < low) <= alpha/2.
  while (interval.low < n && gsl_cdf_binomial_P(static_cast<unsigned>(interval.low), nominal, trials) <= alpha / 2) {
    ++interval.low;
  }
  // high: the smallest count with P(X > high) <= alpha/2.
  interval.high = n;
  while (interval.high > 0 && gsl_cdf_binomial_Q(static_cast<unsigned>(interval.high - 1), nominal, trials) <= alpha / 2) {
    --interval.high;
  }
  return interval;
}

}  // namespace hipfai::stats
