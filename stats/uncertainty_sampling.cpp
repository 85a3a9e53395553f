#include "stats/uncertainty_sampling.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace hipfai::stats {
namespace {

double mean_width(const CandidatePrediction& candidate) {
  if (candidate.low.size() != candidate.high.size()) {
    throw_error("uncertainty: ", candidate.low.size(), " lower ends but ", candidate.high.size(), " upper ends");
  }
  double sum = 0.0;
  int used = 0;
  for (std::size_t j = 0; j < candidate.low.size(); ++j) {
    if (!std::isfinite(candidate.low[j]) || !std::isfinite(candidate.high[j])) continue;
    if (candidate.low[j] > candidate.high[j]) {
      throw_error("uncertainty: step ", j + 1, " has interval [", candidate.low[j], ", ", candidate.high[j], "]");
    }
    sum += candidate.high[j] - candidate.low[j];
    ++used;
  }
  return used > 0 ? sum / used : std::numeric_limits<double>::quiet_NaN();
}

double mean_disagreement(const CandidatePrediction& candidate) {
  if (candidate.estimates.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t steps = candidate.estimates.front().size();
  for (const auto& method : candidate.estimates) {
    if (method.size() != steps) throw_error("uncertainty: the methods' estimates cover different numbers of steps");
  }
  double sum = 0.0;
  int used = 0;
  for (std::size_t j = 0; j < steps; ++j) {
    double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
    int methods = 0;
    for (const auto& method : candidate.estimates) {
      if (!std::isfinite(method[j])) continue;
      lowest = std::min(lowest, method[j]);
      highest = std::max(highest, method[j]);
      ++methods;
    }
    // A range needs two methods at the step.
    if (methods < 2) continue;
    sum += highest - lowest;
    ++used;
  }
  return used > 0 ? sum / used : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

const char* to_string(UncertaintyCriterion criterion) {
  return criterion == UncertaintyCriterion::kIntervalWidth ? "width" : "disagreement";
}

UncertaintyCriterion parse_uncertainty_criterion(const std::string& name) {
  for (const UncertaintyCriterion criterion : kUncertaintyCriteria) {
    if (name == to_string(criterion)) return criterion;
  }
  throw_error("unknown criterion '", name, "' (known: width, disagreement)");
}

double uncertainty_score(const CandidatePrediction& candidate, UncertaintyCriterion criterion) {
  return criterion == UncertaintyCriterion::kIntervalWidth ? mean_width(candidate) : mean_disagreement(candidate);
}

std::vector<std::size_t> least_certain(const std::vector<CandidatePrediction>& candidates,
                                       UncertaintyCriterion criterion, int budget) {
  if (budget < 1) throw_error("uncertainty: budget ", budget, " must be at least 1");
  std::vector<double> scores;
  std::vector<std::size_t> order;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    scores.push_back(uncertainty_score(candidates[c], criterion));
    if (std::isfinite(scores.back())) order.push_back(c);
  }
  std::stable_sort(order.begin(), order.end(), [&scores](std::size_t a, std::size_t b) { return scores[a] > scores[b]; });
  if (order.size() > static_cast<std::size_t>(budget)) order.resize(static_cast<std::size_t>(budget));
  return order;
}

}  // namespace hipfai::stats
