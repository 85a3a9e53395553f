// hipfai — what one run of the collision benchmark measured (collision_bench.h), as one value: a
// row per scenario x method x thread count, the sweeps and the range-of-motion table. The driver
// (collision_bench.cpp) fills it; collision_bench_targets.h judges it against the goals;
// collision_bench_report.h writes its tables, figures and report.md. Nothing here is written to
// disk by the driver itself.
#pragma once

#include "bench/timing.h"

#include <cstddef>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::bench {

// A method's answer against the oracle's on the vertices the oracle checked.
struct Exactness {
  long false_negatives = -1;  // penetrating vertices the method missed; -1: not compared (the oracle's own row)
  long false_positives = -1;  // vertices reported that do not penetrate; -1: not compared
  double max_depth_error_mm = std::numeric_limits<double>::quiet_NaN();  // NaN: the method gives no depths
  std::size_t reported = 0;   // penetrating vertices the method reported
};

// One method on one scenario with one thread count.
struct BenchRow {
  std::string family;    // scenario family: striking_hip, striking_real_ct, sphere_cube, cartilage, ...
  std::string scenario;  // family and level, e.g. "sphere_cube_L8"
  int level = 0;         // resolution level of the scenario
  std::size_t vertices = 0;         // both meshes together
  std::size_t mobile_vertices = 0;  // the vertices every method is asked about
  std::size_t fixed_triangles = 0;
  std::string method;  // ours (cylindrical, cylindrical_pose_cache, radial_<mapping>, ...) or a peer
  int threads = 1;
  TimingStats pre;    // pre-processing (tables, BVHs, hash grids)
  TimingStats query;  // one pose (posing the mobile mesh included where the method needs it)
  MemoryUse memory;   // of the pre-processing
  double ratio_query = std::numeric_limits<double>::quiet_NaN();  // query time / ours, same threads, same run
  double ratio_total = std::numeric_limits<double>::quiet_NaN();  // total time / ours
  Exactness exact;
  std::string reference;  // what the row was compared with ("oracle", or an oracle sample)
  std::string note;       // anything a reader of the row needs (tetrahedra, miss rate, ...)
  double total_ms() const { return pre.median_ms + query.median_ms; }
};

// One scenario of the range-of-motion comparison (thesis Table 7): the one-pass range finder
// against 1 degree stepping with FCL and with spatial hashing.
struct RomTableRow {
  std::string scenario;
  std::size_t vertices = 0;
  double finder_ms = 0.0, fcl_ms = 0.0, hash_ms = 0.0;  // wall time of each, pre-processing included
  double exact_ccw = 0.0, exact_cw = 0.0;  // range finder, deg (anticlockwise / clockwise)
  double fcl_ccw = 0.0, fcl_cw = 0.0;      // FCL stepping, deg
  double hash_ccw = 0.0, hash_cw = 0.0;    // spatial-hashing stepping, deg
  std::string finder_exact;                // the finder against the oracle, in words
};

// Points (x, y) of one curve of a sweep.
using Curve = std::vector<std::pair<double, double>>;

struct CollisionBenchResults {
  bool quick = false;  // measured at the quick sizes (indicative only)
  std::vector<BenchRow> rows;
  // Sweep tables as CSV lines, header first (empty: the sweep did not run).
  std::vector<std::string> sweep_radial_table_csv;     // table size vs time, all mappings, Maciel
  std::vector<std::string> sweep_cylindrical_csv;      // ring resolution vs time
  std::vector<std::string> sweep_stepping_csv;         // step size vs ROM error vs time
  // The same sweeps as curves for the figures: per method, (table cells, ms) ...
  std::map<std::string, Curve> radial_sweep_query, radial_sweep_pre;
  Curve maciel_miss;   // (table cells, missed penetrating vertices %)
  Curve maciel_query;  // (table cells, ms)
  std::map<std::string, Curve> cylindrical_sweep;  // (ring resolution mm, ms) per stage
  std::map<std::string, Curve> stepping_sweep;     // (ms, max ROM error deg) per detector
  std::vector<RomTableRow> rom_table;
  std::vector<std::string> notes;  // scenarios skipped and why
};

// The row of `method` with `threads` on `scenario`; null when it was not measured.
const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& scenario, const std::string& method,
                         int threads);

}  // namespace hipfai::bench
