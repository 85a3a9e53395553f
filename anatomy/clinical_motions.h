// hipfai — the clinical motions of a hip to bony impingement: ten ranges of motion of the femur
// against the pelvis, each with the contact that stops it and where that contact lies on the
// acetabular and femoral clock faces.
//
// Method. Every motion is one rotation of the femur about one axis through the HJC, from a start
// pose, found exactly in one pass by the joint range finder (contact/range_finder.h, both
// directions per pass, vertex-triangle both ways and edge-edge contacts). Axes are the hip axes
// (columns lateral, anterior, superior of ClinicalRomRequest::hip_axes, in mesh coordinates; the
// meshes are never moved into the hip frame). Poses follow the joint coordinate system of
// geometry/hip_frame.h, R = Rx(flexion) Ry(adduction) Rz(internal rotation), so a rotation about
// an axis of the posed femur (intrinsic) is a rotation about that axis turned by the start pose:
//
//   flexion / extension              about lateral, from neutral (+ / -)
//   adduction / abduction            about anterior, from neutral (+ / -)
//   internal / external_rotation     about superior (the femur's long axis), from neutral (+ / -)
//   internal / external_rotation_at_90_flexion
//                                    from Rx(90): about Rx(90) superior (+ / -)
//   fadir_internal_rotation          from Rx(90) Ry(a), a = literature::kFadirAdductionDeg:
//                                    about the posed superior (+)
//   faber                            from Rx(f) Ry(-b), f, b = literature::kFaberAssumed*:
//                                    external rotation about the posed superior (-)
//
// A start pose must be reachable: each of its rotations is checked with the range finder itself
// along the path (flexion from neutral >= f, then adduction or abduction at that flexion >= a or
// b). When it is not, that motion is std::nullopt with a one-line reason.
//
// Limiting contact point, mesh coordinates, at the limit pose: a femur vertex rotated by the
// limit; a pelvis vertex itself; edge-edge: the midpoint of the shortest segment between the
// pelvis edge and the rotated femur edge (they meet there up to rounding). Its acetabular clock
// is the angle about the acetabular axis from the clock's anterior towards its superior; its
// femoral clock is that of the same point taken back into the femur at neutral (the limit pose
// undone) about the neck axis. Clock labels: geometry::clock_label (0 = 3:00, 90 = 12:00).
//
// Bones that intersect in the neutral pose (contact/start_pose.h, beyond touching_mm) throw
// hipfai::Error; bad input (empty mesh, non-unit or non-orthogonal axes) throws too.
#pragma once

#include "contact/range_finder.h"
#include "contact/start_pose.h"
#include "core/literature.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace hipfai::anatomy {

// A clock face: angles about `axis` through `centre`, 0 at `anterior`, 90 at `superior`.
struct ClockFace {
  geometry::Vec3 centre_mm = geometry::Vec3::Zero();   // where the clock's hands turn
  geometry::Vec3 axis = geometry::Vec3::UnitX();        // unit, the clock's normal
  geometry::Vec3 anterior = geometry::Vec3::UnitY();    // unit, perpendicular to axis: clock 0 (3:00)
  geometry::Vec3 superior = geometry::Vec3::UnitZ();    // unit, perpendicular to axis: clock 90 (12:00)
};

// Clock angle (degrees in (-180, 180]) of `point` on `face`: atan2 of its components along
// superior and anterior after the axial component is removed.
double clock_angle_deg(const ClockFace& face, const geometry::Vec3& point);

// The clock face about `axis` through `centre` with 12:00 towards `towards` (made perpendicular to
// the axis): superior = towards's perpendicular part, anterior = superior x axis (3:00 for a right
// hip's acetabulum seen from lateral, and for its neck axis pointing laterally). With
// `towards_is_anterior` the given direction is 3:00 instead, and 12:00 = axis x anterior.
ClockFace make_clock_face(const geometry::Vec3& centre, const geometry::Vec3& axis, const geometry::Vec3& towards,
                          bool towards_is_anterior = false);

// A position on a clock face.
struct ClockPosition {
  double angle_deg = 0.0;  // from anterior (0) towards superior (90)
  std::string label;       // geometry::clock_label(angle_deg), e.g. "1:30"
};

struct ClinicalRomRequest {
  const geometry::TriMesh* pelvis = nullptr;  // required, fixed, closed and outward
  const geometry::TriMesh* femur = nullptr;   // required, in its neutral pose, closed and outward
  geometry::Vec3 hjc_mm = geometry::Vec3::Zero();  // rotation centre
  // Hip axes in mesh coordinates: columns lateral, anterior, superior (a proper rotation).
  Eigen::Matrix3d hip_axes = Eigen::Matrix3d::Identity();
  ClockFace acetabulum;    // centre: acetabular centre; axis: out of the socket
  ClockFace femoral_head;  // centre: femoral head centre; axis: neck axis (head centre -> neck)
  double fadir_adduction_deg = literature::kFadirAdductionDeg;
  double faber_flexion_deg = literature::kFaberAssumedFlexionDeg;
  double faber_abduction_deg = literature::kFaberAssumedAbductionDeg;
  // Neutral-pose intersection check: deeper than this is intersecting (mm).
  double touching_mm = contact::kStartPoseTouchingMm;
  int num_threads = 1;  // range finder and start-pose check threads (0 = all)
};

// One motion to impingement.
struct MotionLimit {
  std::string name;                 // the JSON key, e.g. "internal_rotation_at_90_flexion"
  double angle_deg = 360.0;         // range from the start pose, >= 0; 360 when unlimited
  bool unlimited = false;           // no contact within a full turn (angle_deg = 360)
  geometry::Vec3 axis = geometry::Vec3::UnitX();  // unit rotation axis, mesh coordinates (right-hand)
  double sign = 1.0;                // +1: the motion turns by +angle about axis; -1: by -angle
  Eigen::Matrix3d start_rotation = Eigen::Matrix3d::Identity();  // femur pose before the motion (mesh coords)
  // The limiting contact: kind, femur (mobile) / pelvis (fixed) vertex and triangle, edges.
  contact::LimitingContact contact;
  geometry::Vec3 contact_point_mm = geometry::Vec3::Zero();  // at the limit pose; unset when unlimited
  ClockPosition acetabular_clock;   // of contact_point_mm on ClinicalRomRequest::acetabulum
  ClockPosition femoral_clock;      // of the point taken back to neutral, on femoral_head
};

// A motion that could not be computed (its start pose is out of reach).
struct MotionOutcome {
  std::optional<MotionLimit> limit;  // empty: see reason
  std::string reason;                // one line, e.g. "flexion stops at 84.2 deg, before 90"
};

struct ClinicalRom {
  MotionOutcome flexion, extension, abduction, adduction;
  MotionOutcome internal_rotation, external_rotation;
  MotionOutcome internal_rotation_at_90_flexion, external_rotation_at_90_flexion;
  MotionOutcome fadir_internal_rotation, faber;
  double fadir_adduction_deg = 0.0;   // as used
  double faber_flexion_deg = 0.0;     // as used
  double faber_abduction_deg = 0.0;   // as used
  double milliseconds = 0.0;          // wall time of the whole computation

  // The ten motions in the order above, with their JSON keys.
  std::vector<const MotionOutcome*> motions() const;
};

ClinicalRom clinical_range_of_motion(const ClinicalRomRequest& request);

// {"flexion": {"deg": 112.3, "unlimited": false, "contact": {"kind": ..., "femur_vertex": ...,
//  "point_mm": [...], "acetabular_clock_deg": ..., "acetabular_clock": "1:30", ...}}, ...,
//  "fadir_internal_rotation": null, "reasons": {"fadir_internal_rotation": "..."}, ...}
std::string clinical_rom_json(const ClinicalRom& rom, int indent = 2);

// Shared with motion_depths: throws hipfai::Error when `axes` is not a proper rotation (1e-6).
void check_hip_axes(const Eigen::Matrix3d& axes, const std::string& what);
// Throws when a clock face's axis, anterior or superior is not unit or not perpendicular (1e-6).
void check_clock_face(const ClockFace& face, const std::string& what);

}  // namespace hipfai::anatomy
