// hipfai — the soft-tissue known-truth study's hips (studies/soft_tissue_truth_unit.h) spread over
// the ranks of an MPI job (studies/pipeline/spread_units.h): a worker rank compares a hip and, with an
// FE level, solves the FE of its two tissue sets alone (MPI_COMM_SELF, into the shared cache entries
// the one-process run's worker processes would make) and sends back the hip's row; rank 0 keeps the
// rows in grid order. The output folder and the cache are those of every rank: on a cluster, a
// shared filesystem. A hip that fails is reported with its name; the others' rows are kept.
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "studies/soft_tissue_truth.h"

namespace hipfai::studies {

// Collective over MPI_COMM_WORLD (at least 2 ranks). On the other ranks than 0: holds_results false.
SoftTissueTruthResult run_soft_tissue_truth_over_ranks(const SoftTissueTruthOptions& options);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
