// The validation study spread over MPI ranks (studies/validation_ranks.h), run by ctest under
// `mpirun --oversubscribe -np 3` (every rank runs these tests; rank 0 hands out the units and
// checks): the same steps.csv, byte for byte, and the same FE tables (every column but the wall
// times) as the one-process run with its FE worker processes; a hip that cannot be generated is
// named and the other hips' results kept. A --quick-sized study (2 hips at 3 mm, 6 steps, FE
// coarse): about 20 s on 2 cores.
#include "studies/validation_study.h"

#include "studies/pipeline/mpi_launch.h"
#include "tests/mpi/mpi_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace hipfai::studies {
namespace {

namespace fs = std::filesystem;

using mpi_test::read_text;
using mpi_test::sleeping_barrier;
using mpi_test::without_timings;

const fs::path& scratch() {
  static const fs::path root = fs::path(HIPFAI_BINARY_DIR) / "test-scratch" / "validation_ranks";
  return root;
}

ValidationOptions quick_options(const fs::path& out, const fs::path& cache) {
  ValidationOptions options;
  options.out_dir = out;
  options.cache_dir = cache;
  options.hips = {{20, 40}, {40, 60}};
  options.edge_mm = 3.0;
  options.sub_motions = 6;
  options.fe_level = FeLevel::kCoarse;
  options.progress = false;
  return options;
}

TEST(ValidationRanks, SpreadOverRanksEqualsTheOneProcessRun) {
  const MpiWorld world = join_mpi_world();
  ASSERT_GE(world.size, 2) << "run under mpirun -np 2 or more";
  if (world.rank == 0) {
    fs::remove_all(scratch());
    // The one-process run as `hipfai study validate` does it: FE in `hipfai fem run` workers.
    ValidationOptions serial = quick_options(scratch() / "serial", scratch() / "serial-cache");
    serial.program = fs::path(HIPFAI_BINARY_DIR) / "bin" / "hipfai";
    ASSERT_TRUE(fs::exists(serial.program)) << serial.program << ": build the hipfai program first";
    const ValidationResult result = run_validation_study(serial);
    EXPECT_TRUE(result.wrote_tables);
  }
  sleeping_barrier();
  ValidationOptions spread = quick_options(scratch() / "ranks", scratch() / "ranks-cache");  // a cold cache
  spread.spread = UnitSpread::kMpiRanks;
  const ValidationResult result = run_validation_study(spread);
  if (world.rank != 0) {
    EXPECT_FALSE(result.wrote_tables);
    return;
  }
  ASSERT_TRUE(result.wrote_tables);
  EXPECT_TRUE(result.failed.empty());
  ASSERT_EQ(result.hips.size(), 2u);
  for (const ValidationHipTiming& hip : result.hips) {
    EXPECT_FALSE(hip.fe_reused) << "every FE run solved by a worker rank";
    EXPECT_EQ(hip.fe_steps_failed, 0);
  }
  const std::string steps = read_text(scratch() / "ranks" / "steps.csv");
  EXPECT_EQ(std::count(steps.begin(), steps.end(), '\n'), 13);  // header + 2 hips x 6 steps
  EXPECT_EQ(steps, read_text(scratch() / "serial" / "steps.csv"));
  EXPECT_EQ(without_timings(scratch() / "ranks" / "timings.csv"), without_timings(scratch() / "serial" / "timings.csv"));
  // The same FE entries (the same keys), with the same tables at round-trip precision.
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(scratch() / "serial-cache" / "fe")) {
    const fs::path twin = scratch() / "ranks-cache" / "fe" / entry.path().filename();
    ASSERT_TRUE(fs::exists(twin / "fe.csv")) << twin;
    EXPECT_EQ(without_timings(twin / "fe.csv"), without_timings(entry.path() / "fe.csv")) << twin;
    ++entries;
  }
  EXPECT_EQ(entries, 2);
  EXPECT_TRUE(fs::exists(scratch() / "ranks" / "fig61" / "fe.vtu"));
}

TEST(ValidationRanks, AHipThatCannotBeGeneratedIsNamedAndTheOthersKept) {
  const MpiWorld world = join_mpi_world();
  ValidationOptions options = quick_options(scratch() / "failed", scratch() / "ranks-cache");
  options.hips = {{20, 40}, {80, 40}};  // CE 80 is outside the generator's range
  options.spread = UnitSpread::kMpiRanks;
  const ValidationResult result = run_validation_study(options);
  if (world.rank != 0) return;
  ASSERT_EQ(result.failed.size(), 1u);
  EXPECT_EQ(result.failed[0].unit, "ce80_alpha40");
  EXPECT_NE(result.failed[0].message.find("ce_deg"), std::string::npos) << result.failed[0].message;
  EXPECT_EQ(result.failed[0].message.find('\n'), std::string::npos) << "one line";
  ASSERT_EQ(result.hips.size(), 1u);
  EXPECT_EQ(result.hips[0].ce_deg, 20.0);
  // The CE 20 hip's rows are there, as in the full run.
  const std::string steps = read_text(scratch() / "failed" / "steps.csv");
  EXPECT_EQ(std::count(steps.begin(), steps.end(), '\n'), 7);
  EXPECT_EQ(steps.find("80,40,"), std::string::npos);
}

}  // namespace
}  // namespace hipfai::studies
