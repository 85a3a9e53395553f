// hipfai — how a study spreads its independent units (a hip's penetration, a hip's FE): over this
// machine's cores, as it always did, or over the ranks of an MPI job (`mpirun -np N hipfai study
// ...`, `srun hipfai study ...`). A process started directly never initialises MPI for a study.
#pragma once

#ifdef HIPFAI_WITH_FEM
#include <mpi.h>
#endif

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

enum class UnitSpread {
  kThisMachine,  // this process and its worker processes (--jobs)
  kMpiRanks,     // the ranks of MPI_COMM_WORLD (rank 0 hands out units and writes the results)
};

// A unit of a study spread over MPI ranks that failed: which (the study's name for it, e.g.
// "ce20_alpha40") and why, in one line. The study keeps the other units' results.
struct UnitFailure {
  std::string unit;
  std::string message;
};

// Throws hipfai::Error "<study>: 1 of 3 hips failed (the others are in out/x): ce80_alpha40: ..."
// (one line) when `failed` is not empty; `kept` is how many units the results hold, `what` names
// the units ("hips", "folds").
void throw_if_units_failed(const std::string& study, const std::vector<UnitFailure>& failed, std::size_t kept,
                           const std::string& what, const std::filesystem::path& out_dir);

// True when an MPI launcher started this process: its variables are in the environment (Open MPI's
// OMPI_COMM_WORLD_SIZE, PMIx's PMIX_RANK, PMI's PMI_SIZE as Slurm's srun and MPICH set them).
bool started_by_mpi_launcher();

// kMpiRanks when started_by_mpi_launcher(), else kThisMachine.
UnitSpread unit_spread_of_this_process();

#ifdef HIPFAI_WITH_FEM
struct MpiWorld {
  int rank = 0;
  int size = 1;
};

// Initialises MPI once (with deal.II and PETSc, fem::ensure_mpi_initialized) and returns this
// process's place in MPI_COMM_WORLD.
MpiWorld join_mpi_world();

// Threads of each unit on a worker rank: the hardware threads of its node shared among the
// worker ranks there (rank 0 hands out work and sleeps in between), and no more than the CPUs the
// launcher bound the rank to. Collective over `comm`.
unsigned int threads_per_worker_rank(MPI_Comm comm);
#endif

}  // namespace hipfai::studies
