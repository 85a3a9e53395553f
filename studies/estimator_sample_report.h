// hipfai — what `estimator sample` writes and says: design.csv (one row per hip: name, set, each
// varied parameter's value), one line per hip as it is made, and the closing summary.
#pragma once

#include "studies/estimator_sample.h"

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

}  // namespace hipfai::studies
