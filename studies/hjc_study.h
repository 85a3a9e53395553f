// hipfai — the HJC sensitivity study (thesis §4.4.3-4.4.4, Figs. 67-71, Eq. 12-15), with the
// truth the thesis did not have.
//
// Subjects: generated hips (CE, alpha) whose true centre is known. Each subject's HJC is estimated
// by the five methods (geometry/hjc.h) on its articular surfaces "as segmented": perturbed by
// smooth surface noise (1.0 mm RMS), head asphericity (0.5 mm) and an uneven joint space
// (0.5 mm), the magnitudes of studies/hjc_cohort.h, one random draw per subject; the depths are
// then computed on the clean tissues rotated about each estimate, about the true centre, and about
// the true centre displaced by 1, 2 and 5 mm along +-X, +-Y, +-Z of the hip frame (the effect of a
// known centre error).
// Rotations: the six medical rotations of the hip frame (studies/pipeline/motion.h) from neutral to the AAOS
// normal range (core/literature.h), in 1 deg steps. Per step: maximum curvilinear depth (femur
// bone vs labrum, both roles) and maximum radial depth (femoral cartilage vs acetabular cartilage
// + labrum, both roles), studies/pipeline/penetration_run.h.
// Comparison (thesis Eq. 12-15): per subject and method, |depth_i - depth_dref| over every step of
// the six rotations — curvilinear in mm, radial in % of the dref depth (steps where dref's radial
// depth is 0 are left out: the percentage is undefined there); mean and SD per subject (Figs.
// 68-69); per rotation, the mean over its steps, then mean/min/max over subjects (Figs. 70-71).
// The same against the true centre.
//
// Bones-only mode (femur + pelvis given, e.g. the real CT): no soft tissue, so no depths. The five
// centres, their spread, their fit residuals, and the exact bone-to-bone range of motion
// (contact/range_finder.h) about each centre and each of the six medical directions. The CT has no
// anatomical frame: an approximate hip frame is built from the bones (Z: the femur's principal axis
// towards the head, X: from the pelvis centroid towards the head, made orthogonal to Z; Y = Z x X),
// stated in the report.
//
// The generated subjects are independent units: started under an MPI launcher
// (UnitSpread::kMpiRanks) with two ranks or more, they are spread over the ranks
// (studies/hjc_ranks.h, docs/cluster.md) with the same results, and rank 0 writes the report. The
// bones-only mode (one hip) runs on rank 0.
#pragma once

#include "core/progress.h"
#include "geometry/hjc.h"
#include "studies/pipeline/mpi_launch.h"

#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::studies {

struct HjcStudyOptions {
  std::filesystem::path out_dir = "out/hjc";
  std::filesystem::path femur, pelvis;  // bones-only mode when both are set
  // (CE, alpha): ten subjects like the thesis' ten MRI subjects (§4.4.2.1), a Latin-square-like
  // design over the study grid: each CE of 0-40 and each alpha of 40-80 twice, no (CE, alpha) twice.
  std::vector<std::pair<double, double>> subjects{{20.0, 40.0}, {10.0, 60.0}, {30.0, 70.0}, {40.0, 80.0}, {0.0, 50.0},
                                                  {0.0, 70.0},  {10.0, 80.0}, {20.0, 50.0}, {30.0, 40.0}, {40.0, 60.0}};
  double edge_mm = 3.0;
  double step_deg = 1.0;
  std::vector<double> centre_offsets_mm{1.0, 2.0, 5.0};
  int threads = 2;
  bool progress = true;
  // kMpiRanks: the subjects over the ranks of MPI_COMM_WORLD when there are two or more (every rank
  // calls run_hjc_study with the same options); with one rank, as kThisMachine.
  UnitSpread spread = UnitSpread::kThisMachine;
};

// The segmentation perturbation of every subject's articular surfaces (see above).
inline constexpr double kHjcSegmentationNoiseMm = 1.0;
inline constexpr double kHjcSegmentationAsphericityMm = 0.5;
inline constexpr double kHjcSegmentationUnevenGapMm = 0.5;

// Test-sized study: two generated subjects (CE 20 / alpha 40, CE 30 / alpha 70) at 3 mm, 5 deg
// steps, one centre offset (2 mm); the other fields kept from `base`.
HjcStudyOptions quick_hjc_study_options(HjcStudyOptions base);

// Maximum depth per step of one rotation about one centre.
struct HjcRotationDepths {
  std::vector<double> angle_deg, curvilinear_mm, radial_mm;
};

struct HjcSubjectResult {
  std::string id;
  Eigen::Vector3d true_centre_mm = Eigen::Vector3d::Zero();
  std::map<std::string, Eigen::Vector3d> centres_mm;     // method or "truth" or "offset +X 2mm"
  // centre label -> rotation name -> depths
  std::map<std::string, std::map<std::string, HjcRotationDepths>> depths;
};

struct HjcRomRow {
  std::string method, rotation;
  double rom_deg = 0.0;
};

// Bones-only mode, one femur ("whole femur", or "head removed": only neck and trochanter can meet
// the pelvis): per method and rotation the range of motion and where its first contact lies ("h"
// within the head radius + 4 mm of the centre, "r" farther out, "-" none).
struct HjcBonesVariant {
  std::string femur;
  std::map<std::string, std::map<std::string, double>> rom_deg;     // method -> rotation -> deg
  std::map<std::string, std::map<std::string, std::string>> site;  // method -> rotation -> h/r/-
};

struct HjcBonesResult {
  geometry::HjcResult hjc;
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();  // approximate hip frame, columns X, Y, Z
  std::vector<HjcBonesVariant> variants;                // whole femur, head removed
};

struct HjcStudyResult {
  // False on the ranks other than 0 of a study spread over MPI ranks: they wrote nothing and the
  // fields below are empty.
  bool holds_results = true;
  // Spread over MPI ranks, the subjects that failed (the others are kept); otherwise a failure
  // throws.
  std::vector<UnitFailure> failed;
  HjcStudyOptions options;                        // as run
  std::vector<HjcSubjectResult> subjects;
  std::vector<HjcRomRow> rom;                     // bones-only mode, head removed
  HjcBonesResult bones;                           // bones-only mode
  std::filesystem::path report_path;
  double seconds = 0.0;
};


// The six rotations in the thesis' Eq. 12 order (FL, EX, IR, ER, AD, AB) and their amplitudes.
const std::vector<std::pair<std::string, double>>& hjc_study_rotations();

// The six directions of the centre offsets in the hip frame (+X, -X, +Y, -Y, +Z, -Z), and the
// centre label of the true centre displaced by offset_mm along one: "truth +X 2mm".
const std::array<std::pair<const char*, Eigen::Vector3d>, 6>& hjc_offset_directions();
std::string hjc_offset_label(const char* direction, double offset_mm);

// One generated subject, options.subjects[subject] (the study's unit): its centres and the depths
// about each; `progress` advances once per centre and rotation.
HjcSubjectResult compute_hjc_subject(const HjcStudyOptions& options, std::size_t subject, ProgressBar& progress);

// The subjects' centres and depths, or in bones-only mode the centres and ranges of motion.
HjcStudyResult compute_hjc_study(const HjcStudyOptions& options);

// Computes, then writes the report (studies/hjc_study_report.h) into options.out_dir.
HjcStudyResult run_hjc_study(const HjcStudyOptions& options);

}  // namespace hipfai::studies
