// The FAI study, the HJC study and the estimator's leave-one-out spread over MPI ranks
// (studies/fai_ranks.h, studies/hjc_ranks.h, studies/estimator_fold_ranks.h), run by ctest under
// `mpirun --oversubscribe -np 3`: every rank runs these tests, rank 0 first runs the study in one
// process, then every rank runs it spread, and rank 0 compares every CSV the two wrote (timing
// columns left out) and, for the FAI study, the per-step VTP files the worker ranks wrote, byte for
// byte. A hip that cannot be generated is named and the other hips' results kept. Small cases:
// each about 10-30 s on 2 cores.
#include "studies/estimator_study.h"
#include "studies/fai_study.h"
#include "studies/hjc_study.h"
#include "studies/pipeline/mpi_launch.h"
#include "tests/mpi/mpi_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <set>
#include <string>

namespace hipfai::studies {
namespace {

namespace fs = std::filesystem;

using mpi_test::read_text;
using mpi_test::scratch;
using mpi_test::serial_run_on_rank_zero;
using mpi_test::without_timings;

// Every file of `serial` with one of `extensions` (but those named in `skip`) is in `spread` the
// same: CSVs without their timing columns, others byte for byte. Returns how many were compared.
int expect_same_files(const fs::path& serial, const fs::path& spread, const std::set<std::string>& extensions,
                      const std::set<std::string>& skip = {}) {
  int compared = 0;
  for (const auto& entry : fs::recursive_directory_iterator(serial)) {
    const std::string extension = entry.path().extension().string();
    if (!entry.is_regular_file() || !extensions.contains(extension)) continue;
    if (skip.contains(entry.path().filename().string())) continue;
    const fs::path twin = spread / fs::relative(entry.path(), serial);
    EXPECT_TRUE(fs::exists(twin)) << twin;
    if (extension == ".csv") {
      EXPECT_EQ(without_timings(twin), without_timings(entry.path())) << twin;
    } else {
      EXPECT_TRUE(read_text(twin) == read_text(entry.path())) << twin << " differs from " << entry.path();
    }
    ++compared;
  }
  return compared;
}

// Four hips (the archetypes normal, pincer, cam, combined cam-pincer) at 3 mm, 10 steps; the
// resolution table at 5 mm as well (four more units), per-step VTP files of one hip.
FaiStudyOptions small_fai(const fs::path& out) {
  FaiStudyOptions options;
  options.out_dir = out;
  options.cache_dir = out.string() + "-cache";
  options.ce_deg = {20, 40};
  options.alpha_deg = {40, 80};
  options.edge_mm = 3.0;
  options.sub_motions = 10;
  options.resolution_edges_mm = {5.0};
  options.vtp_models = {"ce40_alpha80"};
  options.vtp_steps = {5, 0};
  options.progress = false;
  return options;
}

TEST(FaiRanks, SpreadOverRanksEqualsTheOneProcessRun) {
  const MpiWorld world = join_mpi_world();
  ASSERT_GE(world.size, 2) << "run under mpirun -np 2 or more";
  ASSERT_TRUE(serial_run_on_rank_zero("fai_ranks", [] { run_fai_study(small_fai(scratch("fai_ranks") / "serial")); }));
  FaiStudyOptions spread = small_fai(scratch("fai_ranks") / "ranks");  // a cold cache
  spread.spread = UnitSpread::kMpiRanks;
  const FaiStudyResult result = run_fai_study(spread);
  if (world.rank != 0) {
    EXPECT_FALSE(result.holds_results);
    return;
  }
  ASSERT_TRUE(result.holds_results);
  EXPECT_TRUE(result.failed.empty());
  ASSERT_EQ(result.models.size(), 4u);
  ASSERT_EQ(result.resolution.size(), 2u);
  EXPECT_EQ(result.resolution[0].maxima.size(), 4u) << "the archetypes at 5 mm";
  EXPECT_GT(result.models.back().max_curvilinear_mm, 0.0) << "the CE 40 / alpha 80 hip impinges";
  const fs::path serial = scratch("fai_ranks") / "serial", ranks = scratch("fai_ranks") / "ranks";
  EXPECT_EQ(expect_same_files(serial, ranks, {".csv"}), 3);  // summary, steps, resolution
  EXPECT_EQ(expect_same_files(serial / "vtp", ranks / "vtp", {".vtp"}), 8);  // 4 tissues x 2 steps, from a worker
  EXPECT_GE(expect_same_files(serial, ranks, {".vtp"}), 11);  // and the coloured hip from rank 0
}

TEST(FaiRanks, AHipThatCannotBeGeneratedIsNamedAndTheOthersKept) {
  const MpiWorld world = join_mpi_world();
  FaiStudyOptions options = small_fai(scratch("fai_ranks") / "failed");
  options.ce_deg = {20, 80};  // CE 80 is outside the generator's range
  options.alpha_deg = {40};
  options.resolution_edges_mm.clear();
  options.spread = UnitSpread::kMpiRanks;
  const FaiStudyResult result = run_fai_study(options);
  if (world.rank != 0) return;
  ASSERT_EQ(result.failed.size(), 1u);
  EXPECT_EQ(result.failed[0].unit, "ce80_alpha40");
  EXPECT_NE(result.failed[0].message.find("ce_deg"), std::string::npos) << result.failed[0].message;
  EXPECT_EQ(result.failed[0].message.find('\n'), std::string::npos) << "one line";
  ASSERT_EQ(result.models.size(), 1u);
  EXPECT_EQ(result.models[0].ce_deg, 20.0);
  const std::string steps = read_text(options.out_dir / "steps.csv");
  EXPECT_EQ(std::count(steps.begin(), steps.end(), '\n'), 11);  // header + 1 hip x 10 steps
}

// The --quick study (two subjects at 3 mm, one centre offset) in 15 deg steps.
HjcStudyOptions small_hjc(const fs::path& out) {
  HjcStudyOptions options = quick_hjc_study_options({});
  options.out_dir = out;
  options.step_deg = 15.0;
  options.progress = false;
  return options;
}

TEST(HjcRanks, SpreadOverRanksEqualsTheOneProcessRun) {
  const MpiWorld world = join_mpi_world();
  ASSERT_GE(world.size, 2) << "run under mpirun -np 2 or more";
  ASSERT_TRUE(serial_run_on_rank_zero("hjc_ranks", [] { run_hjc_study(small_hjc(scratch("hjc_ranks") / "serial")); }));
  HjcStudyOptions spread = small_hjc(scratch("hjc_ranks") / "ranks");
  spread.spread = UnitSpread::kMpiRanks;
  const HjcStudyResult result = run_hjc_study(spread);
  if (world.rank != 0) {
    EXPECT_FALSE(result.holds_results);
    return;
  }
  ASSERT_TRUE(result.holds_results);
  EXPECT_TRUE(result.failed.empty());
  ASSERT_EQ(result.subjects.size(), 2u);
  EXPECT_EQ(result.subjects[0].id, "ce20_alpha40");
  EXPECT_EQ(expect_same_files(scratch("hjc_ranks") / "serial", scratch("hjc_ranks") / "ranks", {".csv"}), 1);
  const std::string steps = read_text(scratch("hjc_ranks") / "ranks" / "steps.csv");
  EXPECT_GT(std::count(steps.begin(), steps.end(), '\n'), 100);
}

TEST(HjcRanks, ASubjectThatCannotBeGeneratedIsNamedAndTheOthersKept) {
  const MpiWorld world = join_mpi_world();
  HjcStudyOptions options = small_hjc(scratch("hjc_ranks") / "failed");
  options.subjects = {{80.0, 40.0}, {20.0, 40.0}};
  options.step_deg = 15.0;
  options.spread = UnitSpread::kMpiRanks;
  const HjcStudyResult result = run_hjc_study(options);
  if (world.rank != 0) return;
  ASSERT_EQ(result.failed.size(), 1u);
  EXPECT_EQ(result.failed[0].unit, "ce80_alpha40");
  EXPECT_EQ(result.failed[0].message.find('\n'), std::string::npos) << "one line";
  ASSERT_EQ(result.subjects.size(), 1u);
  EXPECT_EQ(result.subjects[0].id, "ce20_alpha40");
  EXPECT_TRUE(fs::exists(options.out_dir / "steps.csv"));
}

// `estimator validate --quick`: five hips' FE (coarse, 6 steps) made by the validation study, then
// the leave-one-out. The spread run shares the one-process run's cache, so its FE comes from there
// (the FE spread is mpi.validation_ranks') and the folds are what it spreads.
EstimatorValidateOptions quick_estimator(const fs::path& out) {
  EstimatorValidateOptions options;
  options.out_dir = out;
  options.quick_cache = scratch("estimator_ranks") / "cache";
  options.quick_program = fs::path(HIPFAI_BINARY_DIR) / "bin" / "hipfai";
  options.train.progress = false;
  return options;
}

TEST(EstimatorRanks, FoldsSpreadOverRanksEqualTheOneProcessRun) {
  const MpiWorld world = join_mpi_world();
  ASSERT_GE(world.size, 2) << "run under mpirun -np 2 or more";
  ASSERT_TRUE(serial_run_on_rank_zero("estimator_ranks", [] {
    const EstimatorValidateOptions serial = quick_estimator(scratch("estimator_ranks") / "serial");
    ASSERT_TRUE(fs::exists(serial.quick_program)) << serial.quick_program << ": build the hipfai program first";
    EXPECT_TRUE(validate_estimator(serial).wrote_report);
  }));
  EstimatorValidateOptions spread = quick_estimator(scratch("estimator_ranks") / "ranks");
  spread.spread = UnitSpread::kMpiRanks;
  const EstimatorValidateSummary summary = validate_estimator(spread);
  if (world.rank != 0) {
    EXPECT_FALSE(summary.wrote_report);
    return;
  }
  ASSERT_TRUE(summary.wrote_report);
  EXPECT_EQ(summary.hips[1], 5);
  // loo.csv, estimates.csv, hips.csv, coverage.csv and the FE's steps.csv; the FE's timings.csv
  // differs in fe_reused only (every FE run from the cache here).
  const fs::path serial = scratch("estimator_ranks") / "serial", ranks = scratch("estimator_ranks") / "ranks";
  EXPECT_EQ(expect_same_files(serial, ranks, {".csv"}, {"timings.csv"}), 5);
  std::string reused = without_timings(ranks / "fe" / "timings.csv");
  EXPECT_EQ(std::count(reused.begin(), reused.end(), '\n'), 6);
  EXPECT_EQ(reused.find(",coarse,0,"), std::string::npos) << reused;
  const std::string loo = read_text(scratch("estimator_ranks") / "ranks" / "loo.csv");
  EXPECT_GT(std::count(loo.begin(), loo.end(), '\n'), 100);
}

}  // namespace
}  // namespace hipfai::studies
