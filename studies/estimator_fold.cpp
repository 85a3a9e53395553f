#include "studies/estimator_fold.h"

#include "core/stopwatch.h"

#include <chrono>

namespace hipfai::studies {

std::vector<EstimatorFoldUnit> estimator_fold_units(const EstimatorFoldProblem& problem) {
  std::vector<EstimatorFoldUnit> units;
  for (int c = 0; c < 2; ++c) {
    for (const int hip : problem.eligible[static_cast<std::size_t>(c)]) units.push_back({c, hip});
  }
  return units;
}

EstimatorFold run_estimator_fold(const EstimatorFoldProblem& problem, const EstimatorFoldUnit& unit) {
  const int steps = problem.case_steps[static_cast<std::size_t>(unit.case_index)];
  const Eigen::MatrixXd case_values = problem.values.leftCols(steps);
  const stats::PenetrationDepths case_depths =
      problem.depths.known()
          ? stats::PenetrationDepths{problem.depths.curvilinear_mm.leftCols(steps), problem.depths.radial_mm.leftCols(steps)}
          : stats::PenetrationDepths{};
  EstimatorFold fold;
  auto start = std::chrono::steady_clock::now();
  fold.rows = stats::leave_one_out(problem.features, case_values, problem.settings, problem.max_e_prime, {unit.hip}, {},
                                   case_depths);
  fold.loo_ms = milliseconds_since(start);
  // pca_nn with e' chosen without the target: the fold's rows already hold the estimate at every e',
  // so the choice picks one of them.
  const auto m = problem.features.rows();
  Eigen::MatrixXd train_features(m - 1, problem.features.cols()), train_values(m - 1, steps);
  for (Eigen::Index i = 0, r = 0; i < m; ++i) {
    if (i == unit.hip) continue;
    train_features.row(r) = problem.features.row(i);
    train_values.row(r++) = case_values.row(i);
  }
  start = std::chrono::steady_clock::now();
  fold.chosen_e_prime = stats::select_e_prime(train_features, train_values, problem.settings,
                                              stats::EstimatorMethod::kPcaNn, problem.max_e_prime)
                            .e_prime;
  fold.selection_ms = milliseconds_since(start);
  return fold;
}

}  // namespace hipfai::studies
