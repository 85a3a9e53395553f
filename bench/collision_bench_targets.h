// hipfai — the collision benchmark's results judged against its goals (the thesis' speed-ups; the
// project's own goals: radial vs Embree, the pose cache vs FCL, the one-pass range of motion vs
// stepping, two threads; zero false negatives / positives; bench/README.md), with the measured
// ratios behind every verdict, and the bandwidth floor as a measurement without a threshold.
#pragma once

#include "bench/collision_bench.h"
#include "bench/collision_bench_results.h"

#include <vector>

namespace hipfai::bench {

// One verdict per goal, in the order report.md lists them; ratios are taken from rows of this
// run only (the largest scenario of each family).
std::vector<TargetVerdict> evaluate_targets(const CollisionBenchResults& results);

}  // namespace hipfai::bench
