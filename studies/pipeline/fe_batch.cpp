// hipfai — the FE of many hips into the FE cache, in worker processes (see fe_batch.h).
#include "studies/pipeline/fe_batch.h"

#ifdef HIPFAI_WITH_FEM

#include "core/atomic_file.h"
#include "core/child_process.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/stopwatch.h"


#include <algorithm>
#include <condition_variable>
#include <deque>
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

struct FeBatch::State {
  FeBatchOptions options;
  int workers = 1;
  unsigned int worker_threads = 1;  // FE threads of each worker process
  // Every job added, in order (deques: the workers hold references while add() appends).
  std::deque<FeBatchJob> jobs;
  std::deque<FeBatchEntry> entries;
  std::deque<std::size_t> queue;    // jobs to solve, not yet taken
  std::size_t queued = 0, reused = 0, finished = 0;
  bool closed = false;              // no more jobs
  std::vector<std::string> errors;
  std::mutex mutex;
  std::condition_variable wake;
  SteadyClock::time_point start = SteadyClock::now();
  std::vector<std::thread> threads;

  void work() {
    for (;;) {
      std::size_t j = 0;
      {
        std::unique_lock<std::mutex> lock(mutex);
        wake.wait(lock, [&] { return closed || !queue.empty(); });
        if (queue.empty()) return;
        j = queue.front();
        queue.pop_front();
      }
      const auto job_start = SteadyClock::now();
      std::string error;
      try {
        solve(jobs[j], entries[j].entry, options, worker_threads);
      } catch (const std::exception& e) {
        error = e.what();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      if (!error.empty()) {
        errors.push_back(error);
        entries[j].error = error;
        continue;
      }
      if (options.progress) {
        std::printf("%s: FE [%zu/%zu] %s in %.0f s (%.0f s elapsed)\n", options.label.c_str(), ++finished,
                    queued, jobs[j].id.c_str(), seconds_since(job_start), seconds_since(start));
        std::fflush(stdout);
      }
    }
  }
  // drain: solve the queued jobs first; otherwise drop them (the batch is abandoned).
  void stop(bool drain) {
    {
      const std::lock_guard<std::mutex> lock(mutex);
      closed = true;
      if (!drain) queue.clear();
    }
    wake.notify_all();
    for (std::thread& thread : threads) thread.join();
    threads.clear();
  }
};

FeBatch::FeBatch(FeBatchOptions options) : state_(std::make_unique<State>()) {
  if (options.jobs < 1) throw_error(options.label, ": --jobs must be at least 1");
  State& s = *state_;
  s.options = std::move(options);
  s.workers = s.options.program.empty() ? 1 : s.options.jobs;
  // The machine's threads shared among the workers (one each for two workers on two cores; the
  // results do not depend on them).
  s.worker_threads = static_cast<unsigned int>(std::max(1, resolve_threads(0) / s.workers));
  // Without a program the runs are solved in this process, on the thread that calls finish():
  // never beside the caller's own work (making a hip forks its mesher).
  if (s.options.program.empty()) return;
  for (int w = 0; w < s.workers; ++w) s.threads.emplace_back([&s] { s.work(); });
}

FeBatch::~FeBatch() {
  if (state_) state_->stop(false);  // after finish() there is nothing left to stop
}

void FeBatch::add(FeBatchJob job) {
  State& s = *state_;
  FeBatchEntry entry;
  entry.entry = hip_fe_cache_entry(s.options.cache_dir, hip_fe_cache_key(job.run));
  entry.reused = std::filesystem::exists(entry.entry / "fe.csv");
  {
    const std::lock_guard<std::mutex> lock(s.mutex);
    if (s.closed) throw_error(s.options.label, ": a job added to a finished FE batch");
    s.jobs.push_back(std::move(job));
    s.entries.push_back(std::move(entry));
    if (s.entries.back().reused) {
      ++s.reused;
    } else {
      s.queue.push_back(s.jobs.size() - 1);
      ++s.queued;
    }
  }
  s.wake.notify_one();
}

std::vector<FeBatchEntry> FeBatch::finish() {
  State& s = *state_;
  s.stop(true);
  if (s.options.program.empty()) s.work();  // closed: solves the queue, then returns
  if (s.options.progress) {
    std::printf("%s: FE (level %s) on %zu hips: %zu from the cache, %zu solved in %d process(es), %.0f s\n",
                s.options.label.c_str(), s.jobs.empty() ? "-" : to_string(s.jobs.front().run.level), s.jobs.size(),
                s.reused, s.queued, s.workers, seconds_since(s.start));
    std::fflush(stdout);
  }
  if (!s.errors.empty() && !s.options.keep_going) {
    std::string text;
    for (const std::string& e : s.errors) text += (text.empty() ? "" : "; ") + e;
    throw_error(s.options.label, ": ", s.errors.size(), " FE run(s) failed: ", text);
  }
  return {s.entries.begin(), s.entries.end()};
}

std::vector<FeBatchEntry> run_fe_batch(const std::vector<FeBatchJob>& jobs, const FeBatchOptions& options) {
  FeBatch batch(options);
  for (const FeBatchJob& job : jobs) batch.add(job);
  return batch.finish();
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
