// hipfai — runs a scene: acquires the hip, executes the planned stages, writes the results.
//
// Output folder: results.h5 (layout in docs/results-layout.md), steps.csv (one row per motion step)
// and, when asked, VTP files of the tested tissues with their per-vertex depth fields.
#pragma once

#include "studies/hip_source.h"
#include "studies/motion.h"
#include "studies/penetration_run.h"
#include "studies/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

struct SceneRunOptions {
  std::filesystem::path out_dir = "out/run";
  std::filesystem::path cache_dir = "cache";
  int threads = 2;
  std::vector<int> vtp_steps;   // 1-based steps to write as VTP (0 = the last step)
  bool write_files = true;
};

struct SceneRunSummary {
  PenetrationRun run;
  StageLog log;
  LoadedHip hip;                // tissues as loaded (neutral pose)
  std::string text;             // a short human-readable summary
};

SceneRunSummary run_scene(const Scene& scene, const Motion& motion, const SceneRunOptions& options);

// The motion a scene names.
Motion motion_of(const Scene& scene);

}  // namespace hipfai::studies
