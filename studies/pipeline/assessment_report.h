// hipfai — writes an assessment (studies/pipeline/assessment.h) into an output folder, whole or not at all
// (the folder is filled under a temporary name and renamed into place):
//
//   assessment.json   in the input meshes' coordinates (mm, unit vectors, degrees):
//                     {"side", "hjc_mm", "frames": {"pelvis": {"origin_mm", "right", "anterior",
//                     "superior"}, "femur": {...}}, "measures": {"lateral_ce_deg", ...},
//                     "rom_deg": {"flexion", ...}, "impingement": {...}, "landmarks": {...},
//                     "classification", "findings", "motion", "resection", "timings_s"}; a measure
//                     that cannot be made is null with "<key>_reason" beside it;
//   report.md         the tables a surgeon's team reads, with the figures (assessment_figures.h);
//   pelvis.vtp, femur.vtp    the bones in the input's coordinates (femur as scanned), with the
//                     vertex field "impingement_motions": how many clinical motions' limits lie
//                     within 3 mm of the vertex (ParaView: colour by it);
//   femur_resected.vtp, pelvis_trimmed.vtp   after the resections, when asked for.
#pragma once

#include "studies/pipeline/assessment.h"

#include <filesystem>
#include <string>

namespace hipfai::studies {

struct AssessmentInputs {
  std::string femur_path, pelvis_path, frame_path, motion_path;  // as given (empty: none)
};

std::string assessment_json(const AssessmentResult& result, const AssessmentInputs& inputs, int indent = 2);
std::string assessment_markdown(const AssessmentResult& result, const AssessmentInputs& inputs);

// Writes every file above into `dir` (replacing a previous assessment there). Throws
// hipfai::Error "<dir>: ..." when it cannot; no partial folder is left.
void write_assessment(const AssessmentResult& result, const AssessmentInputs& inputs,
                      const std::filesystem::path& dir);

}  // namespace hipfai::studies
