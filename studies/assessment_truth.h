// hipfai — the assessment against known truth: the 25 generated hips of the study grid (thesis
// §4.3.2.2) know their CE, alpha and frame. Each is assessed from its bones alone (femur_bone,
// acetabular_bone) with its model.json as the frame (`hipfai assess --frame model.json`), then
// again moved by a random rigid transform, and again mirrored into a left hip and moved.
//
// Per hip: the CE and alpha measured vs the generator's (model.json "measured": on bone and
// cartilage, the articular surface), the bone's alpha by the generator's own method on the bone
// alone (the reference for a bones-only measurement), and the largest differences of every measure
// and clinical range of motion between the original, the moved and the mirrored assessments.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

struct AssessmentTruthOptions {
  double edge_mm = 2.0;           // surface edge length of the generated hips
  unsigned seed = 20261126;       // random rigid transforms
  std::filesystem::path out_dir = "out/assessment-truth";
  bool quick = false;             // two hips (CE 20 alpha 80, CE 40 alpha 40) at 3 mm: test-sized
};

struct AssessmentTruthRow {
  std::string hip;                  // "ce20_alpha80"
  double model_ce_deg = 0.0, measured_ce_deg = 0.0;
  double model_alpha_deg = 0.0;     // the generator's, on bone and cartilage
  double bone_alpha_reference_deg = 0.0;  // the generator's method on the bone alone
  double measured_alpha_deg = 0.0;  // the assessment's, on the bone alone
  double measured_alpha_max_deg = 0.0;
  double acetabular_version_deg = 0.0, acetabular_inclination_deg = 0.0;
  double fadir_internal_rotation_deg = 0.0;  // NaN when not reached
  // Largest |difference| over the measures (deg) and over the ten ranges of motion (deg) between
  // the original and the moved / mirrored assessments.
  double moved_measure_diff_deg = 0.0, moved_rom_diff_deg = 0.0;
  double mirrored_measure_diff_deg = 0.0, mirrored_rom_diff_deg = 0.0;
  bool mirrored_side_left = false;
  double assess_seconds = 0.0;      // one assessment (the original)
};

struct AssessmentTruthResult {
  AssessmentTruthOptions options;
  std::vector<AssessmentTruthRow> rows;
  double seconds = 0.0;
};

AssessmentTruthResult run_assessment_truth(const AssessmentTruthOptions& options);

}  // namespace hipfai::studies
