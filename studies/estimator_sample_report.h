// hipfai — what `estimator sample` writes and says: design.csv (one row per hip: name, set, each
// varied parameter's value), one line per hip as it is made, and the closing summary; with its FE
// (studies/estimator_sample_fe.h), the ground-truth tables.
#pragma once

#include "studies/estimator_sample.h"
#include "studies/estimator_sample_fe.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

// design.csv's text: header "name,set,<parameter>_deg..." (e.g. ce_deg, alpha_deg), then one row per
// hip in plan order, values written exactly (shortest round-trip form).
std::string design_csv(const SamplePlan& plan);

// Writes out_dir/design.csv (atomically). When it exists already (a re-run) it must hold the same
// design; otherwise hipfai::Error "<path>: holds another design (...)", nothing written.
void write_design_csv(const SamplePlan& plan, const std::filesystem::path& out_dir);

// "[2/5] train_002 ce 12.3 alpha 55.1: generated in 3.1 s" / ": complete, skipped" /
// ": FAILED: <generator's message>".
std::string sample_hip_line(const SamplePlan& plan, std::size_t index, const SampleHipOutcome& outcome);

// "5 hips (3 train, 2 held_out): 3 generated, 2 skipped, 0 failed; design: <out>/design.csv".
std::string sample_summary(const SamplePlan& plan, const std::vector<SampleHipOutcome>& outcomes,
                           const std::filesystem::path& out_dir);

// The sample's ground truth, in the layout of `study validate` (so `estimator train --fe` reads it)
// with the hip's name, set and varied parameters in front:
//   steps.csv           training hips: hip, set, the other varied parameters (<name>_deg), ce_deg, alpha_deg, step,
//                       angle_deg, max_curvilinear_mm, max_radial_mm, then the FE measures (_mpa;
//                       empty where a step did not converge); CE and alpha written exactly
//   held_out_steps.csv  the held-out hips, same columns
//   timings.csv         per hip: hip, set, ce_deg, alpha_deg, edge_mm, steps, fe_level,
//                       penetration_ms, fe_s, fe_reused, fe_steps_failed, error
// A hip whose FE run failed has no rows in the step tables (its error is in timings.csv). Each
// file is written atomically.
void write_sample_fe_tables(const SamplePlan& plan, const SampleFeResult& result, FeLevel level,
                            const std::filesystem::path& out_dir);

// "230 hips with FE (200 train, 30 held_out), 0 failed, 0 not generated; 812 s; tables in <dir>".
std::string sample_fe_summary(const SamplePlan& plan, const SampleFeResult& result, const std::filesystem::path& out_dir);

}  // namespace hipfai::studies
