// hipfai — hip motions: the poses a study visits, step by step.
//
// A motion is a sequence of femur poses in the hip frame (geometry/hip_frame.h). Each step carries
// its Cardan angles, the single rotation that takes the femur from neutral to that pose (axis and
// angle: the axis the curvilinear depth is measured about), and optionally the joint reaction
// force for the FE.
#pragma once

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
// attaches its own load profile).
Motion standing_to_sitting(int sub_motions);

// The six medical rotations of thesis §4.4 about the hip frame axes: flexion, extension,
// abduction, adduction, internal and external rotation, each from neutral to `max_deg` in `steps`
// equal steps. `which` is one of "flexion", "extension", "abduction", "adduction",
// "internal_rotation", "external_rotation".
Motion medical_rotation(const std::string& which, double max_deg, int steps);
const std::vector<std::string>& medical_rotation_names();

// Reads a motion CSV: header `step,flexion_deg,adduction_deg,internal_rotation_deg` with optional
// `,Fx_N,Fy_N,Fz_N`; one row per step. Errors name the file and line.
Motion read_motion_csv(const std::filesystem::path& path);

}  // namespace hipfai::studies
