// hipfai — the patient-specific FAI assessment of a segmented femur and pelvis (`hipfai assess`):
// frames found on the bones, the radiographic measures in 3D, the clinical motions to bony
// impingement with the exact range finder, the bone-to-bone depths over a user's motion, and the
// virtual resections (cam osteochondroplasty, rim trimming) with the motions again.
//
// Pipeline (each stage timed):
//   1. femur landmarks (anatomy/femur_landmarks.h) and, unless the frame is given, the pelvis' APP
//      (anatomy/pelvis_landmarks.h, its superior hint the femur's axis towards the head);
//   2. side: --side, the frame file's, and the half of the pelvis that holds the femoral head must
//      agree; a LEFT hip is mirrored through the pelvis' midsagittal plane into a right one (working
//      coordinates) and everything is computed there (anatomy/side.h), then mapped back;
//   3. the femur frame (ISB, Wu et al. 2002): superior along the mechanical axis when the distal
//      femur is there, else the shaft; right in the plane of the epicondyles, else the pelvis' right;
//   4. the acetabulum (anatomy/acetabulum.h) and the measures (anatomy/clinical_measures.h);
//   5. the femur moved to neutral (its frame onto the pelvis frame, about the HJC), then the clinical
//      motions (anatomy/clinical_motions.h) and a user motion (anatomy/motion_depths.h);
//   6. resections (anatomy/resection.h) on the scanned-pose bones, measures and motions again.
//
// Results are in the input meshes' coordinates (points mm, unit vectors), angles in degrees,
// clock positions in the right-hip convention for both sides (3 o'clock anterior).
#pragma once

#include "anatomy/acetabulum.h"
#include "anatomy/anatomical_frame.h"
#include "anatomy/clinical_measures.h"
#include "anatomy/clinical_motions.h"
#include "anatomy/femur_landmarks.h"
#include "anatomy/frame_file.h"
#include "anatomy/motion_depths.h"
#include "anatomy/pelvis_landmarks.h"
#include "anatomy/side.h"
#include "geometry/tri_mesh.h"
#include "studies/pipeline/motion.h"

#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::studies {

struct AssessmentRequest {
  const geometry::TriMesh* femur = nullptr;   // required: femur bone, closed, in the scan's frame
  const geometry::TriMesh* pelvis = nullptr;  // required: pelvis bone, same frame
  std::string femur_name = "femur", pelvis_name = "pelvis";  // for messages
  std::optional<anatomy::Side> side;          // --side
  std::optional<anatomy::UserFrame> frame;    // --frame
  std::optional<Motion> motion;               // --motion (JCS angles)
  std::optional<double> resect_alpha_deg;     // --resect-alpha-deg
  std::optional<double> trim_rim_deg;         // --trim-rim-deg
  int threads = 1;
  bool progress = false;  // one line per stage on stdout
};

// What the motions and measures were before and after the resections.
struct AssessmentState {
  anatomy::ClinicalMeasures measures;
  anatomy::ClinicalRom rom;
};

struct ResectionSummary {
  std::string kind;                 // "cam" or "rim"
  double requested_deg = 0.0;       // target alpha, or trim angle
  double removed_volume_mm3 = 0.0;
  double original_volume_mm3 = 0.0;
  bool closed = false, manifold = false;
  std::vector<std::pair<double, double>> removed_by_clock;  // (clock at bin middle, mm^3), non-zero bins
  // Self-intersecting triangle pairs of the bone repaired before the Boolean (0: none), and where.
  std::size_t repaired_pairs = 0;
  geometry::Vec3 repaired_near_mm = geometry::Vec3::Zero();  // working coordinates
  double seconds = 0.0;
};

struct AssessmentResult {
  anatomy::Side side = anatomy::Side::kRight;
  std::string side_source;          // how the side was decided
  // Working coordinates (a right hip) -> input coordinates: identity for a right hip, the mirror for
  // a left one (its own inverse).
  Eigen::Affine3d to_input = Eigen::Affine3d::Identity();

  // In working coordinates (map with to_input for output; the report unit does).
  geometry::Vec3 hjc_mm = geometry::Vec3::Zero();
  anatomy::AnatomicalFrame pelvis_frame, femur_frame;
  std::string pelvis_frame_source, femur_frame_source;
  std::optional<anatomy::PelvisLandmarks> pelvis_landmarks;
  anatomy::FemurLandmarks femur_landmarks;
  geometry::Vec3 neck_axis = geometry::Vec3::UnitX();   // used for alpha and the femoral clock
  std::string neck_axis_source;
  anatomy::Acetabulum acetabulum;
  Eigen::Matrix3d neutral_rotation = Eigen::Matrix3d::Identity();  // femur scanned -> neutral, about hjc

  AssessmentState before;
  std::optional<AssessmentState> after;           // with the resections applied
  std::vector<ResectionSummary> resections;
  std::optional<anatomy::MotionDepths> motion_depths;
  std::string motion_name;

  // Meshes in working coordinates for the figures and the VTP files.
  geometry::TriMesh pelvis, femur_neutral;
  std::optional<geometry::TriMesh> pelvis_after, femur_after_neutral;

  std::vector<std::pair<std::string, double>> stage_seconds;
  double total_seconds = 0.0;

  // A working-coordinates point / direction / frame in the input's coordinates ("right" stays the
  // subject's right).
  geometry::Vec3 point_to_input(const geometry::Vec3& p) const { return to_input * p; }
  geometry::Vec3 direction_to_input(const geometry::Vec3& d) const { return to_input.linear() * d; }
  anatomy::AnatomicalFrame frame_to_input(const anatomy::AnatomicalFrame& frame) const;
};

// Throws hipfai::Error with one line for bad input: empty meshes, no femoral head, a pelvis that is
// not whole without --frame, bones intersecting in the neutral pose, a side that contradicts the
// bones, a resection on a mesh that is not a closed manifold.
AssessmentResult assess_hip(const AssessmentRequest& request);

}  // namespace hipfai::studies
