// hipfai — which geometric features decide whether and when the cam and the rim meet: each
// parameter of the parametric hip over its published range, on the pure-cam (CE 20 / alpha 80)
// and the pure-pincer (CE 40 / alpha 40) hips of thesis Table 10, along standing-to-sitting.
//
// Per variant (one parameter changed from the shipped defaults, both hips):
//   first_contact_deg  exact angle of first contact along the motion's single axis between the
//                      STRIKING part of the femur bone (triangles whose vertices all lie farther
//                      than R + tol from the HJC, the vertices the curvilinear depth counts: see
//                      studies/pipeline/penetration_run.h) and the labrum, by the one-pass range finder;
//                      +inf when beyond 360 deg. Impingement within the motion iff it is below
//                      the motion's angle (63.1 deg for standing to sitting).
//   max_curvilinear_mm, max_radial_mm   the study's depths (penetration_run.h) over the motion.
//   measured_ce_deg, measured_alpha_deg (Nötzli's plane), as a check that the variant still is
//                      the hip it claims to be.
// Hips are generated in memory (gmsh) at `edge_mm`; nothing is cached.
#pragma once

#include "geometry/hip_parameters.h"
#include "geometry/tri_mesh.h"

#include <functional>
#include <string>
#include <vector>

namespace hipfai::studies {

// One parameter value to try: `field` is a HipParameters JSON key.
struct SensitivityVariant {
  std::string field;
  double value = 0.0;
  std::string note;  // where the value comes from (range and source)
};

struct SensitivityOptions {
  double edge_mm = 3.0;
  int sub_motions = 30;
  int threads = 2;
  bool progress = true;
  // The hips every variant is applied to: (label, CE, alpha).
  struct Hip {
    std::string label;
    double ce_deg, alpha_deg;
  };
  std::vector<Hip> hips{{"pure cam", 20.0, 80.0}, {"pure pincer", 40.0, 40.0}};
  // Empty: default_sensitivity_variants().
  std::vector<SensitivityVariant> variants;
  // When not empty: only the variants of these parameters (hipfai::Error for a name that has none).
  std::vector<std::string> only_parameters;
};

// The parameters and published ranges of docs/hip-sensitivity.md (sources in the notes).
std::vector<SensitivityVariant> default_sensitivity_variants();

struct SensitivityRow {
  std::string field;          // "(defaults)" for the reference row
  double value = 0.0;
  bool is_default = false;    // the value equals the shipped default
  std::string note;
  std::string hip;            // label
  double ce_deg = 0.0, alpha_deg = 0.0;
  double first_contact_deg = 0.0;
  double max_curvilinear_mm = 0.0, max_radial_mm = 0.0;
  double measured_ce_deg = 0.0, measured_alpha_deg = 0.0;
  std::string error;          // non-empty when this variant could not be built
};

struct SensitivityResult {
  double motion_angle_deg = 0.0;
  double edge_mm = 0.0;
  std::vector<SensitivityRow> rows;  // reference rows first, then variant x hip
  double seconds = 0.0;
};

SensitivityResult run_hip_sensitivity(const SensitivityOptions& options);

// First contact (deg, +inf if none within a turn) of `femur` turning about `axis` through `centre`
// (right-hand rule) against `labrum`, counting only parts farther than `min_radius_mm` from the
// centre on at least one side (see the header comment). With `exact_border` that part is all of
// the surface beyond the sphere (split along it), as the curvilinear depth's border samples count
// it (PenetrationOptions::sample_striking_boundary).
double first_striking_contact_deg(const geometry::TriMesh& femur, const geometry::TriMesh& labrum,
                                  const geometry::Vec3& centre, const Eigen::Vector3d& axis, double min_radius_mm,
                                  int threads, bool exact_border = false);

}  // namespace hipfai::studies
