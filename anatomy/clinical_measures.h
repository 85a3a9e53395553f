// hipfai — the radiographic measures of a RIGHT hip in 3D, each the way its definition says, and the
// morphology they imply (definitions and thresholds: core/literature.h, "Patient-specific
// assessment" section).
//
//   lateral CE (Wiberg)         geometry::measure_ce_angle in the pelvis frame's coronal plane
//                               (lateral = right, superior from the APP) through the head centre;
//   acetabular orientation      Murray's radiographic and anatomic inclination and anteversion of the
//                               rim plane's axis (anatomy/acetabulum.h);
//   alpha (Nötzli)              geometry::measure_alpha_angle about the femur's neck axis, Nötzli's
//                               plane towards the femur frame's anterior, with the clock profile,
//                               on the head sphere of the femur landmarks; a real head scatters about
//                               its sphere by its fit's RMS residual, so the contour is "off the
//                               sphere" beyond 3 RMS (and never less than the tessellation's own
//                               automatic tolerance), walking from the neck-side end of the longest
//                               run of the articular surface (gaps up to 3 deg bridged: the fovea);
//   head-neck offset (Eijer)    in Nötzli's plane: the anterior head radius (the farthest the anterior
//                               contour gets from the neck axis over the head, centre to pole) minus
//                               the anterior neck radius (the least the outermost anterior contour gets
//                               from the axis over the neck, from the head centre to 2 head radii
//                               along the axis), both perpendicular to the axis; ratio = offset / head
//                               diameter;
//   neck-shaft angle, version   from anatomy/femur_landmarks.h.
//
// Morphology: dysplasia (LCE < 20), pincer (LCE > 39), cam (Nötzli alpha > 50.5), combined (cam and
// pincer), cam with dysplasia, else normal.
#pragma once

#include "anatomy/acetabulum.h"
#include "anatomy/anatomical_frame.h"
#include "anatomy/femur_landmarks.h"
#include "geometry/hip_measure.h"
#include "geometry/tri_mesh.h"

#include <optional>
#include <string>
#include <vector>

namespace hipfai::anatomy {

enum class Morphology { kNormal, kCam, kPincer, kCombined, kDysplasia, kCamWithDysplasia };

// "normal", "cam", "pincer", "combined", "dysplasia", "cam_with_dysplasia".
const char* morphology_name(Morphology morphology);

struct HeadNeckOffset {
  bool measured = false;
  std::string reason;              // why not measured
  double head_radius_mm = 0.0;     // anterior head radius, perpendicular to the neck axis
  double neck_radius_mm = 0.0;     // anterior neck radius at the waist
  double neck_waist_mm = 0.0;      // where along the neck axis (from the head centre)
  double offset_mm = 0.0;
  double ratio = 0.0;              // offset / head diameter
};

// The offset in the half-plane through `centre` spanned by the neck axis and `anterior` (made
// perpendicular to it).
HeadNeckOffset measure_head_neck_offset(const geometry::TriMesh& femur, const geometry::Vec3& centre,
                                        double head_radius_mm, const geometry::Vec3& neck_axis,
                                        const geometry::Vec3& anterior);

struct ClinicalMeasuresRequest {
  const geometry::TriMesh* pelvis = nullptr;  // required
  const geometry::TriMesh* femur = nullptr;   // required, in the scanned pose
  AnatomicalFrame pelvis_frame;               // right hip: right = lateral
  AnatomicalFrame femur_frame;                // its anterior orients Nötzli's plane
  const FemurLandmarks* femur_landmarks = nullptr;  // required
  const Acetabulum* acetabulum = nullptr;           // required
  // The femoral head centre of Wiberg's angle: the HJC (given with a frame, else the head's fit).
  geometry::Vec3 hjc_mm = geometry::Vec3::Zero();
};

struct ClinicalMeasures {
  geometry::CeMeasurement lateral_ce;
  double acetabular_inclination_deg = 0.0;           // radiographic (Murray)
  double acetabular_version_deg = 0.0;               // radiographic (Murray)
  double acetabular_inclination_anatomic_deg = 0.0;
  double acetabular_version_anatomic_deg = 0.0;
  geometry::AlphaMeasurement alpha;
  HeadNeckOffset head_neck_offset;
  double neck_shaft_deg = 0.0;
  std::optional<double> femoral_version_deg;
  std::string femoral_version_reason;                // why not measured
  Morphology morphology = Morphology::kNormal;
  std::vector<std::string> findings;                 // one line per threshold crossed, with its value
};

// Throws hipfai::Error when the CE or alpha section is empty (a pelvis without the acetabulum in
// the coronal plane, a femur without a head contour).
ClinicalMeasures measure_clinical(const ClinicalMeasuresRequest& request);

}  // namespace hipfai::anatomy
