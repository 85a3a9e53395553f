// hipfai — which candidate hips to add to a training set next: the ones whose predictions are
// least certain (uncertainty sampling, the simplest active-learning rule). Two measures of a
// candidate's uncertainty over the steps of the motion:
//   kIntervalWidth       the mean over steps of its interval's width, high - low (in the
//                        estimated quantity's unit, e.g. MPa: a wide interval = the neighbours
//                        the estimate came from disagree);
//   kMethodDisagreement  the mean over steps of the range (max - min) of the estimates of several
//                        methods (pca_nn, knn, ridge, depth_nn): where methods built on different
//                        assumptions disagree, at least one of them is wrong.
// Steps whose values are not finite (a method undefined there) are left out of the mean; a
// candidate with no usable step scores NaN and is never picked.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace hipfai::stats {

enum class UncertaintyCriterion { kIntervalWidth, kMethodDisagreement };
inline constexpr std::array<UncertaintyCriterion, 2> kUncertaintyCriteria{UncertaintyCriterion::kIntervalWidth,
                                                                          UncertaintyCriterion::kMethodDisagreement};
// "width", "disagreement".
const char* to_string(UncertaintyCriterion criterion);
// Throws hipfai::Error "unknown criterion 'x' (known: width, disagreement)".
UncertaintyCriterion parse_uncertainty_criterion(const std::string& name);

// One candidate's predictions over the steps.
struct CandidatePrediction {
  std::vector<double> low, high;               // per step, the interval (kIntervalWidth)
  std::vector<std::vector<double>> estimates;  // per method, per step (kMethodDisagreement)
};

// The candidate's uncertainty (header comment); NaN when no step is usable. Throws hipfai::Error
// when low and high differ in length, an interval has low > high, or the methods' estimates differ
// in length.
double uncertainty_score(const CandidatePrediction& candidate, UncertaintyCriterion criterion);

// The indices of the `budget` candidates with the largest scores, largest first (ties: the lower
// index first); fewer when fewer candidates have a score. Throws on budget < 1.
std::vector<std::size_t> least_certain(const std::vector<CandidatePrediction>& candidates,
                                       UncertaintyCriterion criterion, int budget);

}  // namespace hipfai::stats
