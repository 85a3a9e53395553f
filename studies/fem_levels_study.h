// hipfai — the hip FE model at several mesh levels: what accuracy costs in time (`hipfai fem
// levels`). compute_fem_levels() runs the model and motion at each level (per-level HDF5 and CSV
// as `fem run` writes them) into a FemLevelsResult; write_fem_levels_report()
// (studies/fem_levels_report.h) writes the report from it.
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "studies/pipeline/hip_fe_run.h"

#include <deal.II/base/point.h>

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

struct FemLevelsOptions {
  HipFeRunOptions run;  // model, motion, steps, body weight, solver (level and outputs set per level)
  std::vector<FeLevel> levels{kFeLevels.begin(), kFeLevels.end()};
  std::filesystem::path out_dir;
};

// One level's run and its peaks over the motion.
struct FemLevelRow {
  FeLevel level = FeLevel::kCoarse;
  HipFeRunSummary summary;
  double peak_pressure = 0.0, wall_per_step = 0.0;
  std::vector<double> peak_vm, peak_p95;  // per body, max over the steps
  // Ball-averaged peaks (fem/peak_measures.h), max over the steps; where the pressure peaks sit
  // (at the step of each maximum).
  double ball_peak_pressure = 0.0;
  std::vector<double> ball_peak_vm;  // per body
  dealii::Point<3> max_pressure_position, ball_peak_pressure_position;
  std::string max_pressure_surface = "none", ball_peak_pressure_surface = "none";
  // Integral quantities at the last step (the peak load of standing-to-sitting).
  double last_mean_pressure = 0.0, last_area = 0.0, last_translation = 0.0;
};

struct FemLevelsResult {
  std::vector<FemLevelRow> rows;  // coarsest first; the last is the reference
  bool writer = false;            // this process writes the report (MPI rank 0)
};

// Runs the levels of options.levels, in order of
// refinement. Throws hipfai::Error when the model folder cannot be read (before any output).
FemLevelsResult compute_fem_levels(const FemLevelsOptions& options);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
