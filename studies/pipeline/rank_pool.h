// hipfai — a study's independent units spread over the ranks of an MPI job with dynamic load
// balancing: rank 0 hands a unit (its index) to each free worker rank, a worker runs it and sends
// back its reply, and gets the next one. A unit runs on its one rank (MPI_COMM_SELF for its FE), so
// its results are those of the one-process run. Plain MPI point-to-point messages: no scheduler of
// hipfai's own, and the same program on a laptop (`mpirun --oversubscribe -np 3`) or a cluster.
//
// Units may depend on each other (a hip's FE on the hip made by its penetration unit): rank 0 asks
// next_unit() for a unit ready to run whenever a worker is free, and a finished unit may make
// others ready. Waiting ranks poll with short sleeps instead of MPI's busy wait, so that rank 0 and
// idle workers leave the cores to the ranks that compute (3 ranks on 2 cores).
#pragma once

#ifdef HIPFAI_WITH_FEM

#include <mpi.h>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

namespace hipfai::studies {

// What a worker sent back for a unit: its reply (bytes the study encodes), or why it failed.
struct UnitOutcome {
  bool ok = false;
  std::string reply;  // ok: the reply of the unit's function
  std::string error;  // not ok: the message of the exception it threw
};

struct RankPoolMaster {
  // The next unit ready to run, or nullopt when none is ready now.
  std::function<std::optional<std::size_t>()> next_unit;
  // A unit finished on worker `rank`.
  std::function<void(std::size_t unit, int rank, const UnitOutcome& outcome)> finished;
};

// On rank 0 of `comm` (at least 2 ranks): hands out units until none is ready and none runs, then
// stops every worker. What `finished` throws passes through, after the workers are stopped.
void run_rank_pool_master(MPI_Comm comm, const RankPoolMaster& master);

// On the other ranks: runs the units rank 0 hands out with `run`, which returns the unit's reply;
// an exception it throws is sent back as the unit's failure (and the worker goes on). Returns when
// rank 0 stops the pool.
void run_rank_pool_worker(MPI_Comm comm, const std::function<std::string(std::size_t unit)>& run);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
