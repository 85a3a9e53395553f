#include "bench/timing.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <malloc.h>
#include <sstream>
#include <string>

namespace hipfai::bench {

TimingStats summarise(std::vector<double> samples_ms) {
  TimingStats stats;
  if (samples_ms.empty()) return stats;
  std::sort(samples_ms.begin(), samples_ms.end());
  const std::size_t n = samples_ms.size();
  stats.median_ms = n % 2 == 1 ? samples_ms[n / 2] : 0.5 * (samples_ms[n / 2 - 1] + samples_ms[n / 2]);
  stats.min_ms = samples_ms.front();
  stats.max_ms = samples_ms.back();
  stats.repeats = static_cast<int>(n);
  return stats;
}

TimingStats time_repeated(const std::function<void()>& fn, int min_repeats, int max_repeats,
                          double budget_ms) {
  std::vector<double> samples;
  double total_ms = 0.0;
  for (int i = 0; i < max_repeats; ++i) {
    const auto start = std::chrono::steady_clock::now();
    fn();
    const auto stop = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(stop - start).count();
    samples.push_back(ms);
    total_ms += ms;
    if (i + 1 >= min_repeats && total_ms > budget_ms) break;
    // A single run far over the budget (a slow peer at the largest size) is not repeated.
    if (total_ms > 5.0 * budget_ms) break;
  }
  return summarise(std::move(samples));
}

namespace {

double status_field_mib(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string prefix = std::string(key) + ":";
  while (std::getline(in, line)) {
    if (line.rfind(prefix, 0) == 0) {
      std::istringstream fields(line.substr(prefix.size()));
      double kib = 0.0;
      fields >> kib;
      return kib / 1024.0;
    }
  }
  return 0.0;
}

}  // namespace

void reset_peak_memory() {
  std::ofstream out("/proc/self/clear_refs");
  if (out) out << "5";
}

double resident_mib() { return status_field_mib("VmRSS"); }
double peak_resident_mib() { return status_field_mib("VmHWM"); }

double peak_memory_growth_mib(const std::function<void()>& fn) {
  reset_peak_memory();
  const double before = resident_mib();
  fn();
  const double growth = peak_resident_mib() - before;
  return growth > 0.0 ? growth : 0.0;
}

double heap_in_use_mib() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<double>(info.uordblks + info.hblkhd) / (1024.0 * 1024.0);
}

MemoryUse measure_memory(const std::function<void()>& fn) {
  MemoryUse use;
  const double heap_before = heap_in_use_mib();
  use.peak_rss_growth_mib = peak_memory_growth_mib(fn);
  use.heap_growth_mib = std::max(0.0, heap_in_use_mib() - heap_before);
  return use;
}

}  // namespace hipfai::bench
