// hipfai — a loop over [0, n) split into contiguous chunks, run on the project's worker pool
// (core/parallel.h: TBB arenas kept for the process, so no thread is started per assembly).
//
// The FE stages that are independent per cell or per face (cell matrices, mortar integration,
// rows of the reduced matrix) write into per-item slots, so their results do not depend on the
// number of threads. The threads share the machine's cores with the other MPI ranks on it.
#pragma once

#include "core/parallel.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/multithread_info.h>

#include <mpi.h>

#include <algorithm>
#include <cstddef>

namespace hipfai::fem {

// Threads per rank: the process's thread limit (deal.II's MultithreadInfo: the hardware threads,
// DEAL_II_NUM_THREADS or limit_threads()) shared among the ranks, 1 to 8.
inline std::size_t threads_per_rank(MPI_Comm comm) {
  return std::clamp<std::size_t>(
      dealii::MultithreadInfo::n_threads() / dealii::Utilities::MPI::n_mpi_processes(comm), 1, 8);
}

// Items per chunk when [0, n) is split over n_threads (at least 1).
inline std::size_t chunk_size(std::size_t n, std::size_t n_threads) {
  return std::max<std::size_t>(1, (n + n_threads - 1) / n_threads);
}

// Runs work(first, last) over [0, n) in contiguous chunks of chunk_size(n, n_threads), each chunk
// a task of the pool (as many workers as chunks).
template <class Work>
void run_in_chunks(std::size_t n, std::size_t n_threads, const Work& work) {
  const std::size_t chunk = chunk_size(n, n_threads);
  const std::size_t chunks = (n + chunk - 1) / chunk;
  parallel_chunks(chunks, static_cast<int>(chunks), [&](std::size_t begin, std::size_t end, int) {
    for (std::size_t c = begin; c < end; ++c) work(c * chunk, std::min(n, (c + 1) * chunk));
  });
}

}  // namespace hipfai::fem
