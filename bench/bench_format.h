// hipfai — how the collision benchmark prints numbers in its tables, notes and report.
#pragma once

#include "bench/timing.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace hipfai::bench {

// `value` with `precision` significant digits; empty for NaN (a value not measured).
inline std::string fmt(double value, int precision = 3) {
  if (std::isnan(value)) return "";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*g", precision, value);
  return buffer;
}

// A false-negative / false-positive count, empty when the row was not compared with a reference
// (the oracle's own row): -1 would read as a count.
inline std::string fmt_count(long count) { return count < 0 ? std::string() : std::to_string(count); }

// "median [min–max]" of repeated timings, "-" when nothing ran.
inline std::string fmt_ms(const TimingStats& t) {
  if (t.repeats == 0) return "-";
  return fmt(t.median_ms) + " [" + fmt(t.min_ms) + "–" + fmt(t.max_ms) + "]";
}

}  // namespace hipfai::bench
