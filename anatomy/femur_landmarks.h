// hipfai — landmarks, axes and angles of a femur found on its surface alone (any pose, any frame,
// right or left, whole femur or proximal part).
//
// Method (all steps on the triangle surface; every length is scaled by the head radius R, so the
// steps do not depend on the scanner's frame or units of pose):
//   head      geometry::find_femoral_head (Hough vote for (centre, radius), band refinement, largest
//             spherical patch), then settled: the vertices within max(0.5 mm, 2.5 rms) of the
//             sphere facing away from its centre are refitted (geometric least squares) until
//             that set stops changing, so the result does not depend on the vote's fixed grid.
//             With a head-centre hint only the bone within 60 mm of the hint is searched.
//   neck      the centre line of the narrowest cross-sections of the neck: planes perpendicular to
//             the current axis d at t = 0.5 R .. 2.5 R (0.05 R steps) from the head centre c cut
//             the bone; in each, the closed loop around the axis (its area centroid, shoelace
//             formula) is kept unless most of it lies on the head's sphere (a section of the
//             head, centred on whatever axis is tried). The narrow neck is the run of sections
//             within 10 % of the smallest area; d becomes the line through c fitted to their
//             centroids (least squares; centroids farther from it than 3 median distances,
//             sections reaching into the flare of the neck's base, are dropped and the line
//             refitted); repeated until d settles. Why: the neck is not a cylinder (it widens
//             towards the head and the trochanters); its isthmus is the part that is a tube, so
//             the centroids there lie on its axis and neither the head nor the trochanters pull
//             them. This is the "line through the head centre and the midpoint of the narrowest
//             part of the neck" of anatomical definitions, found in 3D. Start: c towards the
//             centroid of the bone 1.2 R .. 2 R from c. Point kept: the narrowest section's
//             centroid.
//   shaft     the line fitted (principal direction) to the area centroids of sections
//             perpendicular to the current axis over the diaphysis, four rounds (start: principal
//             axis of the bone farther than 2 R from c). Diaphysis of a whole femur: 20 % .. 80 %
//             of the bone length from its distal end, the diaphyseal sections of Ruff & Hayes
//             (core/literature.h). Of a proximal femur: the sections more than 1.5 R below c
//             (below the neck) and more than 10 % of their distance from c above the cut end,
//             within 25 % of the smallest section area (no flare: the trochanters and the neck's
//             base make the sections they cut larger).
//   distal    has_distal when the bone is longer than 8 R along the shaft AND its distal 15 %
//             is wider than twice the shaft's diameter (the condyles: an epicondylar breadth
//             about three midshaft diameters). Transepicondylar direction: largest spread, in the
//             plane perpendicular to the shaft, of the distal 15 %; epicondyles: its extreme
//             points along it; medial: the one on the side of the head. Knee centre: their
//             midpoint (Wu et al. 2002). Posterior: the side towards which the condyles stand out
//             more from the shaft line. Posterior condylar points: the bitangent of the medial and
//             lateral halves of the distal 15 %, projected on the plane perpendicular to the
//             mechanical axis, from behind (a plane containing the mechanical axis touching both
//             condyles posteriorly).
//   side      anterior x superior points to the subject's right: with the distal femur, anterior =
//             -posterior (condyles), superior = the mechanical axis, lateral = away from the head;
//             right if lateral is the subject's right. Without it, anterior = the request's
//             anterior_hint (made perpendicular to the shaft), lateral = the neck axis' part
//             perpendicular to the shaft; no hint: unknown.
//   angles    neck-shaft (CCD) angle: 3D angle between the neck axis towards the head and the
//             shaft axis pointing distally. Femoral version: the angle, in the plane
//             perpendicular to the mechanical axis (the transverse plane of the ISB femoral frame
//             of Wu et al. 2002, so version and the frame agree), from the posterior condylar
//             line (pointing medially) to the neck axis towards the head, positive when the head
//             points anteriorly (anteversion); Murphy et al. 1987's CT definition (neck axis
//             against the posterior condylar line in the transverse plane) in 3D.
//
// Published automatic methods this follows: Kai et al. 2014 (J Biomech 47:1229, sections
// perpendicular to the inertia axis for the shaft; the neck axis through the head centre and the
// narrowest neck section) and GIBOC/STAPLE (Renault et al. 2018, Modenese & Renault 2021, J Biomech
// 116:110186: sphere fit of the head, epicondyles as extreme points of the condyles along the
// transverse direction, ISB frame). Differences: the head is found by a Hough vote rather than a
// curvature segmentation; the neck axis is the fixed point of the narrowest-section centroid line
// rather than one minimal section or a cylinder/ellipse fit; the diaphysis is chosen by length
// fractions (whole femur) or section areas (proximal femur) rather than by fitting the medullary
// canal; the condyles are not fitted (no cylinder or ellipsoid), only their extreme points.
//
// Invariance: every step uses distances and directions between surface points, so a rigid motion
// of the mesh moves the result with it; a reflection (anatomy::reflected) mirrors the landmarks,
// flips the side and keeps the angles (the head's Hough vote uses a fixed grid, which only changes
// where the refinement starts, not where it converges).
#pragma once

#include "anatomy/anatomical_frame.h"
#include "anatomy/side.h"
#include "geometry/tri_mesh.h"

#include <optional>
#include <string>

namespace hipfai::anatomy {

struct FemurLandmarksRequest {
  const geometry::TriMesh* femur = nullptr;  // required: a closed femur surface (whole or proximal)
  // Optional: roughly the head centre (e.g. hip.json's HJC); the head is searched within
  // 60 mm of it. Empty: the whole surface is searched.
  std::optional<geometry::Vec3> head_centre_hint_mm;
  // Optional: roughly the subject's anterior (e.g. the pelvis frame's); used only to tell the side
  // of a femur without its distal end (with the distal end it is never used).
  std::optional<geometry::Vec3> anterior_hint;
  std::string what = "femur";  // names the mesh in error messages
};

struct FemurLandmarks {
  // Femoral head: geometric least-squares sphere of the articular head region.
  geometry::Vec3 head_centre_mm = geometry::Vec3::Zero();
  double head_radius_mm = 0.0;
  double head_fit_rms_mm = 0.0;         // RMS of |p - c| - r over the head region
  std::size_t head_vertices = 0;        // vertices of the head region fitted

  // Neck axis: unit, from the head centre towards the neck and trochanters.
  geometry::Vec3 neck_axis = geometry::Vec3::Zero();
  geometry::Vec3 neck_point_mm = geometry::Vec3::Zero();  // centroid of the narrowest neck section
  double neck_section_area_mm2 = 0.0;   // area of that section
  int neck_sections = 0;                // sections of the narrow neck the axis was fitted to
  int neck_iterations = 0;              // rounds until the axis settled

  // Shaft (anatomical) axis: unit, pointing proximally; through shaft_point_mm.
  geometry::Vec3 shaft_axis = geometry::Vec3::Zero();
  geometry::Vec3 shaft_point_mm = geometry::Vec3::Zero();  // mean of the section centroids used
  // The diaphysis used: distances below the head centre, along the shaft axis, of its proximal
  // and distal sections (mm), and how many sections.
  double shaft_from_mm = 0.0;
  double shaft_to_mm = 0.0;
  int shaft_sections = 0;
  double length_mm = 0.0;               // extent of the bone along the shaft axis
  double shaft_diameter_mm = 0.0;       // equivalent diameter 2 sqrt(A / pi) of the mean section

  // Distal femur: set only when has_distal.
  bool has_distal = false;
  std::string distal_missing_reason;    // why has_distal is false (empty when true)
  std::optional<geometry::Vec3> knee_centre_mm;          // midpoint of the epicondyles
  std::optional<geometry::Vec3> medial_epicondyle_mm;
  std::optional<geometry::Vec3> lateral_epicondyle_mm;
  std::optional<geometry::Vec3> medial_posterior_condyle_mm;   // posterior condylar line's ends
  std::optional<geometry::Vec3> lateral_posterior_condyle_mm;
  std::optional<geometry::Vec3> mechanical_axis;         // unit, knee centre -> head centre

  // Side, when the femur alone (or the anterior hint) tells it, and how it was decided.
  std::optional<Side> side;
  std::string side_method;

  // Angles (degrees).
  double neck_shaft_angle_deg = 0.0;    // CCD angle, 3D
  std::optional<double> version_deg;    // femoral version, + anteversion
  std::string version_missing_reason;   // why version_deg is empty

  // The femoral frame (anatomical_frame.h: origin at the head centre, superior along the
  // mechanical axis, else the shaft axis; right in the plane of the transepicondylar axis, else
  // in the plane of the neck axis (lateral), signed by the side); set when the side is known.
  std::optional<AnatomicalFrame> frame;
};

// Throws hipfai::Error "<what>: ..." (one line) for no or an empty mesh, no femoral head (no part
// fits a sphere of radius 15-35 mm), no neck (nothing narrower than the head beyond it) or no shaft
// (the bone ends within 1.5 head radii of the head centre).
FemurLandmarks find_femur_landmarks(const FemurLandmarksRequest& request);

}  // namespace hipfai::anatomy
