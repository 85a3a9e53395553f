// hipfai — do an estimator's intervals and its flag mean what they say? Measured on rows of
// (prediction, lower, upper, truth, flagged), e.g. every (held-out hip, step) against its FE value:
//   coverage     the share of rows whose truth lies in [lower, upper] (ends included), to compare
//                with the intervals' nominal coverage;
//   flag recall  among the rows whose relative error |prediction - truth| / |truth| exceeds a
//                threshold, the share that carry the flag (a flag meant to warn of large errors
//                should be on them). A truth of 0 makes any non-zero prediction's error infinite and
//                an exact 0 prediction's error 0.
// Rows with a non-finite prediction or truth (a missing FE step) are skipped and counted.
#pragma once

#include <cstddef>
#include <vector>

namespace hipfai::stats {

struct IntervalRow {
  double prediction = 0.0;
  double lower = 0.0, upper = 0.0;  // lower <= upper
  double truth = 0.0;
  bool flagged = false;
};

struct CoverageResult {
  std::size_t rows = 0;                 // rows counted (finite prediction and truth)
  std::size_t skipped = 0;              // rows left out (non-finite prediction or truth)
  std::size_t covered = 0;              // lower <= truth <= upper
  double coverage = 0.0;                // covered / rows; NaN when rows == 0
  std::size_t flagged = 0;              // counted rows with the flag
  std::size_t large_error = 0;          // counted rows with relative error > threshold
  std::size_t large_error_flagged = 0;  // of those, flagged
  double flag_recall = 0.0;             // large_error_flagged / large_error; NaN when large_error == 0
};

// Throws hipfai::Error when a counted row has lower > upper or a non-finite bound, or when
// `relative_error_threshold` is negative or not finite.
CoverageResult interval_coverage(const std::vector<IntervalRow>& rows, double relative_error_threshold);

// The counts of covered rows consistent with a nominal coverage: the central interval [low, high]
// of Binomial(n, nominal) holding at least 1 - alpha of its probability (each tail beyond it at
// most alpha / 2; exact, GSL's binomial distribution). A measured count outside it says the
// intervals' real coverage differs from the nominal (at level alpha). Throws on nominal outside
// (0, 1), alpha outside (0, 1) or n == 0.
struct CountInterval {
  std::size_t low = 0, high = 0;
};
CountInterval binomial_acceptance_interval(double nominal, std::size_t n, double alpha);

}  // namespace hipfai::stats
