// hipfai — the ground truth of an `estimator sample`: for each of its hips, the penetration
// method's depths over standing-to-sitting (studies/pipeline/penetration_run.h, as `study
// validate` computes them) and its FE run through the FE cache (studies/pipeline/fe_batch.h,
// `jobs` worker processes, each run solved once and kept), read back as the validation study's
// FE measures. The tables are written by studies/estimator_sample_report.h: steps.csv holds the
// training hips only, held_out_steps.csv the held-out ones, so that `estimator train --fe <dir>`
// can never train on a held-out hip.
//
// A killed run resumes: hips already generated are kept, finished FE runs come from the cache.
#pragma once

#include "core/fe_choices.h"
#include "studies/estimator_sample.h"
#include "studies/pipeline/motion.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

struct SampleFeOptions {
  std::filesystem::path sample_dir;      // the `estimator sample` folder (its hips are complete)
  std::filesystem::path cache_dir = "cache";
  FeLevel level = FeLevel::kDefault;
  int steps = 30;                        // sub-motions of standing-to-sitting
  int jobs = 2;                          // FE worker processes
  int threads = 2;                       // threads of the penetration queries
  std::filesystem::path program;         // the hipfai executable the FE workers run
  bool progress = true;
};

struct SampleFeHip {
  std::filesystem::path dir;                  // the hip's folder
  std::size_t plan_index = 0;                 // into SamplePlan::hips (run_sample_fe)
  std::vector<double> curvilinear_max_mm;     // per step
  std::vector<double> radial_max_mm;
  std::vector<std::vector<double>> fe;        // [measure][step] (validation_fe_measures()), NaN: not converged
  double penetration_ms = 0;
  double fe_s = 0;                            // the run's wall time when it was solved
  bool fe_reused = false;
  int fe_steps_failed = 0;
  std::string error;                          // the hip could not be used (FE run failed); the others are kept
};

struct SampleFeResult {
  Motion motion;
  std::vector<SampleFeHip> hips;  // the complete hips of the plan, in plan order
  int missing = 0;                // plan hips without a folder (not generated)
  double seconds = 0;
};

// Throws hipfai::Error for unusable options (no --jobs, --steps < 3, a missing FE program, a build
// without the FE module).
void check_sample_fe_options(const SampleFeOptions& options);

#ifdef HIPFAI_WITH_FEM
// One hip's depths over `motion` and its FE, solved in this process on this rank alone
// (FeRanks::kThisRank) with `threads`, through the same cache entry run_sample_fe uses: a unit of
// a sample spread over MPI ranks (studies/estimator_sample_ranks.h). An FE run that fails is the
// hip's error, as in run_sample_fe.
SampleFeHip sample_hip_fe_on_this_rank(std::size_t plan_index, const std::filesystem::path& dir, const Motion& motion,
                                       const SampleFeOptions& options, unsigned int threads);
#endif

// Throws hipfai::Error for unusable options (no such folder, --jobs < 1, --steps < 3, a missing
// FE program) before any work.
SampleFeResult run_sample_fe(const SamplePlan& plan, const SampleFeOptions& options);

// The same for any hip model folders (options.sample_dir is not read): one result per folder, in
// order (plan_index = the folder's index). Used by `estimator refine` for the hips it picks.
SampleFeResult run_hips_fe(const std::vector<std::filesystem::path>& dirs, const SampleFeOptions& options);

}  // namespace hipfai::studies
