// The estimator's test on held-out hips, end to end on a small sample: FE tables that keep the
// held-out hips apart, a held-out report whose tables agree with each other when recomputed here,
// and a refinement loop that never picks a held-out or trained hip.
#include "studies/estimator_holdout.h"

#include "core/csv.h"
#include "studies/estimator_holdout_report.h"
#include "studies/estimator_refine.h"
#include "studies/estimator_sample.h"
#include "studies/estimator_sample_fe.h"
#include "studies/estimator_sample_report.h"
#include "studies/results/table_number.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace hipfai::studies {
namespace {

namespace fs = std::filesystem;

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  }
};

Table read_table(const fs::path& file) {
  std::ifstream in(file);
  Table table;
  std::string line;
  std::getline(in, line);
  table.header = split_csv_line(line);
  while (std::getline(in, line)) {
    if (!line.empty()) table.rows.push_back(split_csv_line(line));
  }
  return table;
}

// One sample with its FE (12 hips, coarse, 3 steps) serves the three checks below, run in one
// test so that ctest's one-process-per-test does not make it three times.
struct SampleWithFe {
  fs::path root_;
  SamplePlan plan_;
  SampleFeOptions fe_;
  SampleFeResult truth_;

  SampleWithFe() {
    root_ = fs::path(HIPFAI_BINARY_DIR) / "test-scratch" / "estimator_holdout";
    fs::remove_all(root_);
    SampleOptions options;
    options.n = 8;
    options.held_out = 4;
    options.seed = 12;
    options.design = stats::SamplingDesign::kSobol;
    options.edge_mm = 3.0;
    plan_ = plan_sample(options);
    write_design_csv(plan_, root_ / "sample");
    generate_sample_hips(plan_, root_ / "sample");
    fe_.sample_dir = root_ / "sample";
    fe_.cache_dir = root_ / "cache";
    fe_.level = FeLevel::kCoarse;
    fe_.steps = 3;
    fe_.progress = false;
    truth_ = run_sample_fe(plan_, fe_);
    write_sample_fe_tables(plan_, truth_, fe_.level, root_ / "sample");
  }
  ~SampleWithFe() { fs::remove_all(root_); }
};

void tables_keep_the_held_out_hips_apart(const SampleWithFe& sample) {
  const auto& [root_, plan_, fe_, truth_] = sample;
  ASSERT_EQ(truth_.hips.size(), 12u);
  int failed = 0;
  for (const SampleFeHip& hip : truth_.hips) failed += !hip.error.empty();
  EXPECT_EQ(failed, 0);
  std::set<std::string> train, held_out;
  for (const auto& row : read_table(root_ / "sample" / "steps.csv").rows) train.insert(row[0]);
  for (const auto& row : read_table(root_ / "sample" / "held_out_steps.csv").rows) held_out.insert(row[0]);
  EXPECT_EQ(train.size(), 8u);
  EXPECT_EQ(held_out.size(), 4u);
  for (const auto& hip : held_out) {
    EXPECT_EQ(hip.rfind("held_out_", 0), 0u);
    EXPECT_EQ(train.count(hip), 0u);
  }
  // A re-run takes every FE run from the cache and writes the same tables.
  const std::string before = [&] {
    std::ifstream in(root_ / "sample" / "steps.csv");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  const SampleFeResult again = run_sample_fe(plan_, fe_);
  for (const SampleFeHip& hip : again.hips) EXPECT_TRUE(hip.fe_reused);
  write_sample_fe_tables(plan_, again, fe_.level, root_ / "sample");
  std::ifstream in(root_ / "sample" / "steps.csv");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), before);
}

void report_tables_agree_when_recomputed(const SampleWithFe& sample) {
  const fs::path& root_ = sample.root_;
  HoldoutOptions options;
  options.sample_dir = root_ / "sample";
  options.sizes = {5, 8, 400};  // 400: more than the sample has, skipped
  options.refine_start = 4;
  options.refine_budget = 2;
  options.refine_rounds = 2;
  options.random_repeats = 2;
  options.progress = false;
  const HoldoutResult result = run_estimator_holdout(options);
  const fs::path out = root_ / "holdout";
  write_holdout_report(result, options, out);
  EXPECT_EQ(result.timings.size(), 2u);
  EXPECT_EQ(result.held_out, 4);

  // errors.csv's mean over all hips = the mean of hips.csv's rows, for every size, method, case.
  std::map<std::string, std::pair<double, int>> sums;
  const Table hips = read_table(out / "hips.csv");
  for (const auto& row : hips.rows) {
    const double error = table_number(row[hips.column("mean_error_percent")]);
    EXPECT_EQ(row[hips.column("hip")].rfind("held_out_", 0), 0u);
    if (!std::isfinite(error)) continue;
    auto& sum = sums[row[0] + "," + row[2] + "," + row[3]];
    sum.first += error;
    ++sum.second;
  }
  const Table errors = read_table(out / "errors.csv");
  int checked = 0;
  for (const auto& row : errors.rows) {
    if (row[errors.column("group")] != "all") continue;
    const auto it = sums.find(row[0] + "," + row[1] + "," + row[2]);
    if (it == sums.end()) continue;
    EXPECT_EQ(std::stoi(row[errors.column("hips")]), it->second.second);
    EXPECT_NEAR(table_number(row[errors.column("mean_error_percent")]), it->second.first / it->second.second, 1e-6);
    ++checked;
  }
  EXPECT_EQ(checked, 2 * stats::kNumEstimatorMethods * 2);

  // coverage.csv's counts = the held-out steps of estimates.csv inside their calibrated intervals,
  // and its flagged large errors = the steps off by more than 10 % that carry the flag.
  std::map<std::string, std::array<int, 4>> counted;  // steps, covered, large, large flagged
  const Table estimates = read_table(out / "estimates.csv");
  for (const auto& row : estimates.rows) {
    const double estimate = table_number(row[estimates.column("estimate")]);
    const double fe = table_number(row[estimates.column("fe")]);
    if (!std::isfinite(estimate) || !std::isfinite(fe)) continue;
    const std::string low_text = row[estimates.column("conformal_low")], high_text = row[estimates.column("conformal_high")];
    const double low = low_text == "-inf" ? -INFINITY : table_number(low_text);
    const double high = high_text == "inf" ? INFINITY : table_number(high_text);
    auto& c = counted[row[0] + "," + row[2]];
    ++c[0];
    c[1] += low <= fe && fe <= high;
    const bool large = std::abs(estimate - fe) > 0.1 * std::abs(fe);
    c[2] += large;
    c[3] += large && row[estimates.column("flagged")] == "1";
  }
  const Table coverage = read_table(out / "coverage.csv");
  ASSERT_EQ(coverage.rows.size(), 2u * static_cast<std::size_t>(stats::kNumEstimatorMethods));
  for (const auto& row : coverage.rows) {
    const auto& c = counted.at(row[0] + "," + row[1]);
    EXPECT_EQ(std::stoi(row[coverage.column("steps")]), c[0]);
    EXPECT_EQ(std::stoi(row[coverage.column("covered")]), c[1]);
    EXPECT_EQ(std::stoi(row[coverage.column("large_error_steps")]), c[2]);
    EXPECT_EQ(std::stoi(row[coverage.column("large_error_flagged")]), c[3]);
  }

  // Refinement: every round adds the budget, from train_005..train_008 only, never twice.
  std::map<std::string, std::set<std::string>> added_by_run;
  const Table refine = read_table(out / "refine.csv");
  for (const auto& row : refine.rows) {
    if (row[refine.column("method")] != "depth_nn" || row[refine.column("case")] != "2") continue;
    const int round = std::stoi(row[refine.column("round")]);
    EXPECT_EQ(std::stoi(row[refine.column("training_hips")]), 4 + 2 * round);
    const std::string run = row[0] + row[1] + row[2];
    std::string added = row[refine.column("added")];
    int count = 0;
    for (std::size_t start = 0; !added.empty() && start <= added.size();) {
      const std::size_t end = std::min(added.find(';', start), added.size());
      const std::string hip = added.substr(start, end - start);
      EXPECT_TRUE(hip == "train_005" || hip == "train_006" || hip == "train_007" || hip == "train_008") << hip;
      EXPECT_TRUE(added_by_run[run].insert(hip).second) << hip << " added twice";
      ++count;
      start = end + 1;
    }
    EXPECT_EQ(count, round == 0 ? 0 : 2);
  }
  EXPECT_EQ(added_by_run.size(), 2u + 2u);  // two criteria, two random draws
}

void refine_loop_never_picks_held_out_or_trained_hips(const SampleWithFe& sample) {
  const fs::path& root_ = sample.root_;
  const SampleFeOptions& fe_ = sample.fe_;
  // A model of the first four training hips: their rows of steps.csv.
  const Table steps = read_table(root_ / "sample" / "steps.csv");
  const fs::path subset = root_ / "first4" / "steps.csv";
  fs::create_directories(subset.parent_path());
  {
    std::ofstream out(subset);
    std::ifstream in(root_ / "sample" / "steps.csv");
    std::string line;
    std::getline(in, line);
    out << line << '\n';
    while (std::getline(in, line)) {
      if (line.rfind("train_00", 0) == 0 && line[8] >= '1' && line[8] <= '4') out << line << '\n';
    }
  }
  EstimatorTrainOptions train;
  train.fe = {subset};
  train.hips = root_ / "sample";
  train.progress = false;
  EstimatorModel model = train_estimator_model(train);
  ASSERT_EQ(model.hips.size(), 4u);
  RefineLoopOptions options;
  options.pick.candidates = root_ / "sample";
  options.pick.budget = 3;
  options.pick.criterion = stats::UncertaintyCriterion::kMethodDisagreement;
  options.rounds = 2;
  options.fe = fe_;
  options.held_out = root_ / "sample";
  const RefineLoopResult result = refine_estimator(std::move(model), options);
  ASSERT_EQ(result.rounds.size(), 3u);
  EXPECT_EQ(result.held_out_hips, 4);
  std::set<std::string> added;
  for (const RefineRound& round : result.rounds) {
    for (const auto& dir : round.added) {
      const std::string name = dir.filename().string();
      EXPECT_TRUE(name >= "train_005" && name <= "train_008") << name;
      EXPECT_TRUE(added.insert(name).second) << name;
    }
    EXPECT_TRUE(std::isfinite(round.held_out_error[3][1]));
  }
  EXPECT_EQ(result.rounds[1].added.size(), 3u);
  EXPECT_EQ(result.rounds[2].added.size(), 1u);  // only one candidate left
  EXPECT_EQ(result.model.hips.size(), 8u);
}

TEST(EstimatorHoldout, SampleFeHeldOutReportAndRefineLoop) {
  const SampleWithFe sample;
  {
    SCOPED_TRACE("tables keep the held-out hips apart");
    tables_keep_the_held_out_hips_apart(sample);
  }
  {
    SCOPED_TRACE("report tables agree when recomputed");
    report_tables_agree_when_recomputed(sample);
  }
  {
    SCOPED_TRACE("refine loop never picks held-out or trained hips");
    refine_loop_never_picks_held_out_or_trained_hips(sample);
  }
}

}  // namespace
}  // namespace hipfai::studies
