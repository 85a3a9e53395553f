// hipfai — the FE of many hips into the FE cache, in worker processes: the one place a study
// solves FE runs it does not have yet (studies/pipeline/hip_fe_run.h has the run, its key and its entry).
//
// run_fe_batch() keys every job (hip_fe_cache_key), takes the finished entries from the cache and
// solves the rest, each in a `hipfai fem run` worker process (`jobs` at once, sharing the machine's
// threads; no MPI launcher's environment) or, without a program, one after the other in this process. A
// worker is killed with the study (PR_SET_PDEATHSIG), and an entry exists only when complete
// (studies/pipeline/fe_entry.h), so a killed batch resumes where it stopped.
//
// Jobs sharing the cache: an entry another job (another study, another user) is solving at the
// moment is put aside and the batch's next job taken; the entry is looked at again when nothing
// else is left, and read once the other job has finished it. Each entry is thus solved once, and
// two studies of the same hips started together share the work instead of doing it twice.
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "studies/pipeline/fe_entry.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace hipfai::studies {

struct FeBatchOptions {
  std::filesystem::path cache_dir = "cache";
  // The hipfai executable the workers run; empty: the runs are solved in this process.
  std::filesystem::path program;
  int jobs = 2;                      // worker processes at once
  bool progress = true;              // a line per finished run on stdout
  std::string label = "FE";          // prefix of those lines ("validate", ...)
  // A run that fails is recorded in its entry (FeBatchEntry::error) and the others go on, instead
  // of an error for the batch.
  bool keep_going = false;
};

struct FeBatchEntry {
  std::filesystem::path entry;       // the cache entry's folder (fe.csv, results.h5, timing.txt)
  bool reused = false;               // not solved by this batch: found in the cache, or made by another job
  EntrySource source = EntrySource::kFound;  // which of the two, or kMade
  std::string error;                 // keep_going: why the run failed (empty: it did not)
};

// A batch that takes its jobs while it runs: its workers start at once and solve each job as it
// is added, so a study can make its next hip while the FE of the earlier ones runs (the machine's
// cores are shared by both). Jobs are solved in the order they are added. Without a program the
// runs are solved in this process, one after the other, when finish() is called.
class FeBatch {
 public:
  explicit FeBatch(FeBatchOptions options);
  ~FeBatch();  // without finish(): the queued jobs are dropped, the running ones end
  FeBatch(const FeBatch&) = delete;
  FeBatch& operator=(const FeBatch&) = delete;

  // Keys the job and queues it, unless its entry is in the cache already.
  void add(FeBatchJob job);
  // No more jobs: waits for the workers. One entry per job, in the order added. Throws
  // hipfai::Error naming every run that failed (a worker that left no table: its run.log is kept
  // and named), unless keep_going; the other runs stay cached.
  std::vector<FeBatchEntry> finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The jobs through one FeBatch: one entry per job, in the jobs' order (see FeBatch::finish).
std::vector<FeBatchEntry> run_fe_batch(const std::vector<FeBatchJob>& jobs, const FeBatchOptions& options);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
