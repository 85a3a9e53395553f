// The cohort studies spread over MPI ranks: the soft-tissue known truth (studies/soft_tissue_truth_ranks.h)
// and an estimator training sample, generation and FE (studies/estimator_sample_ranks.h). Run by ctest
// under `mpirun --oversubscribe -np 3`: rank 0 first runs the study in one process (its FE in
// `hipfai fem run` worker processes, as the command does), then every rank runs it spread, each FE
// run solved on one worker rank alone, and rank 0 compares the tables the two wrote (timing columns
// left out). A hip that cannot be generated is named and the other hips' results kept.
#include "studies/estimator_sample.h"
#include "studies/estimator_sample_fe.h"
#include "studies/estimator_sample_ranks.h"
#include "studies/estimator_sample_report.h"
#include "studies/pipeline/mpi_launch.h"
#include "studies/soft_tissue_truth.h"
#include "studies/soft_tissue_truth_report.h"
#include "tests/mpi/mpi_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <string>

namespace hipfai::studies {
namespace {

namespace fs = std::filesystem;

using mpi_test::read_text;
using mpi_test::scratch;
using mpi_test::serial_run_on_rank_zero;
using mpi_test::without_timings;

fs::path program() { return fs::path(HIPFAI_BINARY_DIR) / "bin" / "hipfai"; }

long lines_of(const fs::path& file) {
  const std::string text = read_text(file);
  return std::count(text.begin(), text.end(), '\n');
}

// --quick: CE 20 / alpha 80 and CE 40 / alpha 40 at 3 mm, 10 sub-motions, FE coarse; each run
// with its own (cold) cache.
SoftTissueTruthOptions quick_truth(const fs::path& out) {
  SoftTissueTruthOptions options;
  options.quick = true;
  options.fe_level = FeLevel::kCoarse;
  options.out_dir = out;
  options.cache_dir = out.string() + "-cache";
  options.program = program();
  options.progress = false;
  return options;
}

TEST(SoftTissueTruthRanks, SpreadOverRanksEqualsTheOneProcessRun) {
  const MpiWorld world = join_mpi_world();
  ASSERT_GE(world.size, 2) << "run under mpirun -np 2 or more";
  const fs::path root = scratch("soft_tissue_truth_ranks");
  ASSERT_TRUE(serial_run_on_rank_zero("soft_tissue_truth_ranks", [&] {
    ASSERT_TRUE(fs::exists(program())) << program() << ": build the hipfai program first";
    write_soft_tissue_truth(run_soft_tissue_truth(quick_truth(root / "serial")));
  }));
  SoftTissueTruthOptions spread = quick_truth(root / "ranks");
  spread.spread = UnitSpread::kMpiRanks;
  const SoftTissueTruthResult result = run_soft_tissue_truth(spread);
  if (world.rank != 0) {
    EXPECT_FALSE(result.holds_results);
    return;
  }
  ASSERT_TRUE(result.holds_results);
  EXPECT_TRUE(result.failed.empty());
  ASSERT_EQ(result.rows.size(), 2u);
  EXPECT_EQ(result.rows[0].hip, "ce20_alpha80");
  for (const SoftTissueTruthRow& row : result.rows) {
    EXPECT_TRUE(row.fe_error.empty()) << row.hip << ": " << row.fe_error;
    ASSERT_TRUE(row.generated_fe && row.synthesised_fe) << row.hip;
    EXPECT_GT(row.synthesised_fe->ball_pressure_mpa, 0.0) << row.hip;
    EXPECT_EQ(row.synthesised_fe->steps, 10) << row.hip;
  }
  write_soft_tissue_truth(result);
  const std::string serial = without_timings(root / "serial" / "soft_tissue_truth.csv");
  EXPECT_EQ(without_timings(root / "ranks" / "soft_tissue_truth.csv"), serial);
  EXPECT_EQ(std::count(serial.begin(), serial.end(), '\n'), 3);  // header + 2 hips
  // Every FE run solved once, on a worker rank (a cold cache): four entries.
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(spread.cache_dir / "fe")) entries += entry.is_directory();
  EXPECT_EQ(entries, 4);
}

TEST(SoftTissueTruthRanks, AHipThatCannotBeGeneratedIsNamedAndTheOthersKept) {
  const MpiWorld world = join_mpi_world();
  SoftTissueTruthOptions options = quick_truth(scratch("soft_tissue_truth_ranks") / "failed");
  options.fe_level.reset();
  options.hips = {{80.0, 40.0}, {20.0, 80.0}};  // CE 80 is outside the generator's range
  options.spread = UnitSpread::kMpiRanks;
  const SoftTissueTruthResult result = run_soft_tissue_truth(options);
  if (world.rank != 0) return;
  ASSERT_EQ(result.failed.size(), 1u);
  EXPECT_EQ(result.failed[0].unit, "ce80_alpha40");
  EXPECT_NE(result.failed[0].message.find("ce_deg"), std::string::npos) << result.failed[0].message;
  EXPECT_EQ(result.failed[0].message.find('\n'), std::string::npos) << "one line";
  ASSERT_EQ(result.rows.size(), 1u);
  EXPECT_EQ(result.rows[0].hip, "ce20_alpha80");
  const fs::path report = write_soft_tissue_truth(result);
  EXPECT_NE(read_text(report).find("ce80_alpha40"), std::string::npos) << "the report names the failed hip";
  EXPECT_EQ(lines_of(options.out_dir / "soft_tissue_truth.csv"), 2);
}

// Three training hips and one held-out hip at 3 mm; FE coarse over 6 steps.
SamplePlan small_plan(double ce_shift = 0.0) {
  SampleOptions options;
  options.n = 3;
  options.held_out = 1;
  options.seed = 7;
  options.edge_mm = 3.0;
  SamplePlan plan = plan_sample(options);
  for (SampledHip& hip : plan.hips) hip.parameters.ce_deg += ce_shift;
  return plan;
}

SampleFeOptions small_fe(const fs::path& out) {
  SampleFeOptions fe;
  fe.sample_dir = out;
  fe.cache_dir = out.string() + "-cache";
  fe.level = FeLevel::kCoarse;
  fe.steps = 6;
  fe.program = program();
  fe.progress = false;
  return fe;
}

TEST(EstimatorSampleRanks, SpreadOverRanksEqualsTheOneProcessRun) {
  const MpiWorld world = join_mpi_world();
  ASSERT_GE(world.size, 2) << "run under mpirun -np 2 or more";
  const fs::path root = scratch("estimator_sample_ranks");
  const SamplePlan plan = small_plan();
  ASSERT_TRUE(serial_run_on_rank_zero("estimator_sample_ranks", [&] {
    ASSERT_TRUE(fs::exists(program())) << program() << ": build the hipfai program first";
    const SampleFeOptions fe = small_fe(root / "serial");
    write_design_csv(plan, fe.sample_dir);
    generate_sample_hips(plan, fe.sample_dir);
    write_sample_fe_tables(plan, run_sample_fe(plan, fe), fe.level, fe.sample_dir);
  }));
  const SampleFeOptions fe = small_fe(root / "ranks");
  const SampleRankRun run = run_sample_over_ranks(plan, fe.sample_dir, &fe);
  if (world.rank != 0) {
    EXPECT_FALSE(run.holds_results);
    return;
  }
  ASSERT_TRUE(run.holds_results);
  ASSERT_EQ(run.outcomes.size(), 4u);
  for (const SampleHipOutcome& outcome : run.outcomes) {
    EXPECT_EQ(outcome.status, SampleHipOutcome::Status::kGenerated) << outcome.error;
  }
  ASSERT_TRUE(run.fe);
  ASSERT_EQ(run.fe->hips.size(), 4u);
  for (const SampleFeHip& hip : run.fe->hips) EXPECT_TRUE(hip.error.empty()) << hip.dir << ": " << hip.error;
  write_sample_fe_tables(plan, *run.fe, fe.level, fe.sample_dir);
  for (const char* table : {"steps.csv", "held_out_steps.csv", "timings.csv"}) {
    EXPECT_EQ(without_timings(root / "ranks" / table), without_timings(root / "serial" / table)) << table;
  }
  EXPECT_EQ(lines_of(root / "ranks" / "steps.csv"), 1 + 3 * 6);  // header + 3 training hips x 6 steps
  EXPECT_EQ(lines_of(root / "ranks" / "held_out_steps.csv"), 1 + 6);
  // The hips' meshes are the one-process run's, byte for byte (generated on worker ranks).
  for (const SampledHip& hip : plan.hips) {
    EXPECT_TRUE(read_text(root / "ranks" / hip.name / "femur_bone.ply") ==
                read_text(root / "serial" / hip.name / "femur_bone.ply"))
        << hip.name;
  }
}

TEST(EstimatorSampleRanks, AHipThatCannotBeGeneratedIsNamedAndTheOthersKept) {
  const MpiWorld world = join_mpi_world();
  SamplePlan plan = small_plan();
  plan.hips[1].parameters.ce_deg = 80.0;  // outside the generator's range
  const fs::path out = scratch("estimator_sample_ranks") / "failed";
  if (world.rank == 0) fs::remove_all(out);
  mpi_test::sleeping_barrier();
  const SampleFeOptions fe = small_fe(out);
  const SampleRankRun run = run_sample_over_ranks(plan, out, &fe);
  if (world.rank != 0) return;
  ASSERT_EQ(run.outcomes.size(), 4u);
  EXPECT_EQ(run.outcomes[1].status, SampleHipOutcome::Status::kFailed);
  EXPECT_NE(run.outcomes[1].error.find("ce_deg"), std::string::npos) << run.outcomes[1].error;
  EXPECT_EQ(sample_hip_line(plan, 1, run.outcomes[1]).find('\n'), std::string::npos) << "one line";
  ASSERT_TRUE(run.fe);
  EXPECT_EQ(run.fe->missing, 1);
  ASSERT_EQ(run.fe->hips.size(), 3u) << "the other hips' FE kept";
  for (const SampleFeHip& hip : run.fe->hips) EXPECT_NE(hip.plan_index, 1u);
}

}  // namespace
}  // namespace hipfai::studies
