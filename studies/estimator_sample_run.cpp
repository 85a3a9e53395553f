#include "studies/estimator_sample_run.h"

#include "core/error.h"
#include "studies/estimator_sample_report.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/estimator_sample_ranks.h"
#include "studies/pipeline/spread_units.h"
#endif

#include <sstream>

namespace hipfai::studies {
namespace {

bool failed(const SampleHipOutcome& outcome) { return outcome.status == SampleHipOutcome::Status::kFailed; }

#ifdef HIPFAI_WITH_FEM
EstimatorSampleRun run_over_ranks(const SamplePlan& plan, const std::filesystem::path& out_dir,
                                  const std::optional<SampleFeOptions>& fe,
                                  const std::function<void(const std::string&, bool)>& say) {
  // Rank 0 writes the design; a folder holding another one stops every rank with its message.
  std::string design_error;
  if (join_mpi_world().rank == 0) {
    try {
      write_design_csv(plan, out_dir);
    } catch (const Error& e) {
      design_error = e.what();
    }
  }
  share_from_rank_zero(MPI_COMM_WORLD, design_error);
  if (!design_error.empty()) throw Error(design_error);
  std::size_t done = 0;
  SampleRankRun spread = run_sample_over_ranks(
      plan, out_dir, fe ? &*fe : nullptr,
      [&](std::size_t index, int rank, const SampleHipOutcome& outcome, const SampleFeHip* hip) {
        std::ostringstream line;
        line << sample_hip_line(plan, index, outcome) << " (rank " << rank << ", " << ++done << " of "
             << plan.hips.size() << " done)";
        if (hip && hip->error.empty()) {
          line << "; FE " << (hip->fe_reused ? "from the cache" : "solved") << ", " << hip->fe_steps_failed
               << " steps not converged";
        }
        if (say) say(line.str(), failed(outcome));
      });
  EstimatorSampleRun run;
  run.holds_results = spread.holds_results;
  run.outcomes = std::move(spread.outcomes);
  run.fe = std::move(spread.fe);
  return run;
}
#endif

}  // namespace

EstimatorSampleRun run_estimator_sample(const SamplePlan& plan, const std::filesystem::path& out_dir,
                                        const std::optional<SampleFeOptions>& fe, UnitSpread spread,
                                        const std::function<void(const std::string& line, bool failed)>& say) {
#ifdef HIPFAI_WITH_FEM
  if (spread == UnitSpread::kMpiRanks && join_mpi_world().size > 1) return run_over_ranks(plan, out_dir, fe, say);
#else
  (void)spread;
#endif
  write_design_csv(plan, out_dir);
  EstimatorSampleRun run;
  run.outcomes = generate_sample_hips(plan, out_dir, [&](std::size_t index, const SampleHipOutcome& outcome) {
    if (say) say(sample_hip_line(plan, index, outcome), failed(outcome));
  });
  if (fe) run.fe = run_sample_fe(plan, *fe);
  return run;
}

}  // namespace hipfai::studies
