// hipfai — the FE ground truth of one hip over one motion (fem/hip_fe_model.h through
// fem/motion_solver.h), its per-step table and the cache that keeps it.
//
// One entry point, run_hip_fe(): reads the model folder, meshes it at a level, solves the motion
// step by step (HDF5 per step, fem/fem_results.h), and returns the per-step results. `hipfai fem
// run`, scenes with FE outputs and `hipfai study validate` all go through it, so the three give
// the same numbers for the same inputs.
//
// The per-step table (write_hip_fe_csv / read_hip_fe_csv) has one row per step with round-trip
// precision; its columns are listed in docs/results-layout.md ("fem run --csv").
//
// Cache: an FE run is keyed by hip_fe_cache_key() — the content of the tissue meshes the volume
// mesh is built from, the level and its mesh options, the materials, every step's rotation and
// joint force, the peak-average radius, the solver and a content hash of the sources behind
// FE results (kFeSourceHash: core/, geometry/, fem/, this driver; a commit elsewhere keeps the cache) — and stored under
// <cache>/fe/<key>/ (fe.csv, results.h5, run.log). An entry exists only when complete: it is
// computed in a temporary folder beside it (core/atomic_file.h, AtomicDirectory) and renamed
// when the motion has finished, under the entry's lock (core/cache_entry.h), so that jobs sharing
// the cache solve each run once.
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "core/atomic_file.h"
#include "core/fe_choices.h"
#include "fem/hip_fe_model.h"
#include "studies/results/hip_fe_table.h"
#include "studies/pipeline/motion.h"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hipfai::studies {

// The MPI ranks that solve one run.
enum class FeRanks {
  kAll,       // every rank of MPI_COMM_WORLD (`mpirun -np N hipfai fem run`): substructured,
              // the column solves dealt to the ranks (fem/rank_team.h)
  kThisRank,  // this rank alone (MPI_COMM_SELF): one unit of a study spread over the ranks
};

struct HipFeRunOptions {
  std::string model_dir;    // folder with model.json and the tissue meshes
  // The motion: `motion` when set (its steps without a force get the constant joint force of
  // body_weight_n), else the CSV `motion_file`, else standing-to-sitting in `steps` sub-motions
  // with the sitting-down load after Bergmann et al. (2001) (studies/pipeline/motion.h).
  std::optional<Motion> motion;
  std::string motion_file;
  int steps = 30;
  FeLevel level = FeLevel::kCoarse;
  double body_weight_n = fem::kDefaultBodyWeightN;
  double peak_radius_mm = fem::ContactOptions{}.peak_average_radius_mm;
  // The labrum meshed n times finer than the level (edge / n, layers * n): for the study of its
  // singular corner (docs/fem-levels.md), not for the ground truth.
  int labrum_refinement = 1;
  std::string out_file;  // per-step HDF5 (required)
  std::string csv_file;  // per-step table (empty: none), written atomically after the motion
  FeSolver solver = FeSolver::kSubstructured;  // core/fe_choices.h
  unsigned int vtu_every = 0;     // fields to <vtu_prefix>_<step>.vtu every n steps and the last
  std::string vtu_prefix;
  // Threads of this process's FE stages (0: every hardware thread); the results do not depend on
  // it (fem::limit_threads), so it is not part of the cache key. The substructured solver on
  // several ranks (kAll under mpirun) gives rank 0 all of them and the other ranks, which only
  // solve compliance columns, one each (fem/rank_team.h); the other solvers share them among the
  // ranks.
  unsigned int threads = 0;
  // Search each step's contact while the steps before are solved (fem::MotionOptions); the
  // results do not depend on it either.
  bool search_ahead = true;
  // The results do not depend on it either where the run is on one rank (kThisRank, or kAll
  // without mpirun); not part of the cache key.
  FeRanks ranks = FeRanks::kAll;
  // kAll on several ranks: which ranks solve compliance columns (fem/contact_problem.h); the
  // results do not depend on it; not part of the cache key.
  fem::TeamColumns team_columns = fem::TeamColumns::kSpareCores;
  bool verbose = false;   // active-set iterations on stdout
  bool progress = true;   // progress bar on stderr (rank 0)
  std::string label = "fem run";  // prefix of the progress and summary lines
  // Where the results will be once the caller has moved them into place (a cache entry computed
  // in a staging folder): named in the summary line instead of out_file. Empty: out_file.
  std::string results_location;
};

struct HipFeRunSummary {
  std::size_t hexes = 0;
  double min_scaled_jacobian = 0.0;
  std::vector<std::string> bodies;         // deformable bodies, fem::hip_fe_body_names()
  std::vector<std::string> pair_surfaces;  // slave surface of each contact pair
  std::vector<fem::ContactResult> results; // one per step
  std::size_t failed = 0;                  // steps that did not converge
  double mesh_seconds = 0.0;               // volume mesh and FE set-up
  double seconds = 0.0;                    // whole run: reading, meshing, set-up and all steps
};

// The motion as run_hip_fe() solves it (with its joint force per step). Throws hipfai::Error for
// an unreadable motion file.
Motion hip_fe_motion(const HipFeRunOptions& options);

// Runs the hip FE model of options.model_dir through the motion (the ranks of options.ranks take
// part; the first of them writes). Throws hipfai::Error for input that cannot be used (model folder,
// motion, level, unwritable output), and — when throw_on_failure — after the motion when some
// step did not converge (its results are written all the same).
HipFeRunSummary run_hip_fe(const HipFeRunOptions& options, bool throw_on_failure = true);

// The per-step table of a run (one row per step, round-trip precision), written atomically.
void write_hip_fe_csv(const std::filesystem::path& file, const HipFeRunSummary& summary);


// The cache key of a run (16 hex digits); see the file comment for what it covers.
std::string hip_fe_cache_key(const HipFeRunOptions& options);

// <cache_dir>/fe/<key>: the entry's folder (fe.csv, results.h5, run.log).
std::filesystem::path hip_fe_cache_entry(const std::filesystem::path& cache_dir, const std::string& key);

// A run from the cache, or computed in this process and then cached (out_file / csv_file of
// `options` are ignored: the entry's files are used), under the entry's lock (core/cache_entry.h):
// when another job is solving the same run, this one waits and reads its entry. Not converged
// steps are kept (their status is in the table), not an error.
struct CachedHipFe {
  HipFeTable table;
  std::filesystem::path entry;  // the cache entry's folder
  bool reused = false;          // true: read from the cache, nothing solved
  double seconds = 0.0;         // this call's wall time
};
CachedHipFe run_hip_fe_cached(HipFeRunOptions options, const std::filesystem::path& cache_dir);

// The command line of `hipfai fem run` that computes `options` (out/csv/vtu as set in them), for
// running a hip in its own process. Only standing-to-sitting or a motion file can be passed.
std::vector<std::string> hip_fe_command_arguments(const HipFeRunOptions& options);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
