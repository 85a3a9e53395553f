#include "studies/estimator_fold_ranks.h"

#ifdef HIPFAI_WITH_FEM

#include <string>

namespace hipfai::studies {

// The problem's and the replies' fields (studies/pipeline/unit_reply.h); internal to this file,
// found by argument-dependent lookup through the writer and reader.
static void write_reply(UnitReplyWriter& out, const stats::RegressionStep& step) {
  out.add(step.estimate).add(step.low).add(step.high).add(step.defined);
}
static void read_reply(UnitReplyReader& in, stats::RegressionStep& step) {
  in.read(step.estimate).read(step.low).read(step.high).read(step.defined);
}

static void write_reply(UnitReplyWriter& out, const stats::LeaveOneOutRow& row) {
  out.add(row.hip).add(row.method).add(row.e_prime);
  out.add(row.result.steps).add(row.result.mahalanobis).add(row.result.outside_components).add(row.result.bordering);
}
static void read_reply(UnitReplyReader& in, stats::LeaveOneOutRow& row) {
  in.read(row.hip).read(row.method).read(row.e_prime);
  in.read(row.result.steps).read(row.result.mahalanobis).read(row.result.outside_components).read(row.result.bordering);
}

static void write_reply(UnitReplyWriter& out, const EstimatorFold& fold) {
  out.add(fold.rows).add(fold.chosen_e_prime).add(fold.loo_ms).add(fold.selection_ms);
}
static void read_reply(UnitReplyReader& in, EstimatorFold& fold) {
  in.read(fold.rows).read(fold.chosen_e_prime).read(fold.loo_ms).read(fold.selection_ms);
}

static void write_reply(UnitReplyWriter& out, const EstimatorFoldProblem& p) {
  out.add(p.features).add(p.values).add(p.depths.curvilinear_mm).add(p.depths.radial_mm);
  out.add(p.settings.pca.components).add(p.settings.pca.scale_floor).add(p.settings.nearest).add(p.settings.knn_k);
  out.add(p.settings.bordering_min_variance_share).add(p.max_e_prime);
  for (int c = 0; c < 2; ++c) out.add(p.case_steps[static_cast<std::size_t>(c)]).add(p.eligible[static_cast<std::size_t>(c)]);
}
static void read_reply(UnitReplyReader& in, EstimatorFoldProblem& p) {
  in.read(p.features).read(p.values).read(p.depths.curvilinear_mm).read(p.depths.radial_mm);
  in.read(p.settings.pca.components).read(p.settings.pca.scale_floor).read(p.settings.nearest).read(p.settings.knn_k);
  in.read(p.settings.bordering_min_variance_share).read(p.max_e_prime);
  for (int c = 0; c < 2; ++c) in.read(p.case_steps[static_cast<std::size_t>(c)]).read(p.eligible[static_cast<std::size_t>(c)]);
}

namespace {

std::optional<std::vector<UnitResult<EstimatorFold>>> spread_folds(const EstimatorFoldProblem& problem) {
  const std::vector<EstimatorFoldUnit> units = estimator_fold_units(problem);
  return spread_units<EstimatorFold>(MPI_COMM_WORLD, units.size(),
                                     [&](std::size_t unit) { return run_estimator_fold(problem, units[unit]); });
}

}  // namespace

std::vector<UnitResult<EstimatorFold>> run_estimator_folds_over_ranks(const EstimatorFoldProblem& problem) {
  std::string bytes = encode_unit_reply(problem);
  share_from_rank_zero(MPI_COMM_WORLD, bytes);
  return *spread_folds(problem);
}

void release_estimator_fold_workers() {
  std::string nothing;
  share_from_rank_zero(MPI_COMM_WORLD, nothing);
}

void serve_estimator_folds() {
  std::string bytes;
  share_from_rank_zero(MPI_COMM_WORLD, bytes);
  if (bytes.empty()) return;
  spread_folds(decode_unit_reply<EstimatorFoldProblem>(bytes));  // the same build as rank 0's: it decodes
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
