#include "stats/pearson.h"

#include "core/error.h"

#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>

namespace hipfai::stats {

PearsonResult pearson(std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size()) {
    throw_error("pearson: samples differ in length (", x.size(), " and ", y.size(), ")");
  }
  PearsonResult result;
  result.n = static_cast<int>(x.size());
  if (result.n < 3) return result;
  double mean_x = 0.0, mean_y = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mean_x += x[i];
    mean_y += y[i];
  }
  mean_x /= result.n;
  mean_y /= result.n;
  double sxx = 0.0, syy = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double dx = x[i] - mean_x, dy = y[i] - mean_y;
    sxx += dx * dx;
    syy += dy * dy;
    sxy += dx * dy;
  }
  if (sxx <= 0.0 || syy <= 0.0) return result;
  result.r = std::clamp(sxy / std::sqrt(sxx * syy), -1.0, 1.0);
  result.defined = true;
  const double dof = result.n - 2.0;
  if (std::abs(result.r) >= 1.0) {
    result.p_value = 0.0;
  } else {
    const double t = result.r * std::sqrt(dof / (1.0 - result.r * result.r));
    result.p_value = 2.0 * gsl_cdf_tdist_Q(std::abs(t), dof);
  }
  return result;
}

std::string correlation_band(double r) {
  const double a = std::abs(r);
  if (a <= 0.3) return "poor";
  if (a <= 0.5) return "fair";
  if (a <= 0.6) return "moderate";
  if (a <= 0.8) return "moderately strong";
  return "very strong";
}

}  // namespace hipfai::stats
