// hipfai — the HJC estimators against a known truth: generated hips, whose centre is
// known exactly, perturbed the way real segmentations are, and each method's centre error in mm.
// The table thesis §4.4 could not make (it had no ground truth and compared methods with dref).
//
// Truth: the centre of the generated hip's articular spheres (HipModel::hjc_mm), about which the
// femur's articular surface is built and rotates. Two surface sets are fitted:
//   articular  femoral cartilage (head) and acetabular cartilage (lunate), the surfaces an MRI
//              segmentation with cartilage gives;
//   bone       femur bone and acetabular bone, what a CT gives. The generator's bony head is the
//              inner face of a cartilage lens that thins towards its edge (hip_generator.h), a
//              sphere shifted along the neck: fits to it are biased by construction, as the
//              subchondral head of a hip with such cartilage would be.
// Perturbations (each replicate draws its own random field or direction, fixed seeds):
//   clean                     the generated meshes (2 mm edges);
//   noise S mm                smooth random displacement along the normals, RMS S (0.5, 1.0,
//                             1.5 mm: up to the 1.5 mm bone segmentation accuracy of thesis
//                             §4.4.2.1.2), correlation length 3 mm (value noise on a 3 mm lattice),
//                             on both surfaces independently;
//   asphericity E mm          the head stretched into an ellipsoid with semi-axes R + E, R, R - E
//                             (random orientation) about the true centre (0.5, 1.0 mm);
//   uneven joint space A mm   the socket pushed out radially by A (1 + u.e) / 2, e random (0.5,
//                             1.0 mm: a gap varying by A across the socket);
//   cam                       the same hip with alpha 80 deg (a cam bump on the head-neck junction);
//   partial lunate            the socket cut by a random plane through the centre containing the
//                             acetabular axis: half of the lunate surface is missing;
//   coarse / fine mesh        3.5 mm / 1.0 mm edges instead of 2 mm.
// The perturbation magnitudes other than the noise are assumptions of this study, named here.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/hip_model.h"
#include "geometry/tri_mesh.h"

namespace hipfai::studies {

// Perturbs a generated hip's head and socket surfaces the way the cohort does (same fields and
// magnitudes' meaning): smooth noise of RMS noise_mm on both, an ellipsoidal head (semi-axes
// R +- asphericity_mm), a socket pushed out by uneven_gap_mm (1 + u.e) / 2. Zero skips a step.
void perturb_like_segmentation(geometry::TriMesh& head_surface, geometry::TriMesh& socket_surface,
                               const geometry::HipModel& model, double noise_mm, double asphericity_mm,
                               double uneven_gap_mm, unsigned seed);

struct HjcCohortOptions {
  std::filesystem::path out_dir = "out/hjc-cohort";
  std::vector<double> ce_deg{10.0, 20.0, 30.0};  // base hips, alpha 40 (no cam)
  double edge_mm = 2.0;
  double coarse_edge_mm = 3.5;
  double fine_edge_mm = 1.0;
  int replicates = 5;
  bool include_fine = true;
  bool progress = true;
};

// Test-sized cohort: one hip (CE 20) at 3 mm, 2 replicates, no fine mesh; out_dir and progress
// kept from `base`.
HjcCohortOptions quick_hjc_cohort_options(HjcCohortOptions base);

struct HjcCohortRow {
  std::string hip, surface, perturbation, method;
  int replicate = 0;
  bool ok = false;
  double error_mm = 0.0;
  Eigen::Vector3d error_vector_mm = Eigen::Vector3d::Zero();  // estimate - truth, hip frame
  double rms_mm = 0.0, max_mm = 0.0;
  double residual_motion_rms_mm = 0.0;   // functional methods; NaN for the fits
};

struct HjcCohortSummary {
  std::string surface, perturbation, method;
  int count = 0, failed = 0;
  double mean_mm = 0.0, sd_mm = 0.0, max_mm = 0.0;
};

struct HjcCohortResult {
  HjcCohortOptions options;  // as run
  std::vector<HjcCohortRow> rows;
  // Per (surface, perturbation, method) with at least one estimate, in the order met; a group
  // whose every estimate failed has rows only.
  std::vector<HjcCohortSummary> summary;
  std::vector<HjcCohortSummary> overall;  // per method over every perturbation and surface
  std::filesystem::path report_path;
  double seconds = 0.0;
};

HjcCohortResult compute_hjc_cohort(const HjcCohortOptions& options);

// Computes, then writes the report (studies/hjc_cohort_report.h) into options.out_dir.
HjcCohortResult run_hjc_cohort(const HjcCohortOptions& options);

}  // namespace hipfai::studies
