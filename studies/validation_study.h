// hipfai — the FAI validation study (thesis §4.3.2.3, Tables 8-9): on every hip of the CE x alpha
// grid and every step of standing-to-sitting, the penetration depths (curvilinear and radial,
// studies/pipeline/penetration_run.h) beside the FE ground truth (von Mises per tissue and contact pressure,
// studies/pipeline/hip_fe_run.h). It computes and stores the per-step values; the correlations, tables and
// figures are made from the stored values by studies/validation_report.h.
//
// Stages per hip: generate (cached by parameters), penetration (radial tables cached), FE (cached
// by hip_fe_cache_key). The FE of the hips runs in `jobs` worker processes (`hipfai fem run`, one
// hip per process, killed with the study: on 2 cores 1.55x faster than one hip after the other and
// 4.7x faster than one hip on two MPI ranks, docs/validation.md). Started under an MPI launcher
// (UnitSpread::kMpiRanks), the hips' penetration and FE units are spread over the ranks instead
// (studies/validation_ranks.h, docs/cluster.md), with the same results, and rank 0 writes them.
// A killed run resumes: generated hips and finished FE runs come from the cache, and only the
// hips without a finished FE entry are solved again.
//
// Output folder (docs/results-layout.md):
//   steps.csv    one row per hip and step: ce_deg, alpha_deg, step, angle_deg, max_curvilinear_mm,
//                max_radial_mm, then one column per FE measure (names ending in _mpa; empty where
//                the FE step did not converge)
//   timings.csv  one row per hip: time of each stage, FE level, DOFs, steps not converged
//   fig61/       the CE 40 / alpha 60 hip at the end pose for ParaView (when on the grid)
#pragma once

#include "core/fe_choices.h"
#include "studies/pipeline/mpi_launch.h"
#include "studies/results/fe_step_record.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/pipeline/hip_fe_run.h"
#include "studies/pipeline/hip_source.h"
#endif

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::studies {

struct ValidationOptions {
  std::filesystem::path out_dir = "out/validate";
  std::filesystem::path cache_dir = "cache";
  std::vector<double> ce_deg = study_ce_deg();  // the thesis' grid (core/literature.h)
  std::vector<double> alpha_deg = study_alpha_deg();
  // (CE, alpha) of the hips to run instead of the grid, when not empty.
  std::vector<std::pair<double, double>> hips;
  double edge_mm = 2.0;       // surface resolution of the penetration method
  int sub_motions = 30;       // steps of standing-to-sitting (thesis: 30)
  FeLevel fe_level = FeLevel::kDefault;
  double body_weight_n = 0.0; // <= 0: fem::kDefaultBodyWeightN
  int jobs = 2;               // FE worker processes at once
  int threads = 2;            // threads of the penetration method
  // The hipfai executable the FE workers run; empty: the FE runs in this process, one hip after
  // the other.
  std::filesystem::path program;
  bool progress = true;
  // kMpiRanks: the hips over the ranks of MPI_COMM_WORLD when there are two or more (every rank
  // calls run_validation_study with the same options); with one rank, as kThisMachine.
  UnitSpread spread = UnitSpread::kThisMachine;
};

// The FE measures of steps.csv, in column order (named by fe_measure_name, so the names end in
// _mpa); the first is the primary one.
const std::vector<FeMeasure>& validation_fe_measures();

#ifdef HIPFAI_WITH_FEM
// Every measure of validation_fe_measures() per step of an `fem run --csv` table, [measure][step];
// NaN where the step did not converge. A von Mises measure is the largest over its tissues and 0
// (a tissue the run lacks counts as 0). Throws hipfai::Error naming `file` when the table has
// another number of steps than `steps`.
std::vector<std::vector<double>> validation_fe_measures_of(const HipFeTable& table, std::size_t steps,
                                                           const std::filesystem::path& file);
#endif

struct ValidationHipTiming {
  double ce_deg = 0, alpha_deg = 0;
  double generate_s = 0;                 // 0 when the hip came from the cache
  double penetration_tables_ms = 0;      // cylindrical + radial tables (built or loaded)
  double penetration_query_ms = 0;       // all steps, curvilinear + radial queries
  double fe_s = 0;                       // the FE run's wall time (as measured when it was solved)
  double fe_step_s = 0;                  // sum of the FE steps' wall times
  bool fe_reused = false;                // the FE came from the cache in this run
  int fe_steps_failed = 0;
  double fe_dofs = 0;
};

// A hip whose unit failed when the hips were spread over MPI ranks (the others were kept): its
// name ("ce20_alpha40") and why.
using ValidationHipFailure = UnitFailure;

struct ValidationResult {
  // False on the ranks other than 0 of a study spread over MPI ranks: they wrote nothing and the
  // fields below are empty.
  bool wrote_tables = true;
  std::vector<ValidationHipTiming> hips;  // the hips in steps.csv
  std::vector<ValidationHipFailure> failed;
  int steps = 0;
  FeLevel fe_level = FeLevel::kDefault;
  double seconds = 0;
};

// Throws hipfai::Error for unusable options (before any work) and when an FE run leaves no
// results (naming the hip and its log). Spread over MPI ranks, a hip that fails is in
// ValidationResult::failed instead, and the tables hold the other hips.
ValidationResult run_validation_study(const ValidationOptions& options);

}  // namespace hipfai::studies
