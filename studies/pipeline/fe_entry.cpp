// hipfai — one hip's FE run made into its cache entry (see fe_entry.h).
#include "studies/pipeline/fe_entry.h"

#ifdef HIPFAI_WITH_FEM

#include "core/atomic_file.h"
#include "core/child_process.h"
#include "core/error.h"
#include "core/stopwatch.h"

#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace hipfai::studies {
namespace {

// The environment of an FE worker: single-threaded BLAS and OpenMP (the worker's own threads are
// its --threads), and nothing of an MPI launcher the parent may have been started under.
std::vector<std::string> worker_environment() {
  std::vector<std::string> env;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    const std::string entry(*e);
    if (entry.rfind("OMPI_", 0) == 0 || entry.rfind("PMIX_", 0) == 0 || entry.rfind("OMP_NUM_THREADS=", 0) == 0 ||
        entry.rfind("OPENBLAS_NUM_THREADS=", 0) == 0) {
      continue;
    }
    env.push_back(entry);
  }
  env.emplace_back("OMP_NUM_THREADS=1");
  env.emplace_back("OPENBLAS_NUM_THREADS=1");
  return env;
}

std::string seconds_text(double seconds) {
  std::ostringstream text;
  text.precision(10);
  text << seconds;
  return text.str();
}

// Solves the run into the entry's temporary folder and writes its wall time beside its table.
void solve_into(const FeBatchJob& job, AtomicDirectory& staging, const std::filesystem::path& entry,
                const FeEntrySolver& solver) {
  const std::filesystem::path& partial = staging.partial_path();
  HipFeRunOptions run = job.run;
  run.out_file = (partial / "results.h5").string();
  run.csv_file = (partial / "fe.csv").string();
  run.results_location = (entry / "results.h5").string();
  if (run.vtu_every > 0) run.vtu_prefix = (partial / "fe").string();
  run.threads = solver.threads;
  const auto start = SteadyClock::now();
  if (solver.program.empty()) {
    run.progress = false;
    (void)run_hip_fe(run, false);
  } else {
    const int status = run_program(solver.program, hip_fe_command_arguments(run), partial / "run.log", worker_environment());
    // Exit status 1 with a complete table: some steps did not converge (kept, with their status).
    if (status != 0 && !std::filesystem::exists(partial / "fe.csv")) {
      staging.keep();  // the log the message points to
      throw_error("FE of ", job.run.model_dir, " failed (exit status ", status, "); see ",
                  (partial / "run.log").string());
    }
  }
  if (!std::filesystem::exists(partial / "fe.csv")) {
    staging.keep();
    throw_error(partial.string(), ": the FE run left no table (fe.csv)");
  }
  write_file_atomically(partial / "timing.txt", "wall_s " + seconds_text(seconds_since(start)) + "\n");
}

}  // namespace

std::filesystem::path fe_job_entry(const FeBatchJob& job, const std::filesystem::path& cache_dir) {
  return hip_fe_cache_entry(cache_dir, hip_fe_cache_key(job.run));
}

bool fe_entry_is_complete(const std::filesystem::path& entry) { return std::filesystem::exists(entry / "fe.csv"); }

EntrySource make_fe_entry(const FeBatchJob& job, const std::filesystem::path& entry, const FeEntrySolver& solver,
                          LockWait wait) {
  return make_cache_entry(
      entry, fe_entry_is_complete, [&](AtomicDirectory& staging) { solve_into(job, staging, entry, solver); }, wait);
}

FeEntryOnRank make_fe_entry_on_this_rank(FeBatchJob job, const std::filesystem::path& cache_dir, unsigned int threads) {
  job.run.ranks = FeRanks::kThisRank;
  FeEntryOnRank made;
  made.entry = fe_job_entry(job, cache_dir);
  made.source = make_fe_entry(job, made.entry, FeEntrySolver{{}, threads}, LockWait::kBlock);
  return made;
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
