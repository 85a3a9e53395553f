// hipfai — Pearson's correlation coefficient with its two-sided p-value.
#pragma once

#include <span>
#include <string>

namespace hipfai::stats {

struct PearsonResult {
  double r = 0.0;        // correlation coefficient in [-1, 1]
  double p_value = 1.0;  // two-sided, from Student's t with n - 2 degrees of freedom
  int n = 0;             // number of pairs used
  bool defined = false;  // false when n < 3 or either sample has zero variance
};

// Pearson r of paired samples x and y (same length). The p-value tests r = 0 with
// t = r sqrt((n - 2) / (1 - r^2)) against Student's t distribution (GSL).
PearsonResult pearson(std::span<const double> x, std::span<const double> y);

// Verbal band of thesis §4.3.2.5 (after Chan 2003): "poor", "fair", "moderate",
// "moderately strong", "very strong", applied to |r|.
std::string correlation_band(double r);

}  // namespace hipfai::stats
