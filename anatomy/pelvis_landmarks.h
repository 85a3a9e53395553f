// hipfai — the anterior pelvic plane (APP) and the pelvis frame, found on a whole pelvis alone.
//
// The APP (Lewinnek et al. 1978) is the plane through both anterior superior iliac spines (ASIS)
// and the pubic tubercles. Like Kai et al. (2014), the landmarks are found as the points where a
// plane laid on the front of the pelvis touches it, refined until the plane and its landmarks agree:
//
//   1. Medio-lateral axis: of the pelvis' three principal axes, the normal of its plane of bilateral
//      symmetry — the one whose mirror image through the centroid lies closest to the pelvis (mean
//      nearest-vertex distance of a vertex sample). A hemipelvis or a fragment has no such plane:
//      it is refused (the user gives --frame).
//   2. Superior: the request's hint (the femur's shaft towards its head, in the scanned pose; only
//      its side of the transverse plane and a rough tilt matter), made perpendicular to the ML axis.
//      Anterior: the side of the HJC on which the pelvis has bone at its midline well below the HJC
//      — the pubic symphysis (without a sacrum nothing else lies there; with one, its tip is above).
//   3. First APP: in the projection on the sagittal plane, the convex hull's longest edge facing
//      anteriorly (within 60 deg of the anterior estimate): it joins the ASIS and the pubic
//      tubercles' silhouettes (between them the anterior inferior iliac spine and the acetabulum lie
//      inside the hull).
//   4. Refinement: with the plane's normal n and its superior direction, ASIS (right, left) = the
//      most anterior (along n) points of each hemipelvis above the middle of the plane's contact
//      segment; pubic tubercles = the same below it. The new plane passes through both ASIS and the
//      tubercles' midpoint; repeated until the four landmarks stop changing (Kai et al. iterate the
//      same way from an inertial guess; here the first plane is the hull's, so a few rounds suffice).
//
// Frame (anatomical_frame.h): anterior = the APP normal pointing forwards; right = from the left
// to the right ASIS, made perpendicular to it; superior = right x anterior. The subject's right is
// decided by anatomy (anterior x superior), never by the scanner's axes, so a mirrored pelvis gives
// a mirrored frame and the hip's side follows from which half holds the HJC.
#pragma once

#include "anatomy/anatomical_frame.h"
#include "anatomy/side.h"
#include "geometry/tri_mesh.h"

#include <string>

namespace hipfai::anatomy {

struct PelvisLandmarksRequest {
  const geometry::TriMesh* pelvis = nullptr;  // required: the whole pelvis (both hemipelves), closed
  geometry::Vec3 hjc_mm = geometry::Vec3::Zero();  // required: the hip joint centre of the hip studied
  // Required: roughly superior (e.g. the femur's shaft axis towards the head). Within ~45 deg of the
  // truth gives the same landmarks; the test says so.
  geometry::Vec3 superior_hint = geometry::Vec3::UnitZ();
  int max_iterations = 20;
  std::string what = "pelvis";  // names the mesh in error messages
};

struct PelvisLandmarks {
  geometry::Vec3 asis_right_mm = geometry::Vec3::Zero();
  geometry::Vec3 asis_left_mm = geometry::Vec3::Zero();
  geometry::Vec3 pubic_tubercle_right_mm = geometry::Vec3::Zero();
  geometry::Vec3 pubic_tubercle_left_mm = geometry::Vec3::Zero();
  // The pelvis frame: origin at the request's HJC (Wu et al. 2002), axes from the APP.
  AnatomicalFrame frame;
  Side side = Side::kRight;  // the half of the pelvis that holds the HJC
  // Mean distance of the mirrored vertex sample to the pelvis, mm, and as a fraction of the
  // pelvis' width: how symmetric the bone is about the plane found (small for a whole pelvis).
  double symmetry_residual_mm = 0.0;
  double width_mm = 0.0;      // extent along the ML axis
  int iterations = 0;         // refinement rounds until the landmarks stopped changing
};

// Throws hipfai::Error "<what>: ..." (one line) for an empty mesh, a pelvis without bilateral
// symmetry (a hemipelvis or fragment: give the frame), no bone at the midline below the HJC, or a
// refinement that does not settle.
PelvisLandmarks find_pelvis_landmarks(const PelvisLandmarksRequest& request);

}  // namespace hipfai::anatomy
