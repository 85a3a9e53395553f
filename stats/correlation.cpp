#include "stats/correlation.h"

#include "core/error.h"

#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hipfai::stats {

std::vector<double> average_ranks(std::span<const double> values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(values.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i + 1;
    while (j < order.size() && values[order[j]] == values[order[i]]) ++j;
    // Positions i..j-1 (0-based) share the mean of ranks i+1..j.
    const double rank = 0.5 * (static_cast<double>(i + 1) + static_cast<double>(j));
    for (std::size_t k = i; k < j; ++k) ranks[order[k]] = rank;
    i = j;
  }
  return ranks;
}

PearsonResult spearman(std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size()) {
    throw_error("spearman: samples differ in length (", x.size(), " and ", y.size(), ")");
  }
  const std::vector<double> rx = average_ranks(x), ry = average_ranks(y);
  return pearson(rx, ry);
}

CorrelationInterval fisher_interval(double r, int n, double level) {
  CorrelationInterval interval;
  if (n < 4 || !(std::abs(r) < 1.0) || !(level > 0.0 && level < 1.0)) return interval;
  const double z = std::atanh(r);
  const double half = gsl_cdf_ugaussian_Pinv(0.5 * (1.0 + level)) / std::sqrt(n - 3.0);
  interval.low = std::tanh(z - half);
  interval.high = std::tanh(z + half);
  interval.defined = true;
  return interval;
}

CorrelationSummary correlate(std::span<const double> x, std::span<const double> y) {
  CorrelationSummary summary;
  summary.n = static_cast<int>(x.size());
  summary.pearson = pearson(x, y);
  summary.spearman = spearman(x, y);
  if (summary.n < 3) {
    summary.status = "too few";
  } else if (!summary.pearson.defined) {
    summary.status = "constant";
  } else {
    summary.status = "ok";
    summary.interval = fisher_interval(summary.pearson.r, summary.n);
  }
  return summary;
}

}  // namespace hipfai::stats
