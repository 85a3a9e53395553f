// hipfai — intervals with a stated coverage, calibrated on residuals the model did not train on
// (conformal prediction; Vovk, Gammerman & Shafer 2005; split form: Papadopoulos et al. 2002;
// groups: Vovk's Mondrian conformal predictors). The estimator's own intervals (the range of the
// neighbours it averaged, studies/estimator_study.h) state no coverage; these do.
//
// A score per calibration row: s = |truth - prediction| / scale, with scale = |prediction| (a
// relative error, the thesis' error measure, §4.5.3.4). With n scores of one group, the half-width
// is the k-th smallest score, k = ceil((n + 1) * nominal): when the calibration rows and a new row
// are exchangeable, the new row's truth lies in prediction ± half_width * |prediction| with
// probability at least `nominal` (infinite half-width when k > n: too few rows for the nominal).
// Groups (Mondrian): each group is calibrated on its own rows, so the coverage holds per group and
// the interval can be wider where the errors are larger (e.g. steps where the hip impinges).
//
// The calibration rows here are leave-one-out estimates of the training hips (each estimated by a
// model without it), so a held-out hip's row is a new draw of the same kind; rows of one hip share
// its errors, which makes the guarantee approximate, and that is why it is checked on held-out
// hips (stats/interval_coverage.h).
#pragma once

#include <cstddef>
#include <vector>

namespace hipfai::stats {

struct ConformalRow {
  double prediction = 0.0;
  double truth = 0.0;
  int group = 0;  // 0 .. groups - 1
};

struct ConformalCalibration {
  double nominal = 0.9;
  std::vector<double> half_width;   // per group, relative to |prediction|; +inf when too few rows
  std::vector<std::size_t> rows;    // calibration rows used per group
};

// Rows with a non-finite prediction or truth, or a prediction of 0 (no relative scale), are left
// out. Throws hipfai::Error when nominal is outside (0, 1), groups < 1 or a row's group is outside
// [0, groups).
ConformalCalibration calibrate_conformal(const std::vector<ConformalRow>& rows, int groups, double nominal);

struct ConformalInterval {
  double lower = 0.0, upper = 0.0;
  double relative_half_width = 0.0;  // the group's calibrated half-width
};

// The interval of a new prediction in `group`: prediction ± half_width * |prediction|. Throws
// hipfai::Error when the group is outside the calibration's.
ConformalInterval conformal_interval(const ConformalCalibration& calibration, double prediction, int group);

}  // namespace hipfai::stats
