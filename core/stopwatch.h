// hipfai — wall-clock time since a start point, in seconds, for the timings studies report.
#pragma once

#include <chrono>

namespace hipfai {

// A steady clock (never adjusted), so a measured interval is never negative.
using SteadyClock = std::chrono::steady_clock;

inline double seconds_since(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

inline double milliseconds_since(SteadyClock::time_point start) {
  return std::chrono::duration<double, std::milli>(SteadyClock::now() - start).count();
}

}  // namespace hipfai
