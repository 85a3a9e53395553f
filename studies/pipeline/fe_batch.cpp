// hipfai — the FE of many hips into the FE cache, in worker processes (see fe_batch.h).
#include "studies/pipeline/fe_batch.h"

#ifdef HIPFAI_WITH_FEM

#include "core/error.h"
#include "core/parallel.h"
#include "core/stopwatch.h"


#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <cstdio>
#include <mutex>
#include <thread>

namespace hipfai::studies {
namespace {

// How long a worker whose only jobs are being solved by other jobs waits before looking again
// (or until a new job is added).
constexpr std::chrono::milliseconds kBusyEntryPoll{500};

}  // namespace

struct FeBatch::State {
  FeBatchOptions options;
  int workers = 1;
  unsigned int worker_threads = 1;  // FE threads of each worker process
  // Every job added, in order (deques: the workers hold references while add() appends).
  std::deque<FeBatchJob> jobs;
  std::deque<FeBatchEntry> entries;
  std::deque<std::size_t> queue;    // jobs to solve, not yet taken
  std::deque<std::size_t> busy;     // jobs whose entry another job was solving when last tried
  std::size_t queued = 0, reused = 0, finished = 0, made_elsewhere = 0;
  bool closed = false;              // no more jobs
  std::vector<std::string> errors;
  std::mutex mutex;
  std::condition_variable wake;
  SteadyClock::time_point start = SteadyClock::now();
  std::vector<std::thread> threads;

  void work() {
    for (;;) {
      std::size_t j = 0;
      bool retried = false;  // a job put aside before: wait a little when it is still busy
      {
        std::unique_lock<std::mutex> lock(mutex);
        wake.wait(lock, [&] { return closed || !queue.empty() || !busy.empty(); });
        if (!queue.empty()) {
          j = queue.front();
          queue.pop_front();
        } else if (!busy.empty()) {
          j = busy.front();
          busy.pop_front();
          retried = true;
        } else {
          return;
        }
      }
      const auto job_start = SteadyClock::now();
      std::string error;
      EntrySource source = EntrySource::kBusy;
      try {
        source = make_fe_entry(jobs[j], entries[j].entry, FeEntrySolver{options.program, worker_threads}, LockWait::kTry);
      } catch (const std::exception& e) {
        error = e.what();
      }
      std::unique_lock<std::mutex> lock(mutex);
      if (!error.empty()) {
        errors.push_back(error);
        entries[j].error = error;
        continue;
      }
      if (source == EntrySource::kBusy) {
        busy.push_back(j);
        if (retried) wake.wait_for(lock, kBusyEntryPoll);
        continue;
      }
      entries[j].source = source;
      entries[j].reused = source != EntrySource::kMade;
      made_elsewhere += source != EntrySource::kMade;
      if (options.progress) {
        std::printf("%s: FE [%zu/%zu] %s %s in %.0f s (%.0f s elapsed)\n", options.label.c_str(), ++finished,
                    queued, jobs[j].id.c_str(), source == EntrySource::kMade ? "solved" : "made by another job",
                    seconds_since(job_start), seconds_since(start));
        std::fflush(stdout);
      }
    }
  }
  // drain: solve the queued jobs first; otherwise drop them (the batch is abandoned).
  void stop(bool drain) {
    {
      const std::lock_guard<std::mutex> lock(mutex);
      closed = true;
      if (!drain) {
        queue.clear();
        busy.clear();
      }
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
  entry.entry = fe_job_entry(job, s.options.cache_dir);
  entry.reused = fe_entry_is_complete(entry.entry);
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
    std::printf(
        "%s: FE (level %s) on %zu hips: %zu from the cache, %zu solved in %d process(es), %zu made by another job, "
        "%.0f s\n",
        s.options.label.c_str(), s.jobs.empty() ? "-" : to_string(s.jobs.front().run.level), s.jobs.size(), s.reused,
        s.queued - s.made_elsewhere - s.errors.size(), s.workers, s.made_elsewhere, seconds_since(s.start));
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
