// hipfai — the collision benchmark driver (thesis §3.4-3.6, Tables 1-7, Figs. 31-39).
//
// `run_collision_bench` generates the thesis' scenarios (scenarios.h), runs the thesis' methods and
// their peers on the same poses in the same process, checks each against the exhaustive oracle
// (contact/oracle_*.h), and writes to `out_dir`:
//   results.csv                 one row per scenario x method x thread count: pre-processing,
//                               per-pose query and total time (median of repeats, min, max), peak
//                               memory growth, ratio to ours measured in this run, exactness
//                               (false negatives / positives, max depth error vs the oracle);
//   sweep_radial_table.csv      radial table size vs time and exactness (Figs. 37-39), all mappings,
//                               and Maciel's ray-based sampling miss rate and time;
//   sweep_cylindrical_resolution.csv   ring resolution vs time;
//   sweep_stepping.csv          stepping ROM: step size vs ROM error vs time (FCL, spatial hashing)
//                               and the one-pass range finder; rom_table7.csv per resolution;
//   scaling.csv                 fitted log-log exponent of time vs vertex count per method;
//   report.md + *.svg           the tables, the benchmark's goals (met / not met with the
//                               measured ratios) and one plot per sweep / scaling family.
// Timing: std::chrono steady clock; each figure is the median of repeated runs (min-max shown);
// pre-processing and per-pose query are timed separately; the posing of the mobile mesh is part of
// every per-pose query that needs a posed mesh (FCL takes a transform instead).
// Oracle: exhaustive when #mobile vertices x #fixed triangles is within budget, otherwise on a
// fixed random sample of mobile vertices plus every vertex our method reports (so false positives
// of our method are still checked completely); the report says which.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::bench {

struct CollisionBenchOptions {
  bool quick = false;                    // small sizes (for development and the CLI test)
  std::filesystem::path out_dir = "bench-collision";
  std::vector<int> thread_counts{1, 2};  // per-pose query figures for each
  std::string lhdl_dir;                  // real CT bones; empty = skip that scenario
  bool verbose = true;                   // one progress line per step on stdout
};

struct TargetVerdict {
  std::string target;
  bool met = false;
  bool informational = false;  // a measurement without a threshold (met is meaningless)
  std::string measured;  // the ratios / counts behind the verdict
};

struct CollisionBenchReport {
  std::vector<TargetVerdict> targets;
  std::filesystem::path report_path;
  double seconds = 0.0;
};

CollisionBenchReport run_collision_bench(const CollisionBenchOptions& options);

}  // namespace hipfai::bench
