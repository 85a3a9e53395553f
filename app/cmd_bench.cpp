// hipfai bench collision: the collision benchmark (thesis §3.4-3.6, Tables 1-7): the
// thesis' methods against FCL, Embree, CGAL, spatial hashing, ray-based sampling and stepping ROM,
// in the same process, with exactness against the oracle; writes CSV + report.md + SVG plots.
#include "app/command_registry.h"
#include "bench/collision_bench.h"
#include "bench/radial_probe.h"
#include "bench/striking_probe.h"
#include "core/error.h"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace hipfai::app {
namespace {

struct BenchArgs {
  bool quick = false;
  std::string out = "bench-collision";
  int threads = 2;
  std::string lhdl_dir = "meshes/real-hips/LHDL_CT";  // relative to the working directory
};

void run(const BenchArgs& args) {
  bench::CollisionBenchOptions options;
  options.quick = args.quick;
  options.out_dir = args.out;
  options.thread_counts.clear();
  for (int t = 1; t <= args.threads; ++t) options.thread_counts.push_back(t);
  options.lhdl_dir = args.lhdl_dir;
  const auto report = bench::run_collision_bench(options);
  std::printf("\n%-100s %s\n", "target", "verdict");
  for (const auto& t : report.targets) {
    std::printf("%-100s %s\n  %s\n", t.target.c_str(), t.informational ? "(measure)" : t.met ? "MET" : "not met", t.measured.c_str());
  }
  std::printf("\nreport: %s (%.1f s)\n", report.report_path.string().c_str(), report.seconds);
}

// A probe whose methods disagree is a failed run: one line naming them.
void fail_on_mismatch(const std::vector<std::string>& mismatched, const std::string& what) {
  if (mismatched.empty()) return;
  std::string list;
  for (const std::string& name : mismatched) list += (list.empty() ? "" : ", ") + name;
  throw_error(list, " ", what);
}

const CommandRegistrar bench_registrar("bench", [](CLI::App& parent) {
  auto* bench = parent.add_subcommand("bench", "Benchmarks (collision: the thesis' methods against real peers)");
  bench->require_subcommand(1);
  auto* collision = bench->add_subcommand(
      "collision", "Collision benchmark: FCL, Embree, CGAL, spatial hashing, ray-based sampling, stepping ROM");
  auto args = std::make_shared<BenchArgs>();
  collision->add_flag("--quick", args->quick, "Small sizes only (about half a minute)");
  collision->add_option("--out", args->out, "Output directory (CSV, report.md, SVG)");
  collision->add_option("--threads", args->threads, "Report figures for 1..N threads")->check(CLI::Range(1, 2));
  collision->add_option("--real-bones", args->lhdl_dir,
                        "Folder of the real CT bones (hip.json, femur and pelvis; default: meshes/real-hips/LHDL_CT relative to the working directory, i.e. run from the source root); skipped in --quick or when absent, with a line on the console and in the report")
      ->check(CLI::ExistingDirectory);
  collision->callback([args] { run(*args); });
  auto probe = std::make_shared<bench::RadialProbeOptions>();
  auto* radial = bench->add_subcommand(
      "radial", "Quick probe: per-pose radial query (all mappings) vs Embree on one scenario");
  radial->add_option("--scenario", probe->family, "cartilage or sphere_cube")
      ->check(CLI::IsMember({"cartilage", "sphere_cube"}));
  radial->add_option("--level", probe->level, "cartilage 0..3, sphere_cube 2..8")->check(CLI::Range(0, 8));
  radial->add_option("--threads", probe->threads, "1 or 2")->check(CLI::Range(1, 2));
  radial->add_option("--repeats", probe->repeats, "Timed runs per method")->check(CLI::Range(1, 100));
  radial->callback([probe] {
    const bench::RadialProbeReport report = bench::run_radial_probe(*probe);
    std::fputs(report.table.c_str(), stdout);
    fail_on_mismatch(report.mismatched, "reported other vertices than the Embree ray caster (bench radial)");
  });
  auto striking_probe = std::make_shared<bench::StrikingProbeOptions>();
  auto* striking = bench->add_subcommand(
      "striking", "Quick probe: per-pose one-pass cylindrical query (every candidate, angular walk) vs FCL on one scenario");
  striking->add_option("--scenario", striking_probe->family, "hip or real_ct")
      ->check(CLI::IsMember({"hip", "real_ct"}));
  striking->add_option("--level", striking_probe->level, "hip 0..3")->check(CLI::Range(0, 3));
  striking->add_option("--real-bones", striking_probe->lhdl_dir, "Folder of the real CT bones (real_ct)")
      ->check(CLI::ExistingDirectory);
  striking->add_option("--threads", striking_probe->threads, "1 or 2")->check(CLI::Range(1, 2));
  striking->add_option("--repeats", striking_probe->repeats, "Timed runs per method")->check(CLI::Range(1, 100));
  striking->callback([striking_probe] {
    const bench::StrikingProbeReport report = bench::run_striking_probe(*striking_probe);
    std::fputs(report.table.c_str(), stdout);
    fail_on_mismatch(report.mismatched, "reported other pairs than the every-candidate query (bench striking)");
  });
});

}  // namespace
}  // namespace hipfai::app
