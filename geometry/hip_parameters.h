// hipfai — parameters of the parametric CAD-like hip (thesis §4.3.2.2, Figs. 58-59).
//
// Every dimension of a generated hip is one field below with its default, its allowed range and
// its source. Generated hips are RIGHT hips in the hip frame of geometry/hip_frame.h (origin at
// the HJC, +X lateral, +Y anterior, +Z superior). Lengths in mm, angles in degrees.
//
// The two clinical parameters of the FAI study are
//   ce_deg     lateral centre-edge angle of Wiberg: in the frontal plane Y = 0, the angle between
//              +Z and the line from the HJC to the lateral edge of the bony acetabulum (the rim of
//              the acetabular bone and cartilage; the labrum is NOT part of it). The rim is a
//              cone with its apex at the HJC (every rim point is seen from the HJC at the same
//              angle socket_opening_deg from the acetabular axis), so the angle is the same on
//              the 25 mm and 27 mm spheres. By default (ce_rim_mode 0) CE sets the depth of the
//              whole rim about a fixed acetabular axis: the socket is a hemisphere at
//              hemisphere_ce_deg (the thesis' normal hip), deeper everywhere above it
//              (coxa profunda, global over-coverage) and shallower below it (dysplasia).
//   alpha_deg  alpha angle of Nötzli: in the oblique axial plane through the neck axis (the
//              half-plane towards anterior, "3 o'clock"), the angle between the neck axis and
//              the line from the HJC to where the bone+cartilage contour first leaves the head
//              sphere. The cam holds this alpha over the clock arc cam_begin_deg..cam_end_deg
//              (3 o'clock to 1:30 by default) and tapers outside it.
#pragma once

#include "core/literature.h"
#include "geometry/tri_mesh.h"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::geometry {

struct HipParameters {
  // Lateral CE angle, [0, 45] deg; study grid 0..40 (thesis §4.3.2.2).
  double ce_deg = 30.0;
  // Alpha angle, [35, 90] deg; study grid 40..80, a normal hip has ~40 (literature::kNormalAlphaDeg).
  double alpha_deg = literature::kNormalAlphaDeg;
  // Radius shared by the articulating surfaces, [20, 30] mm (literature::kArticularRadiusMm).
  double articular_radius_mm = literature::kArticularRadiusMm;
  // Femoral cartilage at the pole, [0.5, 4] mm (literature::kFemoralCartilageMaxThicknessMm).
  double femoral_cartilage_mm = literature::kFemoralCartilageMaxThicknessMm;
  // Acetabular cartilage, constant, [0.5, 4] mm (literature::kAcetabularCartilageThicknessMm).
  double acetabular_cartilage_mm = literature::kAcetabularCartilageThicknessMm;
  // Labrum, rim to tip along the acetabular axis, [3, 10] mm (literature::kLabrumHeightMm).
  double labrum_height_mm = literature::kLabrumHeightMm;
  // Labrum base width on the rim plane, from the articular sphere outwards, [3, 10] mm
  // (literature::kLabrumBaseWidthMm).
  double labrum_base_mm = literature::kLabrumBaseWidthMm;
  // The labrum stops this far [0, 5] mm outside the femoral neck's cylinder: where a shallow socket
  // (CE 0-10 deg) brings the posteroinferior rim over the neck in the neutral pose, the labrum is
  // left out there rather than standing inside the bone (see hip_generator.h); where a deep socket's
  // rim reaches the neck, its cartilage and bone stop as far outside it. A modelling choice.
  double labrum_neck_clearance_mm = 1.0;
  // Neck-shaft (CCD) angle, [110, 150] deg (literature::kNeckShaftAngleDeg).
  double neck_shaft_angle_deg = literature::kNeckShaftAngleDeg;
  // Femoral anteversion, [-10, 40] deg (literature::kFemoralAnteversionDeg).
  double femoral_anteversion_deg = literature::kFemoralAnteversionDeg;
  // Acetabular anteversion, [0, 35] deg (literature::kAcetabularAnteversionDeg). Tilts the
  // acetabular axis about Z; it leaves the CE angle unchanged.
  double acetabular_anteversion_deg = literature::kAcetabularAnteversionDeg;
  // The CE angle at which the socket is exactly a hemisphere (its rim cone a plane through the
  // HJC), [0, 45] deg: the thesis' normal hip, CE 20 (literature::kThesisNormalCeDeg). Fixes the
  // acetabular axis; with ce_rim_mode 0 the CE then sets the rim's depth all around.
  double hemisphere_ce_deg = literature::kThesisNormalCeDeg;
  // How CE is imposed, 0 or 1: 0 = the whole rim (a spherical cap about the fixed axis whose
  // lateral edge is at CE; thesis Fig. 59's pincer and dysplastic sockets differ in depth);
  // 1 = a hemispherical socket tilted so its lateral edge is at CE (lateral only: the anterior and
  // posterior rims barely move). docs/hip-sensitivity.md compares the two.
  double ce_rim_mode = 0.0;
  // Neck radius, [8, 20] mm (must be below articular_radius * sin(min(alpha, 40 deg))).
  double neck_radius_mm = 13.0;
  // HJC to the shaft axis along the neck axis, [30, 70] mm (a femoral offset of ~40 mm).
  double neck_length_mm = 45.0;
  // Shaft stub radius [8, 25] mm and length below the neck [10, 120] mm.
  double shaft_radius_mm = 14.0;
  double shaft_length_mm = 45.0;
  // Angle of the normal head-neck junction from the neck axis, [30, 50] deg: the alpha angle of a
  // hip without cam (literature::kNormalAlphaDeg). Requests below it move the junction instead
  // of adding a cam.
  double normal_alpha_deg = literature::kNormalAlphaDeg;
  // Edge of the femoral cartilage from the neck axis, [normal_alpha + 2, 80] deg; the cartilage
  // thins to zero there (Eckstein et al. 1997: thinning towards the head-neck junction).
  double femoral_cartilage_edge_deg = 45.0;
  // Cam extent on the clock face, as angles about the neck axis from anterior (3 o'clock)
  // towards superior (12 o'clock), [-90, 180] deg: the cam holds alpha_deg from cam_begin_deg to
  // cam_end_deg and tapers to the normal junction within about a cam radius beyond each end
  // (literature::kCamArcBeginDeg / kCamArcEndDeg: 3 o'clock to 1:30). Equal ends: a single bump.
  double cam_begin_deg = literature::kCamArcBeginDeg;
  double cam_end_deg = literature::kCamArcEndDeg;
  // Cam cross-section: a circle of this radius [4, 20] mm standing this far out of the head
  // sphere [0.5, 6] mm (literature::kCamHeightMm), swept along the arc; balls of the same
  // radius close its ends.
  double cam_radius_mm = 10.0;
  double cam_height_mm = literature::kCamHeightMm;
  // Pelvis block around the socket, extents along X, Y, Z [60, 200] mm; the block is centred
  // medially and superiorly of the HJC by a quarter of its X and Z extents.
  double pelvis_block_x_mm = 80.0;
  double pelvis_block_y_mm = 80.0;
  double pelvis_block_z_mm = 90.0;
  // Acetabular fossa: cartilage is removed within this angle [15, 60] deg of the fossa axis, which
  // lies 30 deg from the inferior rim towards the acetabular pole, so the cartilage becomes a
  // horseshoe open at the inferior notch.
  double fossa_half_angle_deg = 40.0;
  // Width of the labrum gap at the inferior notch [5, 40] mm (the transverse ligament is not modelled).
  double notch_width_mm = 24.0;
  // Target surface edge length, [0.2, 10] mm (thesis Table 3 resolutions).
  double edge_mm = 2.0;
};

// Throws hipfai::Error "<what>: <field> = <value> is outside [lo, hi]" on the first bad field.
void validate_hip_parameters(const HipParameters& parameters, const std::string& what = "hip parameters");

// JSON object with one key per field (the names above); from_json accepts a subset (missing keys
// keep their defaults), rejects unknown keys and validates. Errors name `what` and the key.
std::string hip_parameters_to_json(const HipParameters& parameters, int indent = 2);
HipParameters hip_parameters_from_json(const std::string& text, const std::string& what);
// The same from a JSON file; errors name the file ("<path>: no such file", or as above).
HipParameters load_hip_parameters(const std::filesystem::path& path);
// The fields of `p` whose value differs from `reference`'s, as (JSON key, value), in field order.
std::vector<std::pair<std::string, double>> hip_parameters_changed(const HipParameters& p,
                                                                   const HipParameters& reference = {});

// Directions derived from the parameters, unit vectors in the hip frame.
// Neck axis: from the HJC towards the neck (lateral, inferior and, with anteversion, posterior).
Vec3 neck_axis(const HipParameters& parameters);
// Acetabular axis: axis of the rim cone, pointing out of the socket (lateral, inferior,
// anterior). The socket is the set of directions at least socket_opening_deg from it.
Vec3 acetabular_axis(const HipParameters& parameters);
// Angle (deg) between the acetabular axis and every rim direction: 90 for a hemisphere, below 90
// for a deeper socket. Chosen so that the rim passes through the lateral edge at CE.
double socket_opening_deg(const HipParameters& parameters);
// Unit vector perpendicular to the neck axis at `clock_deg` from anterior towards superior.
Vec3 clock_direction(const HipParameters& parameters, double clock_deg);
// Anterior and superior directions perpendicular to the neck axis (clock 0 and 90 deg).
Vec3 neck_anterior(const HipParameters& parameters);
Vec3 neck_superior(const HipParameters& parameters);

}  // namespace hipfai::geometry
