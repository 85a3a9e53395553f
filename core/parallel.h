// hipfai — the project's one worker pool: TBB task arenas (Debian libtbb-dev, also a deal.II
// dependency), one per thread count, created once and kept for the process, so a per-pose query
// on a motion's hundreds of poses never starts a thread.
#pragma once

#include <cstddef>
#include <functional>

namespace hipfai {

// Number of worker threads for `requested` (0 = all hardware threads, at least 1).
int resolve_threads(int requested);

// Runs fn(begin, end, chunk) over [0, n) split in `threads` contiguous chunks (chunk = 0, 1, ...),
// in parallel on the pool; one chunk runs on the calling thread alone.
void parallel_chunks(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t, int)>& fn);

// Runs fn(begin, end) over [0, n) in blocks of about `grain` items taken dynamically by `threads`
// workers of the same pool (for uneven work per item; fn must not depend on which worker runs it).
void parallel_blocks(std::size_t n, int threads, std::size_t grain,
                     const std::function<void(std::size_t, std::size_t)>& fn);

}  // namespace hipfai
