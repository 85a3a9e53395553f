// hipfai — the FE of many hips into the FE cache, in worker processes (see fe_batch.h).
#include "studies/fe_batch.h"

#ifdef HIPFAI_WITH_FEM

#include "core/atomic_file.h"
#include "core/child_process.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/stopwatch.h"


#include <algorithm>
#include <atomic>
#include <cstdio>
#include <mutex>
#include <sstream>
#include <thread>

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

// Solves one run into its cache entry (in this process or a worker process with `threads` FE
// threads); writes the run's wall time beside its table.
void solve(const FeBatchJob& job, const std::filesystem::path& entry, const FeBatchOptions& options,
           unsigned int threads) {
  AtomicDirectory staging(entry);
  const std::filesystem::path& partial = staging.partial_path();
  HipFeRunOptions run = job.run;
  run.out_file = (partial / "results.h5").string();
  run.csv_file = (partial / "fe.csv").string();
  if (run.vtu_every > 0) run.vtu_prefix = (partial / "fe").string();
  const auto start = SteadyClock::now();
  if (options.program.empty()) {
    run.progress = false;
    (void)run_hip_fe(run, false);
  } else {
    run.threads = threads;
    const int status = run_program(options.program, hip_fe_command_arguments(run), partial / "run.log", worker_environment());
    // Exit status 1 with a complete table: some steps did not converge (kept, with their status).
    if (status != 0 && !std::filesystem::exists(partial / "fe.csv")) {
      staging.keep();  // the log the message points to
      throw_error("FE of ", job.run.model_dir, " failed (exit status ", status, "); see ",
                  (partial / "run.log").string());
    }
  }
  write_file_atomically(partial / "timing.txt", "wall_s " + seconds_text(seconds_since(start)) + "\n");
  commit_hip_fe_entry(staging);
}

}  // namespace

std::vector<FeBatchEntry> run_fe_batch(const std::vector<FeBatchJob>& jobs, const FeBatchOptions& options) {
  if (options.jobs < 1) throw_error(options.label, ": --jobs must be at least 1");
  std::vector<FeBatchEntry> entries(jobs.size());
  std::vector<std::size_t> to_solve;
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    entries[j].entry = hip_fe_cache_entry(options.cache_dir, hip_fe_cache_key(jobs[j].run));
    entries[j].reused = std::filesystem::exists(entries[j].entry / "fe.csv");
    if (!entries[j].reused) to_solve.push_back(j);
  }
  const int workers = options.program.empty() ? 1 : std::max(1, std::min<int>(options.jobs, static_cast<int>(to_solve.size())));
  // The machine's threads shared among the workers (one each for two workers on two cores; the
  // results do not depend on them).
  const auto worker_threads = static_cast<unsigned int>(std::max(1, resolve_threads(0) / workers));
  if (options.progress) {
    std::printf("%s: FE (level %s) on %zu hips, %zu from the cache, %zu to solve in %d process(es)\n",
                options.label.c_str(), jobs.empty() ? "-" : to_string(jobs.front().run.level), jobs.size(),
                jobs.size() - to_solve.size(), to_solve.size(), workers);
    std::fflush(stdout);
  }
  std::atomic<std::size_t> next{0}, done{0};
  std::mutex mutex;
  std::vector<std::string> errors;
  const auto start = SteadyClock::now();
  auto worker = [&] {
    for (std::size_t k = next++; k < to_solve.size(); k = next++) {
      const std::size_t j = to_solve[k];
      const auto job_start = SteadyClock::now();
      try {
        solve(jobs[j], entries[j].entry, options, worker_threads);
      } catch (const std::exception& error) {
        const std::lock_guard<std::mutex> lock(mutex);
        errors.emplace_back(error.what());
        entries[j].error = error.what();
        continue;
      }
      const std::lock_guard<std::mutex> lock(mutex);
      if (options.progress) {
        const std::size_t finished = ++done;
        std::printf("%s: FE [%zu/%zu] %s in %.0f s (%.0f s elapsed)\n", options.label.c_str(), finished,
                    to_solve.size(), jobs[j].id.c_str(), seconds_since(job_start), seconds_since(start));
        std::fflush(stdout);
      }
    }
  };
  std::vector<std::thread> threads;
  for (int w = 0; w < workers; ++w) threads.emplace_back(worker);
  for (std::thread& thread : threads) thread.join();
  if (!errors.empty() && !options.keep_going) {
    std::string text;
    for (const std::string& e : errors) text += (text.empty() ? "" : "; ") + e;
    throw_error(options.label, ": ", errors.size(), " FE run(s) failed: ", text);
  }
  return entries;
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
