// hipfai — a quick per-pose timing probe of the striking (cylindrical) one-pass query on one
// benchmark scenario, for development (`hipfai bench striking`): seconds instead of the full
// benchmark's minutes. It times the one-pass query on the posed mesh (every candidate of a
// circle's cell, and the angular walk of CylindricalTable::nearest_crossing), the query that
// takes the pose, and FCL's collide with all contacts on the same pose in the same process,
// checks that the query variants report the same pairs bit for bit, and reports how many mobile
// vertices reach a non-empty cell and how many candidates their cells hold.
#pragma once

#include <string>
#include <vector>

namespace hipfai::bench {

struct StrikingProbeOptions {
  std::string family = "hip";  // hip (the parametric striking hip) or real_ct
  int level = 3;               // hip 0..3 (midpoint subdivisions); ignored for real_ct
  std::string lhdl_dir = "meshes/real-hips/LHDL_CT";
  int threads = 1;             // 1 or 2
  int repeats = 9;
};

struct StrikingProbeReport {
  std::string table;                    // a small Markdown table and the vertex counts
  std::vector<std::string> mismatched;  // query variants whose pairs differ from the reference
};

// Runs the probe. Throws hipfai::Error for an unknown family, a level out of range or missing
// real CT files.
StrikingProbeReport run_striking_probe(const StrikingProbeOptions& options);

}  // namespace hipfai::bench
