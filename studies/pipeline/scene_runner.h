// hipfai — runs a scene: acquires the hip, executes the planned stages, writes the results.
//
// Output folder: results.h5 (layout in docs/results-layout.md), steps.csv (one row per motion step)
// and, when asked, VTP files of the tested tissues with their per-vertex depth fields.
//
// Stages run on demand: the penetration methods only for penetration outputs, the contact FE
// (studies/pipeline/hip_fe_run.h, cached under <cache>/fe/) only for von_mises / contact_pressure, after
// the penetration stages. FE columns of steps.csv (the same names under /fe/ in results.h5):
//   fe_status                                    converged | active set not converged | ...
//   von_mises_max_<tissue>_mpa                   von_mises: maximum over the tissue's elements,
//   von_mises_ball_<tissue>_mpa                    averaged over a ball about the peak,
//   von_mises_p95_<tissue>_mpa                     95th percentile; tissue: femoral_cartilage,
//                                                  acetabular_cartilage, labrum
//   pressure_max_mpa, pressure_mean_mpa,         contact_pressure: maximum, mean over the contact
//   pressure_ball_mpa                              area, averaged over a ball about the peak
#pragma once

#include "core/fe_choices.h"

#include "studies/results/fe_step_record.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/motion.h"
#include "studies/pipeline/penetration_run.h"
#include "studies/pipeline/scene.h"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::studies {

struct SceneRunOptions {
  std::filesystem::path out_dir = "out/run";
  std::filesystem::path cache_dir = "cache";
  int threads = 2;
  std::vector<int> vtp_steps;   // 1-based steps to write as VTP (0 = the last step)
  bool write_files = true;
  bool progress = true;         // FE progress: summary lines on stdout, a bar on stderr
};

// One FE column of steps.csv: its measure (the column's name is fe_measure_name's) and its values.
struct SceneFeColumn {
  FeMeasure measure;
  std::vector<double> values;  // one per step, as the FE table has it (NaN where it has no number)
};

// The FE part of a run, without FE types (the runner builds without the FE module too).
struct SceneFeResult {
  bool ran = false;                   // the scene asked for FE outputs
  bool reused = false;                // answered from the cache entry, nothing solved
  std::filesystem::path entry;        // <cache>/fe/<key>
  FeLevel level = FeLevel::kDefault;
  std::string load;                   // the joint force applied, in words
  double seconds = 0.0;               // wall time of the FE stage in this run
  std::vector<std::string> status;    // per step: "converged", ...
  std::vector<int> status_code;       // per step: fem::ContactStatus
  std::size_t not_converged = 0;
  std::vector<SceneFeColumn> columns; // the outputs' columns (see above), in column order
  std::vector<double> step_seconds;   // per step solve time (s), as computed (also when reused)

  const std::vector<double>& column(const FeMeasure& measure) const;  // throws when missing
};

struct SceneRunSummary {
  PenetrationRun run;           // empty when the scene has no penetration output
  SceneFeResult fe;             // ran == false when the scene has no FE output
  StageLog log;
  LoadedHip hip;                // tissues as loaded (neutral pose)
  std::string text;             // a short human-readable summary
};

SceneRunSummary run_scene(const Scene& scene, const Motion& motion, const SceneRunOptions& options);

// The motion a scene names.
Motion motion_of(const Scene& scene);

// The motion the FE solves: standing-to-sitting with the sitting-down load of the scene's body
// weight (studies/pipeline/motion.h); other motions unchanged (the FE gives steps without a force the
// constant joint force of that body weight).
Motion fe_motion_of(const Scene& scene, const Motion& motion);

}  // namespace hipfai::studies
