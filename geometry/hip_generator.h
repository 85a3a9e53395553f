// hipfai — the parametric CAD-like hip (thesis §4.3.2.2, Figs. 58-59), built with gmsh's
// OpenCASCADE kernel and meshed per tissue.
//
// Construction in the hip frame (R = articular radius, n = neck axis, a = acetabular axis):
//   femur_bone           head ball of radius R - t_f + s centred at s n (s chosen so that the lens
//                        below thins to zero at femoral_cartilage_edge_deg from n), clipped to the
//                        R sphere and cut by the plane normal to n at the head-neck junction
//                        (min(alpha, normal_alpha) from n), fused with a neck cylinder along n, a
//                        shaft stub along -Z at the end of the neck, and, when alpha exceeds
//                        normal_alpha, the cam: a ball in the anterosuperior cam plane whose
//                        intersection with the R sphere passes through the point at alpha from n,
//                        swept about n over the cam's clock arc (one solid sewn from faces that
//                        share their edges: no boolean between its tangent parts).
//   femoral_cartilage    R ball minus the head ball (and the cam): a lens, t_f thick at the pole,
//                        zero at its edge.
//   acetabular_bone      pelvis block intersected with the socket half-space x . a <= 0, minus the
//                        R + t_a ball.
//   acetabular_cartilage shell R .. R + t_a in the socket half-space, minus the fossa cylinder
//                        (horseshoe open inferiorly). Both acetabular solids are cut back to
//                        labrum_neck_clearance_mm outside the neck cylinder where a deep socket's
//                        rim reaches it in the neutral pose (not on the study grid).
//   labrum               triangle (R, 0), (R + base, 0), tip on the R sphere at labrum_height along
//                        a, revolved about a; interrupted at the inferior notch and kept
//                        labrum_neck_clearance_mm outside the neck cylinder (shallow sockets
//                        bring the posteroinferior rim over the neck in the neutral pose); a
//                        sliver the two cuts leave between them (less than one base width of the
//                        section along the rim) is removed.
// Each tissue is meshed on its own (surfaces are not shared between tissues), so each is a
// closed manifold surface; triangles are re-oriented outward.
// Coincidences the B-rep cannot carry are kept out of every (CE, alpha) of the range: a circle of
// the head (margin, junction) on a foot of the cam is moved 0.01 deg off it, the cam's clip is
// kept 1 mm off its section's centre, a rim cone within 1e-4 rad of a plane is built as the plane,
// the cam's end balls are sewn to its sweep along their tangent circles instead of fused with it,
// and a femoral sphere whose seam would cross the head's band takes the seam's other half
// (hip_generator.cpp says why each).
#pragma once

#include "geometry/hip_model.h"
#include "geometry/hip_parameters.h"

#include <filesystem>
#include <string>

namespace hipfai::geometry {

struct HipGeneratorResult {
  enum class Status { kOk, kFailed };
  Status status = Status::kFailed;
  HipModel model;
  double seconds = 0.0;   // wall-clock time of construction + meshing
};

// Builds and meshes one hip. Throws hipfai::Error on invalid parameters or when OpenCASCADE or
// the mesher fails (the message names the tissue). Serialised: gmsh is not re-entrant.
// gmsh runs in a forked child (core/child_process.h): when the surface mesher crashes (Debian's
// gmsh 4.8 frees a point twice on some spherical seams), the next algorithm of the list (6, 1, 5)
// is tried in a new child, and the error lists each algorithm's failure ("gmsh crashed (SIGABRT)").
HipGeneratorResult generate_hip(const HipParameters& parameters);

}  // namespace hipfai::geometry
