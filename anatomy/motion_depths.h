// hipfai — bone-to-bone penetration depths over a motion: for each pose of a list, the deepest
// curvilinear and radial penetration of the femur bone into the pelvis bone and back.
//
// Method (thesis ch. 3-4, as studies/pipeline/penetration_run.h applies it to the tissues, here between the
// two bones). Each pose (geometry::HipPoseDeg, joint coordinate system) is one rotation R of the
// femur from neutral about the HJC, R = A Rjcs A^T in mesh coordinates (A = hip axes, columns
// lateral, anterior, superior), with a single axis and angle (Euler's theorem):
//   - curvilinear depth: cylindrical segmenting about that axis through the HJC (table of the
//     pelvis restricted to the femur, femur posed by R), the arc length back to the surface; with
//     swap_roles also pelvis vertices against the femur (table of the femur, pelvis posed by R^T:
//     the femur turning by +angle is the pelvis turning by -angle relative to it);
//   - radial depth: radial segmenting about the HJC with the kUnion crossing rule
//     (contact/radial_segmenting.h): femur vertices inside the pelvis solid (kMobileInsideFixed),
//     depth along the ray from the HJC to where it enters the pelvis; with swap_roles pelvis
//     vertices inside the femur solid (kFixedInsideMobile). Each body is prepared once for the
//     motion (contact::RadialPoseQuery); cylindrical tables are built once per distinct axis.
// Only vertices are tested (the thesis' definition): where two rims first cross edge on edge
// (clinical_motions.h reports such limits), the bones overlap without a vertex inside until the
// rims have passed each other by about an edge, and the depths stay 0 meanwhile.
// A vertex counts when its depth exceeds contact_tolerance_mm (0: every penetrating vertex the
// queries report; they already ignore touching within 1e-9 mm). The neutral pose (angle 0) has no
// axis: its curvilinear query runs about the lateral axis at angle 0.
// Per step: the maxima, the deepest vertex (which body, index, the other body's triangle, its
// position at the pose, acetabular clock of that position, femoral clock of the same point taken
// back to neutral, as in clinical_motions.h) and the number of penetrating vertices (both roles).
// Bad input throws hipfai::Error.
#pragma once

#include "anatomy/clinical_motions.h"
#include "geometry/hip_frame.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace hipfai::anatomy {

struct MotionDepthsRequest {
  const geometry::TriMesh* pelvis = nullptr;  // required, fixed, closed and outward
  const geometry::TriMesh* femur = nullptr;   // required, in its neutral pose, closed and outward
  geometry::Vec3 hjc_mm = geometry::Vec3::Zero();
  Eigen::Matrix3d hip_axes = Eigen::Matrix3d::Identity();  // columns lateral, anterior, superior
  std::vector<geometry::HipPoseDeg> poses;                 // the motion, JCS angles
  ClockFace acetabulum;    // as in ClinicalRomRequest
  ClockFace femoral_head;  // as in ClinicalRomRequest
  bool swap_roles = true;  // also pelvis vertices penetrating the femur
  double contact_tolerance_mm = 0.0;  // depths at or below this do not count (>= 0)
  // Radial depths count only for vertices within this distance of the HJC (0: every vertex). The
  // radial depth is taken along the ray from the HJC: on whole bones, past a limit, vertices far
  // from the joint (neck base, shaft) enter the other bone and are crossed obliquely by that ray, so
  // their radial depth reads many times the overlap. The thesis' radial depth describes the
  // articular region; the assessment passes 2 head radii (the head, the head-neck junction, the
  // rim and the labrum's reach, ~1.3 R, with margin).
  double radial_reach_mm = 0.0;
  int num_threads = 1;                // query threads (radial: 1 or 2)
};

enum class DepthBody { kNone, kFemur, kPelvis };

// The deepest penetrating vertex of one kind of depth at one step.
struct DeepestVertex {
  DepthBody body = DepthBody::kNone;  // whose vertex; kNone: nothing penetrates
  std::int32_t vertex = -1;           // its index in that body's mesh
  std::int32_t triangle = -1;         // the other body's triangle it was measured against
  double depth_mm = 0.0;
  geometry::Vec3 point_mm = geometry::Vec3::Zero();  // the vertex at the step's pose, mesh coordinates
  ClockPosition acetabular_clock;     // of point_mm
  ClockPosition femoral_clock;        // of point_mm taken back to the femur's neutral pose
};

struct StepDepths {
  geometry::HipPoseDeg pose;                       // as requested
  geometry::Vec3 axis = geometry::Vec3::UnitX();   // unit axis of the step's rotation, mesh coordinates
  double angle_deg = 0.0;                          // its angle, >= 0
  double max_curvilinear_mm = 0.0;
  DeepestVertex curvilinear_deepest;
  int curvilinear_vertices = 0;                    // penetrating vertices, both roles
  double max_radial_mm = 0.0;
  DeepestVertex radial_deepest;
  int radial_vertices = 0;                         // penetrating vertices, both roles
};

struct MotionDepths {
  std::vector<StepDepths> steps;  // one per requested pose, in order
  double milliseconds = 0.0;      // wall time, tables included
  // True when the femur holds the HJC (a whole bone): the radial pelvis-in-femur role is then
  // left out (its depth towards the HJC is undefined; see bone_depths_over_motion).
  bool radial_swap_skipped = false;

  double max_curvilinear_mm() const;
  double max_radial_mm() const;
};

MotionDepths bone_depths_over_motion(const MotionDepthsRequest& request);

}  // namespace hipfai::anatomy
