// hipfai — the FAI penetration study's units (studies/fai_unit.h) spread over the ranks of an MPI
// job (studies/pipeline/spread_units.h): a worker rank runs a unit alone and sends back its summary
// and per-step penetration; rank 0 takes the unit's hip from the cache the worker made it in (the
// same files, so the same meshes as the one-process run) and keeps the run. The cache and the
// output folder are those of every rank: on a cluster, a shared filesystem.
//
// A unit that fails (a hip that cannot be generated) is reported with its name; rank 0 keeps the
// other units' runs.
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "studies/fai_unit.h"
#include "studies/pipeline/mpi_launch.h"

#include <optional>
#include <vector>

namespace hipfai::studies {

struct FaiRankRun {
  bool holds_results = false;                   // this is rank 0: it has the runs
  std::vector<std::optional<FaiModelRun>> runs;  // rank 0: per unit, nullopt when it failed
  std::vector<UnitFailure> failed;               // rank 0: the units that failed, in unit order
};

// Collective over MPI_COMM_WORLD (at least 2 ranks).
FaiRankRun run_fai_units_over_ranks(const std::vector<FaiUnit>& units, const Motion& motion,
                                    const FaiStudyOptions& options);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
