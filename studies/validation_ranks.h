// hipfai — the FAI validation study's hips spread over the ranks of an MPI job
// (studies/pipeline/rank_pool.h): each hip is two units, its penetration (makes the hip) and its FE
// (ready once the hip exists), handed by rank 0 to whichever worker rank is free, the FE first
// when one is ready (the long units start early). A worker solves an FE run on its rank alone
// (MPI_COMM_SELF) into the FE cache and sends back where the entry is; a penetration unit sends
// back the hip's per-step depths. The cache and the output folder are those of every rank: on a
// cluster, a shared filesystem.
//
// A unit that fails (a hip that cannot be generated, an FE run that leaves no table) is reported
// with the hip's name; the other hips go on, and rank 0 keeps their results.
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "studies/pipeline/motion.h"
#include "studies/validation_hip.h"
#include "studies/validation_study.h"

#include <cstddef>
#include <utility>
#include <vector>

namespace hipfai::studies {

struct ValidationRankRun {
  bool writes = false;                        // this is rank 0: it has the results and writes them
  std::vector<ValidationHip> hips;            // rank 0: the hips that succeeded, FE read back, grid order
  std::vector<ValidationHipFailure> failed;   // rank 0: the hips that did not, grid order
};

// Collective over MPI_COMM_WORLD (at least 2 ranks). `order` is the order in which the hips of
// `grid` are started.
ValidationRankRun run_validation_over_ranks(const std::vector<std::pair<double, double>>& grid,
                                            const std::vector<std::size_t>& order, const Motion& motion,
                                            const ValidationOptions& options);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
