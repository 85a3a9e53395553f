#include "bench/stepping_rom.h"

#include "core/error.h"

#include <cmath>

namespace hipfai::bench {

SteppingRom stepping_range_of_motion(const CollisionAtAngle& collides, const SteppingRomOptions& options) {
  if (!(options.step_deg > 0.0) || !(options.max_deg > 0.0)) {
    throw_error("stepping range of motion: step_deg and max_deg must be positive");
  }
  SteppingRom rom;
  const long long max_steps = static_cast<long long>(std::floor(options.max_deg / options.step_deg + 1e-9));
  for (int direction = 0; direction < 2; ++direction) {
    const double sign = direction == 0 ? 1.0 : -1.0;
    double free_deg = max_steps * options.step_deg;
    bool limited = false;
    for (long long k = 1; k <= max_steps; ++k) {
      ++rom.detections;
      // k * step, not a running sum, so that 0.1 degree steps do not accumulate rounding.
      if (collides(sign * static_cast<double>(k) * options.step_deg)) {
        free_deg = static_cast<double>(k - 1) * options.step_deg;
        limited = true;
        break;
      }
    }
    if (direction == 0) {
      rom.anticlockwise_deg = free_deg;
      rom.anticlockwise_limited = limited;
    } else {
      rom.clockwise_deg = free_deg;
      rom.clockwise_limited = limited;
    }
  }
  return rom;
}

}  // namespace hipfai::bench
