#include "core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

namespace hipfai {

namespace {

// One arena per thread count, kept for the process: TBB's workers stay alive between queries.
tbb::task_arena& arena_of(int threads) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& arena = arenas[threads];
  if (!arena) {
    arena = std::make_unique<tbb::task_arena>(threads);
    arena->initialize();
  }
  return *arena;
}

}  // namespace

int resolve_threads(int requested) {
  if (requested > 0) return requested;
  const unsigned hardware = std::thread::hardware_concurrency();
  return hardware == 0 ? 1 : static_cast<int>(hardware);
}

void parallel_chunks(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t, int)>& fn) {
  const int chunks = static_cast<int>(std::min<std::size_t>(
      static_cast<std::size_t>(std::max(threads, 1)), std::max<std::size_t>(n, 1)));
  if (chunks <= 1) {
    fn(0, n, 0);
    return;
  }
  const std::size_t step = (n + static_cast<std::size_t>(chunks) - 1) / static_cast<std::size_t>(chunks);
  arena_of(chunks).execute([&] {
    tbb::parallel_for(0, chunks, [&](int c) {
      const std::size_t begin = std::min(n, static_cast<std::size_t>(c) * step);
      fn(begin, std::min(n, begin + step), c);
    }, tbb::static_partitioner());
  });
}

void parallel_blocks(std::size_t n, int threads, std::size_t grain,
                     const std::function<void(std::size_t, std::size_t)>& fn) {
  if (threads <= 1 || n <= grain) {
    fn(0, n);
    return;
  }
  arena_of(threads).execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::max<std::size_t>(grain, 1)),
                      [&](const tbb::blocked_range<std::size_t>& range) { fn(range.begin(), range.end()); });
  });
}

}  // namespace hipfai
