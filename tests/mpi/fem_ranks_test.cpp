// One FE model on several ranks (`mpirun -np 2 hipfai fem run`, FeRanks::kAll; the substructured
// solver's column solves dealt to the ranks, fem/rank_team.h), run by ctest under
// `mpirun --oversubscribe -np 2`: the steps table of a small model (generated hip at 3 mm, FE
// level coarse, 4 steps) is that of the same model solved by rank 0 alone (FeRanks::kThisRank,
// the path of a study's units) in every column but the wall time and the rank count, with both
// ways of sharing the columns (fem::TeamColumns); the ranks together solved the one-rank run's
// columns, and with kEveryRank each a share (fewer than all). A few seconds on 2 cores.
#include "fem/contact_problem.h"
#include "geometry/hip_generator.h"
#include "geometry/hip_model.h"
#include "studies/pipeline/hip_fe_run.h"

#include <gtest/gtest.h>

#include <mpi.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace hipfai::studies {
namespace {

namespace fs = std::filesystem;

const fs::path& scratch() {
  static const fs::path root = fs::path(HIPFAI_BINARY_DIR) / "test-scratch" / "fem_ranks";
  return root;
}

// A barrier the waiting ranks sleep through (MPI_Barrier would spin them on the cores rank 0
// computes on).
void sleeping_barrier() {
  MPI_Request request;
  MPI_Ibarrier(MPI_COMM_WORLD, &request);
  for (int done = 0; !done;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

// The table without the columns named in `dropped`, row by row.
std::string without_columns(const fs::path& file, const std::set<std::string>& dropped) {
  std::ifstream in(file);
  std::string line, out;
  std::vector<bool> keep;
  while (std::getline(in, line)) {
    std::istringstream cells(line);
    std::string cell;
    for (std::size_t c = 0; std::getline(cells, cell, ','); ++c) {
      if (keep.size() <= c) keep.push_back(!dropped.contains(cell));
      if (keep[c]) out += cell + ',';
    }
    out += '\n';
  }
  return out;
}

HipFeRunOptions small_run(const fs::path& model_dir, const fs::path& out, FeRanks ranks) {
  HipFeRunOptions options;
  options.model_dir = model_dir.string();
  options.level = FeLevel::kCoarse;
  options.steps = 4;
  options.out_file = (out / "results.h5").string();
  options.csv_file = (out / "steps.csv").string();
  options.ranks = ranks;
  options.progress = false;
  return options;
}

unsigned int columns_solved_here(const HipFeRunSummary& summary) {
  unsigned int columns = 0;
  for (const fem::ContactResult& result : summary.results)
    columns += result.statistics.rank_columns;
  return columns;
}

// Rank 0 alone (FeRanks::kThisRank) writes scratch()/one once; then every rank runs the model
// with `team_columns` into scratch()/<name>. Rank 0 gets the columns each rank solved and the
// one-rank run's column count; the other ranks an empty vector.
struct TeamRun {
  std::vector<unsigned int> columns;  // per rank
  unsigned int one_rank_columns = 0;
};

TeamRun run_on_every_rank(fem::TeamColumns team_columns, const std::string& name) {
  fem::ensure_mpi_initialized();
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const fs::path model_dir = scratch() / "ce20_alpha40";
  TeamRun out;
  if (rank == 0) {
    static bool solved_alone = false;  // once per test program, from an empty folder
    if (!solved_alone) {
      solved_alone = true;
      fs::remove_all(scratch());
      geometry::HipParameters parameters;
      parameters.ce_deg = 20.0;
      parameters.alpha_deg = 40.0;
      parameters.edge_mm = 3.0;
      geometry::write_hip_model(geometry::generate_hip(parameters).model, model_dir);
      fs::create_directories(scratch() / "one");
      const HipFeRunSummary one =
          run_hip_fe(small_run(model_dir, scratch() / "one", FeRanks::kThisRank));
      EXPECT_EQ(one.failed, 0u);
      std::ofstream(scratch() / "one" / "columns.txt") << columns_solved_here(one);
    }
    std::ifstream(scratch() / "one" / "columns.txt") >> out.one_rank_columns;
    fs::remove_all(scratch() / name);
    fs::create_directories(scratch() / name);
  }
  sleeping_barrier();
  HipFeRunOptions options = small_run(model_dir, scratch() / name, FeRanks::kAll);
  options.team_columns = team_columns;
  const HipFeRunSummary all = run_hip_fe(options);
  EXPECT_EQ(all.failed, 0u);
  for (const fem::ContactResult& result : all.results)
    EXPECT_EQ(result.statistics.n_ranks, static_cast<unsigned int>(size));
  std::vector<unsigned int> columns(static_cast<std::size_t>(size));
  const unsigned int mine = columns_solved_here(all);
  MPI_Gather(&mine, 1, MPI_UNSIGNED, columns.data(), 1, MPI_UNSIGNED, 0, MPI_COMM_WORLD);
  if (rank == 0) {
    out.columns = std::move(columns);
    EXPECT_EQ(without_columns(scratch() / "one" / "steps.csv", {"wall_time_s", "ranks"}),
              without_columns(scratch() / name / "steps.csv", {"wall_time_s", "ranks"}));
    EXPECT_EQ(std::accumulate(out.columns.begin(), out.columns.end(), 0u), out.one_rank_columns);
  }
  return out;
}

TEST(FeRanks, EveryRankSolvingItsShareEqualsOneRank) {
  const TeamRun run = run_on_every_rank(fem::TeamColumns::kEveryRank, "every_rank");
  for (std::size_t r = 0; r < run.columns.size(); ++r) {
    EXPECT_GT(run.columns[r], 0u) << "rank " << r << " solved no column";
    EXPECT_LT(run.columns[r], run.one_rank_columns) << "rank " << r << " solved every column";
  }
}

TEST(FeRanks, HelpersOnSpareCoresOnlyEqualsOneRank) {
  // Which rank solves how many depends on the cores free at each set of columns (under
  // --oversubscribe, none may be); the numbers may not.
  const TeamRun run = run_on_every_rank(fem::TeamColumns::kSpareCores, "spare_cores");
  if (!run.columns.empty()) {
    EXPECT_GT(run.columns[0], 0u) << "rank 0 solves the first block of every set itself";
  }
}

}  // namespace
}  // namespace hipfai::studies
