// hipfai — timing and memory probes of the benchmark suite.
//
// Every figure of the report is a median over repeated runs in the same process, with its min and
// max, so that a ratio between two methods compares like with like (same machine load, same
// caches, same binary). Peak memory is the growth of the resident set's high-water mark (VmHWM of
// /proc/self/status) while a structure is built; the mark is reset before each build by writing
// "5" to /proc/self/clear_refs (Linux >= 4.0), so each figure is that build's own peak.
#pragma once

#include <functional>
#include <vector>

namespace hipfai::bench {

struct TimingStats {
  double median_ms = 0.0;
  double min_ms = 0.0;
  double max_ms = 0.0;
  int repeats = 0;
};

// Runs `fn` up to `max_repeats` times (at least `min_repeats`, and fewer than max_repeats only when
// the runs already took more than `budget_ms` in total, or fewer than min_repeats when they took
// more than 5 x budget_ms) and returns the median, min and max.
TimingStats time_repeated(const std::function<void()>& fn, int min_repeats, int max_repeats,
                          double budget_ms);

// The time of two stages run one after the other (pre-processing in parts): medians, minima and
// maxima added (repeats kept).
inline void add_stage(TimingStats& total, const TimingStats& stage) {
  total.median_ms += stage.median_ms;
  total.min_ms += stage.min_ms;
  total.max_ms += stage.max_ms;
}

// Statistics of already measured durations (ms).
TimingStats summarise(std::vector<double> samples_ms);

// Resets the peak-RSS mark to the current RSS (no-op where the kernel does not support it).
void reset_peak_memory();
// Resident set size and its high-water mark since the last reset, in MiB (0 when unavailable).
double resident_mib();
double peak_resident_mib();

// Peak memory growth (MiB) while `fn` runs: peak after minus resident before. Heap pages that
// were already resident (freed earlier, reused by malloc) do not show here, so see also below.
double peak_memory_growth_mib(const std::function<void()>& fn);

// Heap bytes in use (malloc'd, including mmapped blocks) in MiB, from glibc's mallinfo2.
double heap_in_use_mib();

struct MemoryUse {
  double peak_rss_growth_mib = 0.0;  // VmHWM growth while building
  double heap_growth_mib = 0.0;      // heap in use after minus before: the size of what was built
};

// Both measures around `fn`, which should build a structure and keep it alive.
MemoryUse measure_memory(const std::function<void()>& fn);

}  // namespace hipfai::bench
