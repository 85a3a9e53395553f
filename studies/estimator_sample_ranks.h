// hipfai — an `estimator sample` spread over the ranks of an MPI job (studies/pipeline/spread_units.h),
// the way a training set of hundreds or thousands of hips is made on a cluster: each unit is one hip
// of the plan, which a worker rank generates (unless its folder is complete) and, with FE options,
// whose depths over standing-to-sitting and FE it computes alone (the FE on MPI_COMM_SELF, into the
// shared cache entry `run_sample_fe` would use). Rank 0 hands out the hips as ranks come free and
// gets each one's outcome back, so it writes the same design, tables and summary as the one-process
// run (studies/estimator_sample_report.h): the same numbers bit for bit, as each FE run is solved on
// one rank either way.
//
// A hip the generator cannot make, or whose FE fails, is reported with its name and why; the others
// are kept. A job killed mid-way and re-run skips the finished hips and takes their FE from the cache.
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "studies/estimator_sample.h"
#include "studies/estimator_sample_fe.h"

#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

namespace hipfai::studies {

struct SampleRankRun {
  bool holds_results = false;             // this is rank 0: it has the outcomes
  std::vector<SampleHipOutcome> outcomes;  // rank 0: one per hip of the plan, in plan order
  std::optional<SampleFeResult> fe;        // rank 0, with FE options: as run_sample_fe returns it
};

// Collective over MPI_COMM_WORLD (at least 2 ranks). `fe` null: the hips are only generated.
// `on_hip(index, outcome, fe_hip)` on rank 0 as each hip's reply arrives (fe_hip null without FE
// or when the hip was not generated), for progress. Throws (on every rank) what check_sample_fe_options
// throws, before any work.
SampleRankRun run_sample_over_ranks(
    const SamplePlan& plan, const std::filesystem::path& out_dir, const SampleFeOptions* fe,
    const std::function<void(std::size_t index, int rank, const SampleHipOutcome&, const SampleFeHip*)>& on_hip = {});

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
