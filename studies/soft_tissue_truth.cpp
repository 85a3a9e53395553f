// hipfai — synthesised soft tissue against known truth (see soft_tissue_truth.h).
#include "studies/soft_tissue_truth.h"

#include "core/error.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "studies/pipeline/mpi_launch.h"
#include "studies/soft_tissue_truth_unit.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/pipeline/fe_batch.h"
#include "studies/soft_tissue_truth_ranks.h"
#endif

#include <algorithm>

namespace hipfai::studies {
namespace {

#ifdef HIPFAI_WITH_FEM
// Both tissue sets of every hip, generated first, through the FE cache: their peaks over the
// motion, or why the FE failed.
void add_fe_peaks(SoftTissueTruthResult& result, const Motion& motion) {
  const SoftTissueTruthOptions& options = result.options;
  std::vector<FeBatchJob> jobs;
  for (const SoftTissueTruthRow& row : result.rows) {
    for (FeBatchJob& job : soft_tissue_fe_jobs(row, options, motion)) jobs.push_back(std::move(job));
  }
  FeBatchOptions batch;
  batch.cache_dir = options.cache_dir;
  batch.program = options.program;
  batch.jobs = options.jobs;
  batch.label = "soft-tissue-truth";
  batch.progress = options.progress;
  batch.keep_going = true;  // a hip whose FE fails is reported with why, the others compared
  const std::vector<FeBatchEntry> entries = run_fe_batch(jobs, batch);
  for (std::size_t h = 0; h < result.rows.size(); ++h) {
    SoftTissueTruthRow& row = result.rows[h];
    for (std::size_t k = 0; k < 2; ++k) {
      const FeBatchEntry& entry = entries[2 * h + k];
      if (!entry.error.empty()) {
        row.fe_error += (row.fe_error.empty() ? "" : "; ") + entry.error;
        continue;
      }
      (k == 0 ? row.generated_fe : row.synthesised_fe) = soft_tissue_fe_peaks(entry.entry);
    }
  }
}
#endif

}  // namespace

SoftTissueTruthResult run_soft_tissue_truth(const SoftTissueTruthOptions& options) {
  const auto start = SteadyClock::now();
#ifndef HIPFAI_WITH_FEM
  if (options.fe_level) throw_error("soft-tissue-truth: this build has no FE (HIPFAI_WITH_FEM off); use --fe-level none");
#else
  if (options.spread == UnitSpread::kMpiRanks && join_mpi_world().size > 1) {
    SoftTissueTruthResult result = run_soft_tissue_truth_over_ranks(options);
    result.seconds = seconds_since(start);
    return result;
  }
#endif
  SoftTissueTruthResult result;
  result.options = options;
  const std::vector<std::pair<double, double>> grid = soft_tissue_truth_grid(options);
  const Motion motion = soft_tissue_truth_motion(options);
  ProgressBar progress("soft tissue known truth", grid.size(), options.progress);
  for (const auto& [ce, alpha] : grid) {
    result.rows.push_back(compare_soft_tissue_hip(ce, alpha, options, motion, result.contact_tolerance_mm));
    progress.advance();
  }
  progress.finish();
#ifdef HIPFAI_WITH_FEM
  if (options.fe_level) add_fe_peaks(result, motion);
#endif
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace hipfai::studies
