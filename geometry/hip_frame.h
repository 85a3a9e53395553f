// hipfai — the hip frame, written once.
//
// Notation (FCL / Drake style): p_HX is point X measured in frame H; R_HF rotates femur-fixed
// vectors into H. Every hip model, generated or user-supplied, is expressed in its hip frame H:
//
//   origin  the hip joint centre (HJC), the centre of the femoral head;
//   +X      from the left femoral head towards the right one (for a right hip: lateral);
//   +Y      anterior;
//   +Z      superior.
//
// This is the frame of thesis §4.3.2.3 (after Bergmann et al. 2001) and, for a right hip, the ISB
// pelvic frame of Wu et al. (2002) with its axes relabelled. Motions are right-hand rotations of
// the femur about axes through the HJC; for a RIGHT hip:
//
//   flexion            +  about +X (the knee moves anteriorly),
//   adduction          +  about +Y (the knee moves medially),
//   internal rotation  +  about +Z (the anterior femur turns medially).
//
// A pose (flexion, adduction, internal rotation) is the intrinsic X-Y'-Z'' Cardan sequence
// R = Rx(flexion) * Ry(adduction) * Rz(internal_rotation), following the joint coordinate system
// order of Wu et al. (2002). Generated hips are right hips.
//
// The same three angles can also be read as rotations about the FIXED hip-frame axes, in the
// order listed: flexion about X, then adduction about Y, then internal rotation about Z, i.e.
// R = Rz(internal_rotation) * Ry(adduction) * Rx(flexion) (PoseSequence::kFixedAxes). That is
// the literal reading of thesis §4.3.2.3 ("the rotations of the femur head around these axes were
// defined as flexion, adduction and internal rotation respectively"); the two readings differ by
// 17.4 deg at the standing-to-sitting end pose (59.6, 13.6, 10.9), and docs/hip-geometry.md
// measures which one the thesis' cam results follow (the joint coordinate system).
#pragma once

#include "core/numbers.h"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace hipfai::geometry {

// The angle conversions of core/numbers.h, under the names the geometry code uses.
inline constexpr double kDegToRad = kRadPerDeg;
inline constexpr double kRadToDeg = kDegPerRad;

struct HipFrameAxes {
  Eigen::Vector3d flexion_axis{1.0, 0.0, 0.0};
  Eigen::Vector3d adduction_axis{0.0, 1.0, 0.0};
  Eigen::Vector3d internal_rotation_axis{0.0, 0.0, 1.0};
};

// How the three angles of a HipPoseDeg compose (see the header comment).
enum class PoseSequence {
  kJointCoordinateSystem,  // intrinsic X-Y'-Z'': Rx * Ry * Rz (Wu et al. 2002), the default
  kFixedAxes,              // about the fixed X, then Y, then Z: Rz * Ry * Rx
};

// Which femur-fixed line the pose's zero puts along the pelvic Z (see core/literature.h,
// kAnatomicMechanicalAngleDeg).
enum class FemoralNeutral {
  kShaftAxis,       // the femur as built: its shaft along Z
  kMechanicalAxis,  // the ISB femoral frame (Wu et al. 2002): HJC-to-knee along Z
};

struct HipPoseDeg {
  double flexion_deg = 0.0;
  double adduction_deg = 0.0;
  double internal_rotation_deg = 0.0;
};

// Rotation of the femur, in the hip frame, for a pose given as Cardan angles (degrees).
inline Eigen::Matrix3d femur_rotation(const HipPoseDeg& pose, const HipFrameAxes& axes = {}) {
  return (Eigen::AngleAxisd(pose.flexion_deg * kDegToRad, axes.flexion_axis) *
          Eigen::AngleAxisd(pose.adduction_deg * kDegToRad, axes.adduction_axis) *
          Eigen::AngleAxisd(pose.internal_rotation_deg * kDegToRad, axes.internal_rotation_axis))
      .toRotationMatrix();
}

// Rotation of the femur for a pose read in the given sequence.
inline Eigen::Matrix3d femur_rotation(const HipPoseDeg& pose, PoseSequence sequence, const HipFrameAxes& axes = {}) {
  if (sequence == PoseSequence::kJointCoordinateSystem) return femur_rotation(pose, axes);
  return (Eigen::AngleAxisd(pose.internal_rotation_deg * kDegToRad, axes.internal_rotation_axis) *
          Eigen::AngleAxisd(pose.adduction_deg * kDegToRad, axes.adduction_axis) *
          Eigen::AngleAxisd(pose.flexion_deg * kDegToRad, axes.flexion_axis))
      .toRotationMatrix();
}

}  // namespace hipfai::geometry
