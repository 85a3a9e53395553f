#include "studies/pipeline/mpi_launch.h"

#include "core/error.h"

#include <cstdlib>

#ifdef HIPFAI_WITH_FEM
#include "core/parallel.h"
#include "fem/contact_problem.h"

#include <algorithm>
#include <sched.h>
#endif

namespace hipfai::studies {

void throw_if_units_failed(const std::string& study, const std::vector<UnitFailure>& failed, std::size_t kept,
                           const std::string& what, const std::filesystem::path& out_dir) {
  if (failed.empty()) return;
  std::string units;
  for (const UnitFailure& unit : failed) units += (units.empty() ? "" : "; ") + unit.unit + ": " + unit.message;
  throw_error(study, ": ", failed.size(), " of ", failed.size() + kept, " ", what, " failed (the others are in ",
              out_dir.string(), "): ", units);
}

bool started_by_mpi_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

UnitSpread unit_spread_of_this_process() {
  return started_by_mpi_launcher() ? UnitSpread::kMpiRanks : UnitSpread::kThisMachine;
}

#ifdef HIPFAI_WITH_FEM
MpiWorld join_mpi_world() {
  fem::ensure_mpi_initialized();
  MpiWorld world;
  MPI_Comm_rank(MPI_COMM_WORLD, &world.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &world.size);
  return world;
}

unsigned int threads_per_worker_rank(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node);
  const int is_worker = rank == 0 ? 0 : 1;
  int workers_here = 0;
  MPI_Allreduce(&is_worker, &workers_here, 1, MPI_INT, MPI_SUM, node);
  MPI_Comm_free(&node);
  int threads = std::max(1, resolve_threads(0) / std::max(1, workers_here));
  // A launcher that binds each rank to its own CPUs (srun --cpus-per-task, mpirun --bind-to):
  // no more threads than the rank may run on.
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0) threads = std::min(threads, std::max(1, CPU_COUNT(&allowed)));
  return static_cast<unsigned int>(threads);
}
#endif

}  // namespace hipfai::studies
