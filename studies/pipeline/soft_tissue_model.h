// hipfai — a hip model folder made from a segmented femur and pelvis (`hipfai soft-tissue`): the
// assessment's frames and landmarks (studies/pipeline/assessment.h), cartilage and labrum synthesised on the
// bones (anatomy/soft_tissue.h), everything expressed in the hip frame and written in the format
// every command reads (geometry/hip_model.h), with a short soft_tissue.md.
//
// Frames. The tissues are synthesised in working coordinates (a left hip mirrored into a right
// one), with the femur at its neutral pose (AssessmentResult::femur_neutral: its frame onto the
// pelvis frame, about the HJC). The model is that scene in the hip frame: origin the HJC, axes the
// pelvis frame (+X lateral, +Y anterior, +Z superior), so a LEFT hip's folder holds its mirror
// image, a right hip (model.json has no handedness key; soft_tissue.md says so).
//
// model.json. hjc_mm the origin, the axes the identity, neck_axis (at neutral), acetabular_axis,
// socket_opening_deg (mean polar angle of the rim), "measured" CE (lateral, Wiberg) and alpha
// (Nötzli plane, largest and its clock, the profile). "parameters" (the generator's fields, which
// the reader checks against their ranges) carries what a real hip has of them: articular radius =
// the common articular sphere's (anatomy/soft_tissue.h), the cartilage and labrum sizes used, and ce_deg/alpha_deg
// = the measured angles clamped into the generator's ranges (CE 0-45, alpha 35-90 deg; the exact
// values are in "measured").
#pragma once

#include "anatomy/soft_tissue.h"
#include "geometry/hip_model.h"
#include "studies/pipeline/assessment.h"

#include <filesystem>
#include <string>

namespace hipfai::studies {

struct SoftTissueModelRequest {
  // femur, pelvis, names, side and frame are used; motion, resections and threads are not.
  AssessmentRequest assessment;
  anatomy::SoftTissueOptions options;
};

struct SoftTissueModel {
  geometry::HipModel model;                 // hip frame; tissues: the five of kHipTissueNames
  anatomy::SoftTissueReport report;         // areas mm^2, thicknesses mm, volumes mm^3
  anatomy::SoftTissueOptions options;       // the thicknesses and sizes used
  anatomy::Side side = anatomy::Side::kRight;
  std::string side_source;                  // how the side was decided (the assessment's)
  std::string pelvis_frame_source;          // how the pelvis frame was found or given
  geometry::Vec3 hjc_input_mm = geometry::Vec3::Zero();  // the HJC in the input meshes' coordinates
  double head_radius_mm = 0.0;              // femoral head sphere
  double lunate_radius_mm = 0.0;            // acetabular (lunate) sphere
  double assessment_seconds = 0.0;          // frames, landmarks, acetabulum
  double total_seconds = 0.0;
};

// Throws hipfai::Error with one line for bad bones (the assessment's errors: no femoral head, no
// acetabulum, ...; anatomy::synthesise_soft_tissues's).
SoftTissueModel build_soft_tissue_model(const SoftTissueModelRequest& request);

// The same from an assessment already made (hipfai assess --soft-tissue): its bones at neutral,
// frames, head and acetabulum; `femur_name`, `pelvis_name` for messages. Resections the assessment
// made do not change the bones used (the tissues dress the bones as scanned).
SoftTissueModel soft_tissue_model_from(const AssessmentResult& assessment, const anatomy::SoftTissueOptions& options,
                                       const std::string& femur_name = "femur", const std::string& pelvis_name = "pelvis");

// Writes `dir` atomically (core/atomic_file.h AtomicDirectory: a whole folder or none): the model
// (geometry::write_hip_model, PLY) and soft_tissue.md; `femur_path`, `pelvis_path` are named in it.
// An existing `dir` is replaced.
void write_soft_tissue_model(const SoftTissueModel& result, const std::string& femur_path,
                             const std::string& pelvis_path, const std::filesystem::path& dir);

}  // namespace hipfai::studies
