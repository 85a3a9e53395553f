// hipfai — writes what one run of the collision benchmark measured (collision_bench_results.h)
// into `dir`: results.csv, the sweep tables, rom_table7.csv, scaling.csv, one SVG per sweep and
// scaling family, and report.md with the targets' verdicts (files: collision_bench.h). Every file
// is written atomically; nothing is measured here.
#pragma once

#include "bench/collision_bench.h"
#include "bench/collision_bench_results.h"

#include <filesystem>
#include <vector>

namespace hipfai::bench {

// Returns the path of report.md. Throws hipfai::Error when a file cannot be written.
std::filesystem::path write_collision_bench_report(const CollisionBenchResults& results,
                                                   const std::vector<TargetVerdict>& targets,
                                                   const std::filesystem::path& dir);

}  // namespace hipfai::bench
