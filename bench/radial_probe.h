// hipfai — a quick per-pose timing probe of the sliding (radial) query on one benchmark scenario,
// for development (`hipfai bench radial`): the full benchmark takes ~10 minutes, this a few
// seconds. It times the query of radial segmenting (all mappings) and of the Embree ray caster
// on the same posed mesh in the same process, and checks that both report the same vertices.
#pragma once

#include <string>
#include <vector>

namespace hipfai::bench {

struct RadialProbeOptions {
  std::string family = "cartilage";  // cartilage or sphere_cube
  int level = 3;                     // cartilage 0..3, sphere_cube 2..8
  int threads = 1;                   // 1 or 2
  int repeats = 5;
};

struct RadialProbeReport {
  std::string table;                    // a small Markdown table
  std::vector<std::string> mismatched;  // methods whose vertices differ from Embree's
};

// Runs the probe. Throws hipfai::Error for an unknown family or a level out of range.
RadialProbeReport run_radial_probe(const RadialProbeOptions& options);

}  // namespace hipfai::bench
