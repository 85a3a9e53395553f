// hipfai — range of motion by stepping (thesis §4.2.3, Table 7): rotate the mobile mesh by
// successive steps of `step_deg` about the axis and run a collision detector at each pose until
// the first collision. The range is the last collision-free angle, so it under-estimates the exact
// range by less than one step (for a detector that sees every contact), and its cost is one
// detection per step. The thesis' one-pass range finder (contact/range_finder.h) needs no step.
#pragma once

#include <functional>

namespace hipfai::bench {

// True when the mobile mesh rotated by angle_deg (right-hand rule, may be negative) collides.
using CollisionAtAngle = std::function<bool(double angle_deg)>;

struct SteppingRomOptions {
  double step_deg = 1.0;
  double max_deg = 180.0;  // give up (range reported as max_deg) beyond this
};

struct SteppingRom {
  double anticlockwise_deg = 0.0;  // last free angle stepping by +step
  double clockwise_deg = 0.0;      // last free angle stepping by -step
  int detections = 0;              // collision queries run
  bool anticlockwise_limited = false;
  bool clockwise_limited = false;
};

SteppingRom stepping_range_of_motion(const CollisionAtAngle& collides,
                                     const SteppingRomOptions& options = {});

}  // namespace hipfai::bench
