// hipfai — a loop over [0, n) split into contiguous chunks on threads.
//
// The FE stages that are independent per cell or per face (cell matrices, mortar integration,
// rows of the reduced matrix) write into per-item slots, so their results do not depend on the
// number of threads. The threads share the machine's cores with the other MPI ranks on it.
#pragma once

#include <deal.II/base/mpi.h>

#include <mpi.h>

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace hipfai::fem {

// Threads per rank: the hardware threads shared among the ranks, 1 to 8.
inline std::size_t threads_per_rank(MPI_Comm comm) {
  return std::clamp<std::size_t>(
      std::thread::hardware_concurrency() / dealii::Utilities::MPI::n_mpi_processes(comm), 1, 8);
}

// Items per chunk when [0, n) is split over n_threads (at least 1).
inline std::size_t chunk_size(std::size_t n, std::size_t n_threads) {
  return std::max<std::size_t>(1, (n + n_threads - 1) / n_threads);
}

// Runs work(first, last) over [0, n) in contiguous chunks of chunk_size(n, n_threads), one per
// thread; the calling thread takes the first chunk.
template <class Work>
void run_in_chunks(std::size_t n, std::size_t n_threads, const Work& work) {
  const std::size_t chunk = chunk_size(n, n_threads);
  std::vector<std::thread> workers;
  for (std::size_t first = chunk; first < n; first += chunk) {
    workers.emplace_back(work, first, std::min(n, first + chunk));
  }
  work(0, std::min(n, chunk));
  for (std::thread& worker : workers) worker.join();
}

}  // namespace hipfai::fem
