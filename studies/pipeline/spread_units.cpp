#include "studies/pipeline/spread_units.h"

#ifdef HIPFAI_WITH_FEM

#include <chrono>
#include <cstdint>
#include <thread>

namespace hipfai::studies {
namespace {

// As the rank pool's: short against units of seconds, long enough to leave the cores alone.
constexpr std::chrono::milliseconds kPollInterval{5};

void wait_sleeping(MPI_Request& request) {
  for (int done = 0; !done;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (!done) std::this_thread::sleep_for(kPollInterval);
  }
}

}  // namespace

std::vector<UnitOutcome> spread_units_over_ranks(
    MPI_Comm comm, std::size_t units, const std::function<std::string(std::size_t unit)>& run,
    const std::function<void(std::size_t unit, int rank, const UnitOutcome& outcome)>& finished) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank != 0) {
    run_rank_pool_worker(comm, run);
    return {};
  }
  std::vector<UnitOutcome> outcomes(units);
  std::size_t next = 0;
  run_rank_pool_master(comm, RankPoolMaster{[&]() -> std::optional<std::size_t> {
                                              if (next == units) return std::nullopt;
                                              return next++;
                                            },
                                            [&](std::size_t unit, int worker, const UnitOutcome& outcome) {
                                              outcomes[unit] = outcome;
                                              if (finished) finished(unit, worker, outcome);
                                            }});
  return outcomes;
}

void share_from_rank_zero(MPI_Comm comm, std::string& bytes) {
  std::uint64_t size = bytes.size();
  MPI_Request request;
  MPI_Ibcast(&size, 1, MPI_UINT64_T, 0, comm, &request);
  wait_sleeping(request);
  bytes.resize(size);
  MPI_Ibcast(bytes.data(), static_cast<int>(size), MPI_CHAR, 0, comm, &request);
  wait_sleeping(request);
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
