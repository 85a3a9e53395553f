// fem/thread_chunks.h: the chunks cover [0, n) once each, in contiguous pieces.
#include "fem/thread_chunks.h"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>

namespace hipfai::fem {
namespace {

TEST(FemThreadChunks, EveryItemOnce) {
  for (const std::size_t n : {0u, 1u, 7u, 100u}) {
    for (const std::size_t threads : {1u, 3u, 8u}) {
      std::vector<std::atomic<int>> visits(n);
      std::mutex mutex;
      std::vector<std::pair<std::size_t, std::size_t>> chunks;
      run_in_chunks(n, threads, [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) ++visits[i];
        const std::lock_guard<std::mutex> lock(mutex);
        chunks.emplace_back(first, last);
      });
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(visits[i].load(), 1) << n << " " << threads;
      EXPECT_LE(chunks.size(), std::max<std::size_t>(threads, 1));
      for (const auto& [first, last] : chunks) {
        EXPECT_EQ(first % chunk_size(n, threads), 0u);  // chunks start on multiples of the size
        EXPECT_LE(last - first, chunk_size(n, threads));
      }
    }
  }
  EXPECT_EQ(chunk_size(0, 4), 1u);
  EXPECT_EQ(chunk_size(10, 4), 3u);
}

}  // namespace
}  // namespace hipfai::fem
