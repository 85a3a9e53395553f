// hipfai — rank correlation, confidence interval and a per-series summary for the validation
// reports (thesis Tables 8-9 report Pearson r and p; Spearman's rho and the Fisher-z interval are
// the robust companions a reader expects beside them).
#pragma once

#include "stats/pearson.h"

#include <span>
#include <string>
#include <vector>

namespace hipfai::stats {

// Ranks 1..n of `values`, ties given the mean of the ranks they span.
std::vector<double> average_ranks(std::span<const double> values);

// Spearman's rho: Pearson's r of the average ranks (exact with ties), and its two-sided p from
// Student's t with n - 2 degrees of freedom (the usual large-sample approximation).
PearsonResult spearman(std::span<const double> x, std::span<const double> y);

// Two-sided confidence interval for a correlation r from n pairs by Fisher's z transform:
// tanh(atanh(r) -+ q / sqrt(n - 3)), q the standard normal quantile of (1 + level) / 2.
struct CorrelationInterval {
  double low = -1.0, high = 1.0;
  bool defined = false;  // false when n < 4 or |r| >= 1
};
CorrelationInterval fisher_interval(double r, int n, double level = 0.95);

// One paired series, all of the above, with a status a report prints: "ok", or "constant" when
// either series has no variance (r undefined), or "too few" when n < 3.
struct CorrelationSummary {
  int n = 0;
  PearsonResult pearson;
  PearsonResult spearman;
  CorrelationInterval interval;  // of Pearson's r, 95 %
  std::string status;
};
CorrelationSummary correlate(std::span<const double> x, std::span<const double> y);

}  // namespace hipfai::stats
