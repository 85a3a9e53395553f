// hipfai — one hip's FE run made into its cache entry (<cache>/fe/<key>, studies/pipeline/hip_fe_run.h),
// once, however many jobs ask for it at the same time (core/cache_entry.h: a per-entry lock held
// while the run is solved, the entry filled under a temporary name and renamed into place).
//
// The run is solved in this process (on this rank alone when the job says FeRanks::kThisRank) or
// in a `hipfai fem run` worker process. Each entry holds fe.csv, results.h5, run.log (worker
// processes) and timing.txt ("wall_s <seconds>").
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "core/cache_entry.h"
#include "studies/pipeline/hip_fe_run.h"

#include <filesystem>
#include <string>

namespace hipfai::studies {

struct FeBatchJob {
  std::string id;         // names the hip in progress lines and errors
  HipFeRunOptions run;    // model_dir, motion, level, ... (out_file and csv_file are the entry's)
};

struct FeEntrySolver {
  // The hipfai executable to run `fem run` in a worker process; empty: solved in this process.
  std::filesystem::path program;
  unsigned int threads = 1;  // FE threads of the run (the results do not depend on them)
};

// The job's cache entry folder (keys the run: reads its model's tissue meshes).
std::filesystem::path fe_job_entry(const FeBatchJob& job, const std::filesystem::path& cache_dir);

// True when `entry` holds a finished run (its table, the last file a run writes before the rename).
bool fe_entry_is_complete(const std::filesystem::path& entry);

// Makes `entry` (fe_job_entry of the job) unless it is complete. With LockWait::kTry, returns
// EntrySource::kBusy at once when another job is solving it. Throws hipfai::Error "FE of <model>
// failed (exit status N); see <run.log>" when a worker leaves no table (its folder is kept for the
// log), and what an in-process run throws.
EntrySource make_fe_entry(const FeBatchJob& job, const std::filesystem::path& entry, const FeEntrySolver& solver,
                          LockWait wait);

// A run made into its entry in this process on this rank alone (FeRanks::kThisRank: a unit of a
// study spread over MPI ranks), waiting while another job solves it: where the entry is and how it
// came (kMade, or kFound / made by another job). Throws what make_fe_entry throws.
struct FeEntryOnRank {
  std::filesystem::path entry;
  EntrySource source = EntrySource::kMade;
};
FeEntryOnRank make_fe_entry_on_this_rank(FeBatchJob job, const std::filesystem::path& cache_dir, unsigned int threads);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
