// hipfai — virtual resections: cam osteochondroplasty of the femoral head-neck junction, and
// trimming of the acetabular rim (pincer).
//
// Both cut the bone with a "curved box": a closed solid bounded by coordinate surfaces of the
// spherical coordinates (r, polar angle v from an axis, clock angle u about it) centred on the
// head (cam) or the acetabulum (rim). It is meshed as the boundary of an index grid
// [0, nu] x [0, nv] x [0, 1] mapped to space: the r direction needs one step (its lines are rays
// from the centre, so the r = const faces are the only curved ones), the u and v steps are chosen
// so that every flat facet stays within a prescribed distance of the sphere it stands for (a
// triangle with angular circumradius a on a sphere of radius r sags r (1 - cos a) below it; the
// grid's triangles are near-right with legs of at most h, so a <= h / sqrt(2)). The clock
// direction is periodic when the cut goes all around; when the polar range reaches the axis
// (the cam's pole side) the last row collapses onto it, so the solid is a thick spherical cap
// (a ball topologically) rather than a ring with a thin hole along the axis.
// The bone minus the tool (mesh Booleans, anatomy/mesh_boolean.h) is the resected bone; bone ∩
// tool is the removed bone, whose volume is reported in total and per clock sector. The volume of
// a closed region inside a wedge of clock angles is the flux through its surface of the field
// F(x) = P (x - c) / 2 (P projects onto the plane normal to the axis: div F = 1, and F is tangent
// to the wedge's half-planes), so each triangle contributes F(centroid) . area normal to the bin
// of its centroid's clock angle; the bins sum to the removed volume exactly.
//
// Cam (CamResectionRequest): with head sphere (c, R) and neck axis n, the alpha angle is the polar
// angle from n at which the head-neck contour, walked from the pole, first leaves the sphere by
// more than the measurement's tolerance t (geometry/hip_measure.h). To bring alpha down to A, all
// bone outside the sphere (c, R + t) at polar angles >= A is removed, out to R_out. The tool's
// inner surface has its vertices at R + 3t/4 and facets that sag at most t/4, so the new bone
// surface lies between R + t/2 and R + 3t/4: inside the tolerance band with t/4 of margin either
// side (never into the head sphere, never flagged by the alpha measurement).
//
// Rim (RimTrimRequest): with acetabular centre c, opening axis a (out of the socket) and the
// rim's polar angle from a as a function of the clock angle, trimming by D removes, in a clock
// sector, the bone whose polar angle is below rim(clock) + D — the rim moves D deg deeper and the
// lateral CE angle drops by about D where the sector covers the frontal plane's superior point.
//
// Clock angles: from the anterior direction (0, 3 o'clock of a right hip) towards the superior one
// (90, 12 o'clock), as geometry/hip_measure.h. A ClockSector runs from `from_deg` counter-clockwise
// (increasing clock angle) to `to_deg`; to - from >= 360 means all around.
#pragma once

#include "core/literature.h"
#include "geometry/tri_mesh.h"

#include <vector>

namespace hipfai::anatomy {

struct ClockSector {
  double from_deg = -180.0;  // start, clock angle (deg)
  double to_deg = 180.0;     // end, reached going through increasing clock angles (deg)
};

struct ClockBinVolume {
  double from_deg = 0.0;      // bin start, clock angle (deg)
  double to_deg = 0.0;        // bin end (deg)
  double removed_mm3 = 0.0;   // removed bone volume in the bin, mm^3
};

struct CamResectionRequest {
  const geometry::TriMesh* femur = nullptr;  // femur bone surface, a closed solid (required)
  geometry::Vec3 head_centre_mm = geometry::Vec3::Zero();  // fitted head sphere centre c
  double head_radius_mm = 0.0;                             // fitted head sphere radius R (> 0)
  geometry::Vec3 neck_axis = geometry::Vec3::UnitX();      // unit, from c towards the neck
  geometry::Vec3 anterior = geometry::Vec3::UnitY();       // clock 0; made perpendicular to n
  geometry::Vec3 superior = geometry::Vec3::UnitZ();       // picks the side of clock 90
  double target_alpha_deg = literature::kCamResectionTargetAlphaDeg;  // A, in (0, 180)
  // The alpha measurement's departure tolerance t, mm (geometry::AlphaMeasurement::tolerance_mm);
  // > 0 and < R.
  double tolerance_mm = 0.0;
  // R_out / R. 1.5: a cam stands a few mm (2-5) proud of the head sphere, well inside 1.5 R
  // (~35 mm for R = 23), while the trochanters are 45 mm and more from the head centre.
  double outer_radius_factor = 1.5;
  // The blend into the neck, deg (0: none, a step where the cut meets bone at A). Below A the cut
  // surface rises from the sphere tangentially, r = R + 3t/4 + 0.9 (R_out - R - 3t/4) ((A - polar) / w)^2
  // for A - w <= polar < A (the ramp starts 1 deg below A: the alpha measurement extrapolates the
  // ramp back to the sphere, ~1 deg above its start), so cam bone proud just below A is shaved along a smooth ramp
  // instead of leaving a ledge (the concave head-neck contour an osteochondroplasty recreates); the
  // ramp passes the tolerance t within ~1-2 deg of A, so alpha ends at or just below A. 15 deg: an
  // assumption (a few mm of neck at the head-neck junction), not a published value.
  double transition_deg = 15.0;
  ClockSector sector;              // where to resect; all around by default
  double clock_bin_deg = 15.0;     // width of the removed-volume bins (deg, > 0)
};

struct CamResection {
  geometry::TriMesh resected;      // femur minus the tool: closed, manifold, outward
  geometry::TriMesh removed;       // femur ∩ tool (empty when nothing is removed)
  geometry::TriMesh tool;          // the cutting solid
  double original_volume_mm3 = 0.0;
  double resected_volume_mm3 = 0.0;
  double removed_volume_mm3 = 0.0;  // volume of `removed` (= original - resected up to rounding)
  std::vector<ClockBinVolume> removed_by_clock;  // bins over [-180, 180), clock about n
  double seconds = 0.0;             // wall-clock time of resect_cam
};

// The cam tool alone: {R + 3t/4 (faceted, see above) <= r <= R_out, polar >= A, clock in sector},
// extended below A by the blend (transition_deg).
geometry::TriMesh make_cam_tool(const CamResectionRequest& request);

// Removes the bone outside the sphere (c, R + t) at polar angles >= A from the neck axis, within
// R_out and the clock sector. Throws hipfai::Error for bad input (femur not a solid, R, t, A out
// of range, axes degenerate).
CamResection resect_cam(const CamResectionRequest& request);

struct RimSample {
  double clock_deg = 0.0;  // clock angle about the opening axis (deg)
  double polar_deg = 0.0;  // the rim's polar angle from the opening axis there (deg, in (0, 180))
};

struct RimTrimRequest {
  const geometry::TriMesh* pelvis = nullptr;  // pelvis (or hemipelvis) bone, a closed solid (required)
  geometry::Vec3 acetabular_centre_mm = geometry::Vec3::Zero();  // centre c of the socket sphere
  double acetabular_radius_mm = 0.0;                             // its radius R (> 0)
  geometry::Vec3 opening_axis = geometry::Vec3::UnitX();  // unit a, pointing out of the socket
  geometry::Vec3 anterior = geometry::Vec3::UnitY();      // clock 0; made perpendicular to a
  geometry::Vec3 superior = geometry::Vec3::UnitZ();      // picks the side of clock 90
  // Rim profile, linearly interpolated in clock angle (periodic); at least one sample.
  std::vector<RimSample> rim;
  double trim_deg = 0.0;  // D: how much deeper the rim goes (deg, > 0)
  // 9 o'clock through 12 to 3 o'clock: the superior half, where pincer rims are trimmed.
  ClockSector sector{0.0, 180.0};
  // The tool starts this far outside the rim (deg) so that bone standing proud of the given rim
  // profile is cut too; its lower polar bound is clamped at 1 deg (off the axis).
  double overreach_deg = 30.0;
  // r_in / R = 0.8: inside the socket cavity (where the head is), so the cut goes through the
  // rim from its articular side; r_out / R = 1.6: beyond the bony rim's thickness (the wall near
  // the rim is well under 0.6 R thick), short of the inferior iliac spine.
  double inner_radius_factor = 0.8;
  double outer_radius_factor = 1.6;
  // Largest distance of the tool's facets from the surfaces they stand for, mm (> 0).
  double facet_tolerance_mm = 0.05;
  double clock_bin_deg = 15.0;  // width of the removed-volume bins (deg, > 0)
};

struct RimTrim {
  geometry::TriMesh trimmed;   // pelvis minus the tool
  geometry::TriMesh removed;   // pelvis ∩ tool (empty when nothing is removed)
  geometry::TriMesh tool;      // the cutting solid
  double original_volume_mm3 = 0.0;
  double trimmed_volume_mm3 = 0.0;
  double removed_volume_mm3 = 0.0;
  std::vector<ClockBinVolume> removed_by_clock;  // bins over [-180, 180), clock about a
  double seconds = 0.0;  // wall-clock time of trim_rim
};

// The rim tool alone: {clock in sector, max(1, rim - overreach) <= polar <= rim + D,
// r_in <= r <= r_out}.
geometry::TriMesh make_rim_tool(const RimTrimRequest& request);

// Trims the rim (see the header comment). Throws hipfai::Error for bad input.
RimTrim trim_rim(const RimTrimRequest& request);

// The rim's polar angle at `clock_deg`, linear interpolation of the samples (periodic in clock).
double rim_polar_deg(const std::vector<RimSample>& rim, double clock_deg);

}  // namespace hipfai::anatomy
