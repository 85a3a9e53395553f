// hipfai — one leave-one-out fold of `estimator validate` (studies/estimator_validate.h), the
// study's independent unit: a case's held-out hip estimated by every method and e' from a model
// trained on the other hips (stats::leave_one_out), and pca_nn's e' chosen on those other hips
// alone (stats::select_e_prime). A fold needs only the numbers of EstimatorFoldProblem, so it runs
// the same in this process or on a worker rank (studies/estimator_fold_ranks.h).
#pragma once

#include "stats/pressure_estimator.h"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace hipfai::studies {

// What every fold reads: the features, FE values and depths of all hips, the settings, e' = 1..max
// and per case its steps and its eligible hips (held out one at a time).
struct EstimatorFoldProblem {
  Eigen::MatrixXd features;             // m x f
  Eigen::MatrixXd values;               // m x p, NaN = missing
  stats::PenetrationDepths depths;      // m x p each, or empty
  stats::EstimatorSettings settings;
  int max_e_prime = 0;
  std::array<int, 2> case_steps{};              // the first steps of the motion in case 0 and 1
  std::array<std::vector<int>, 2> eligible;     // per case, the hips held out, ascending
};

struct EstimatorFoldUnit {
  int case_index = 0;
  int hip = 0;
};

struct EstimatorFold {
  // stats::leave_one_out's rows of the held-out hip over the case's steps: every method, e' = 1..max.
  std::vector<stats::LeaveOneOutRow> rows;
  int chosen_e_prime = 0;  // pca_nn's e', chosen without the held-out hip
  double loo_ms = 0, selection_ms = 0;
};

// The folds in the order the study gathers them: case 0's eligible hips, then case 1's.
std::vector<EstimatorFoldUnit> estimator_fold_units(const EstimatorFoldProblem& problem);

// Runs one fold. Throws hipfai::Error as stats::leave_one_out does.
EstimatorFold run_estimator_fold(const EstimatorFoldProblem& problem, const EstimatorFoldUnit& unit);

}  // namespace hipfai::studies
