// hipfai — hip motions: the poses a study visits, step by step.
//
// A motion is a sequence of femur poses in the hip frame (geometry/hip_frame.h). Each step carries
// its Cardan angles, the single rotation that takes the femur from neutral to that pose (axis and
// angle: the axis the curvilinear depth is measured about), and optionally the joint reaction
// force for the FE.
#pragma once

#include "core/literature.h"
#include "geometry/hip_frame.h"

#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hipfai::studies {

struct MotionStep {
  geometry::HipPoseDeg pose;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // R_H(femur) from neutral
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();           // unit axis of `rotation`
  double angle_deg = 0.0;                                    // angle of `rotation`, >= 0
  std::optional<Eigen::Vector3d> force_N;                    // joint reaction force, hip frame
};

struct Motion {
  std::string name;
  std::vector<MotionStep> steps;  // step 0 is the first sub-motion, not the neutral pose
};

// Builds a step from Cardan angles (computes rotation, axis and angle).
MotionStep make_step(const geometry::HipPoseDeg& pose);

// Standing to sitting after thesis §4.3.2.3: `sub_motions` equal sub-motions from neutral to
// (flexion, adduction, internal rotation) = (59.6, 13.6, 10.9) deg. The end rotation is split into
// equal angles about its single axis, so every step shares one axis. Forces: none (the FE module
// attaches its own load profile). `sequence` says how the end pose's three angles compose
// (geometry/hip_frame.h); the steps' Cardan angles are always written back in the joint coordinate
// system (X-Y'-Z''), the convention of motion CSV files.
Motion standing_to_sitting(int sub_motions,
                           geometry::PoseSequence sequence = geometry::PoseSequence::kJointCoordinateSystem);

// "jcs" / "fixed-axes" and back; pose_sequence_from_name throws hipfai::Error for another name.
std::string pose_sequence_name(geometry::PoseSequence sequence);
geometry::PoseSequence pose_sequence_from_name(const std::string& name);

// The six medical rotations of thesis §4.4 about the hip frame axes: flexion, extension,
// abduction, adduction, internal and external rotation, each from neutral to `max_deg` in `steps`
// equal steps. `which` is one of "flexion", "extension", "abduction", "adduction",
// "internal_rotation", "external_rotation".
Motion medical_rotation(const std::string& which, double max_deg, int steps);
const std::vector<std::string>& medical_rotation_names();

// Reads a motion CSV: header `step,flexion_deg,adduction_deg,internal_rotation_deg` with optional
// `,Fx_N,Fy_N,Fz_N`; one row per step. Errors name the file and line.
Motion read_motion_csv(const std::filesystem::path& path);
// Same from the file's text; `path` names it in messages and gives the motion's name (its stem).
Motion parse_motion_csv(const std::string& text, const std::filesystem::path& path);

// Writes `motion` in the format read_motion_csv reads (force columns when every step has a
// force), with round-trip precision. Throws hipfai::Error naming the file when it cannot write.
void write_motion_csv(const Motion& motion, const std::filesystem::path& path);

// Joint reaction force of sitting down after Bergmann et al. (2001, J Biomech 34:859-871).
//
// Sign convention: the force the FEMUR APPLIES TO THE PELVIS (to the acetabular tissues), in the
// hip frame (+X lateral for a right hip, +Y anterior, +Z superior): mostly superior, tilted
// medially (-X). This is fem::MotionStep::force_n, "force the moving body applies to the
// tissues", so it is copied over unchanged (the pelvis pushes back on the femur with -force).
//
// Taken from the paper: only the peak resultant, peak_percent_bw (156 %BW, average patient).
// Assumptions (core/literature.h, kSitDownAssumed*): the resultant rises by a half-cosine from
// start_percent_bw at phase 0 (upright) to the peak at peak_phase, then falls by a half-cosine to
// end_percent_bw at phase 1; its direction is fixed in the hip frame. The shape between these
// points is not the published curve, only a smooth stand-in with the published peak.
struct SittingDownLoadOptions {
  double body_weight_n = 0.0;  // required, > 0
  double start_percent_bw = literature::kSitDownAssumedStartForcePercentBW;
  double peak_percent_bw = literature::kStandToSitPeakForcePercentBW;
  double end_percent_bw = literature::kSitDownAssumedEndForcePercentBW;
  double peak_phase = literature::kSitDownAssumedPeakPhase;  // in (0, 1]
  // Angle of the force from +Z towards -X (medial) in the frontal plane, and towards +Y
  // (anterior) in the sagittal plane.
  double frontal_angle_deg = literature::kSitDownAssumedFrontalAngleDeg;
  double sagittal_angle_deg = literature::kSitDownAssumedSagittalAngleDeg;
};

// Force (N, hip frame, convention above) at `phase` in [0, 1] of the sitting-down activity.
// Throws hipfai::Error for an invalid option.
Eigen::Vector3d sitting_down_force_n(double phase, const SittingDownLoadOptions& options);

// Sets force_N of every step of `motion`: step k of n (0-based) sits at phase (k + 1) / n, so the
// last sub-motion, the thesis's end pose, is phase 1 (step 0 is the first sub-motion, not the
// neutral pose: see Motion).
void attach_sitting_down_load(Motion& motion, const SittingDownLoadOptions& options);

}  // namespace hipfai::studies
