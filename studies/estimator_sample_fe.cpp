#include "studies/estimator_sample_fe.h"

#include "core/error.h"
#include "core/stopwatch.h"
#include "geometry/hip_model.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/penetration_run.h"
#include "studies/validation_study.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/pipeline/fe_batch.h"
#include "studies/results/hip_fe_table.h"
#endif

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>

namespace hipfai::studies {
namespace {

// The depths of one hip folder over the motion, as `study validate` computes them.
void penetration_of(SampleFeHip& hip, const std::filesystem::path& dir, const Motion& motion, int threads) {
  const auto start = SteadyClock::now();
  const geometry::HipModel model = geometry::load_hip_model(dir);
  const LoadedHip loaded = loaded_hip_from_model(model, dir.filename().string());
  PenetrationOptions penetration;
  penetration.threads = threads;
  StageLog log;
  const PenetrationRun run = compute_penetration(loaded, motion, penetration, log);
  hip.curvilinear_max_mm = run.curvilinear_maxima_mm();
  hip.radial_max_mm = run.radial_maxima_mm();
  hip.penetration_ms = 1e3 * seconds_since(start);
}

#ifdef HIPFAI_WITH_FEM
void read_entry(SampleFeHip& hip, const FeBatchEntry& done, const Motion& motion) {
  hip.fe_reused = done.reused;
  if (!done.error.empty()) {
    hip.error = done.error;
    return;
  }
  const std::filesystem::path table_file = done.entry / "fe.csv";
  const HipFeTable table = read_hip_fe_csv(table_file);
  hip.fe = validation_fe_measures_of(table, motion.steps.size(), table_file);
  double step_s = 0;
  for (const FeStepRecord& step : table.steps) {
    step_s += step.wall_time_s;
    hip.fe_steps_failed += !step.converged();
  }
  std::ifstream timing(done.entry / "timing.txt");
  std::string word;
  if (timing >> word >> hip.fe_s; !timing) hip.fe_s = step_s;
}

// The FE run of a hip folder: the same job, so the same cache entry, however it is solved.
FeBatchJob sample_fe_job(const std::filesystem::path& dir, const SampleFeOptions& options) {
  FeBatchJob job;
  job.id = dir.filename().string();
  job.run.model_dir = dir.string();
  job.run.steps = options.steps;
  job.run.level = options.level;
  return job;
}
#endif

}  // namespace

#ifdef HIPFAI_WITH_FEM
SampleFeHip sample_hip_fe_on_this_rank(std::size_t plan_index, const std::filesystem::path& dir, const Motion& motion,
                                       const SampleFeOptions& options, unsigned int threads) {
  SampleFeHip hip;
  hip.dir = dir;
  hip.plan_index = plan_index;
  penetration_of(hip, dir, motion, static_cast<int>(threads));
  FeBatchEntry done;
  try {
    const FeEntryOnRank made = make_fe_entry_on_this_rank(sample_fe_job(dir, options), options.cache_dir, threads);
    done.entry = made.entry;
    done.source = made.source;
    done.reused = done.source != EntrySource::kMade;
  } catch (const std::exception& e) {
    done.error = e.what();  // as the batch keeps going: the hip is named with why, the others kept
  }
  read_entry(hip, done, motion);
  return hip;
}
#endif

void check_sample_fe_options(const SampleFeOptions& options) {
  if (options.steps < 3) throw_error("estimator sample: --steps must be at least 3");
  if (options.jobs < 1) throw_error("estimator sample: --jobs must be at least 1");
#ifdef HIPFAI_WITH_FEM
  if (!options.program.empty() && !std::filesystem::exists(options.program)) {
    throw_error("estimator sample: FE worker program ", options.program.string(), " not found");
  }
#else
  throw_error("estimator sample: this build has no FE module (configure with HIPFAI_WITH_FEM=ON)");
#endif
}

namespace {

// The depths of each (index, folder) and its FE through one batch, in order.
SampleFeResult run_fe_of(const std::vector<std::pair<std::size_t, std::filesystem::path>>& hips, std::size_t total,
                         const SampleFeOptions& options) {
  const auto start = SteadyClock::now();
  SampleFeResult result;
  result.motion = standing_to_sitting(options.steps);
#ifdef HIPFAI_WITH_FEM
  FeBatchOptions batch;
  batch.cache_dir = options.cache_dir;
  batch.program = options.program;
  batch.jobs = options.jobs;
  batch.progress = options.progress;
  batch.label = "sample FE";
  batch.keep_going = true;
  FeBatch fe(batch);
  for (const auto& [index, dir] : hips) {
    SampleFeHip hip;
    hip.dir = dir;
    hip.plan_index = index;
    penetration_of(hip, dir, result.motion, options.threads);
    if (options.progress) {
      std::printf("sample: penetration [%zu/%zu] %s: max curvilinear %.2f mm, radial %.2f mm (%.1f s)\n", index + 1,
                  total, dir.filename().string().c_str(),
                  *std::max_element(hip.curvilinear_max_mm.begin(), hip.curvilinear_max_mm.end()),
                  *std::max_element(hip.radial_max_mm.begin(), hip.radial_max_mm.end()), hip.penetration_ms / 1e3);
      std::fflush(stdout);
    }
    fe.add(sample_fe_job(dir, options));
    result.hips.push_back(std::move(hip));
  }
  const std::vector<FeBatchEntry> done = fe.finish();
  for (std::size_t k = 0; k < result.hips.size(); ++k) read_entry(result.hips[k], done[k], result.motion);
#endif
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace

SampleFeResult run_sample_fe(const SamplePlan& plan, const SampleFeOptions& options) {
  if (!std::filesystem::is_directory(options.sample_dir)) {
    throw_error(options.sample_dir.string(), ": no such sample folder (make it with `hipfai estimator sample`)");
  }
  check_sample_fe_options(options);
  std::vector<std::pair<std::size_t, std::filesystem::path>> hips;
  int missing = 0;
  for (std::size_t h = 0; h < plan.hips.size(); ++h) {
    const std::filesystem::path dir = options.sample_dir / plan.hips[h].name;
    if (sample_hip_complete(dir)) {
      hips.emplace_back(h, dir);
    } else {
      ++missing;
    }
  }
  SampleFeResult result = run_fe_of(hips, plan.hips.size(), options);
  result.missing = missing;
  return result;
}

SampleFeResult run_hips_fe(const std::vector<std::filesystem::path>& dirs, const SampleFeOptions& options) {
  check_sample_fe_options(options);
  std::vector<std::pair<std::size_t, std::filesystem::path>> hips;
  for (std::size_t h = 0; h < dirs.size(); ++h) {
    if (!sample_hip_complete(dirs[h])) throw_error(dirs[h].string(), ": not a hip folder (no model.json)");
    hips.emplace_back(h, dirs[h]);
  }
  return run_fe_of(hips, dirs.size(), options);
}

}  // namespace hipfai::studies
