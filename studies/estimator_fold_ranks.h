// hipfai — the leave-one-out folds of `estimator validate` (studies/estimator_fold.h) spread over
// the ranks of an MPI job (studies/pipeline/spread_units.h): rank 0 shares the fold problem with
// every rank once, then hands out the folds; a worker rank runs a fold and sends back its rows.
// The folds come back on rank 0 in the order of estimator_fold_units().
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "studies/estimator_fold.h"
#include "studies/pipeline/spread_units.h"

#include <vector>

namespace hipfai::studies {

// On rank 0 of MPI_COMM_WORLD (at least 2 ranks, the others in serve_estimator_folds): every fold's
// result, or why it failed.
std::vector<UnitResult<EstimatorFold>> run_estimator_folds_over_ranks(const EstimatorFoldProblem& problem);

// On rank 0 when it has no folds to spread (it failed before it had a problem): lets the ranks in
// serve_estimator_folds return.
void release_estimator_fold_workers();

// On the other ranks: takes the problem from rank 0 and runs the folds handed out; returns when
// rank 0 is done or released the workers.
void serve_estimator_folds();

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
