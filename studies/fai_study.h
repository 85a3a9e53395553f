// hipfai — the FAI penetration study (thesis §4.3): 25 parametric hips (CE 0-40 deg x alpha
// 40-80 deg), standing to sitting, curvilinear and radial penetration depths per step, the
// pathology map and Table 10, with timings and an accuracy-vs-resolution table.
//
// Output folder:
//   results.h5        /models/<id>/...  per-step maxima, timings, per-vertex maxima;
//                     /summary/...      one value per model (layout: docs/results-layout.md)
//   summary.csv       one row per model: angles, maxima, normalised difference, pathology, bands
//   steps.csv         one row per model and step
//   resolution.csv    the study at several surface resolutions: maxima and run times
//   report.md         tables and the figures (SVG) below
//   fig60_*.svg, fig62_*.svg, fig63_*.svg, hip_*.svg, *.vtp
//
// The study is two steps: compute_fai_study() computes a FaiStudyResult (writing nothing but the
// per-step VTP files asked for, which are streamed as the motion runs), and
// write_fai_study_outputs() (studies/fai_report.h) writes the files above from it. run_fai_study()
// does both.
//
// The hips are independent units (studies/fai_unit.h). Started under an MPI launcher
// (UnitSpread::kMpiRanks) with two ranks or more, they are spread over the ranks
// (studies/fai_ranks.h, docs/cluster.md) with the same results, and rank 0 writes the files.
#pragma once

#include "contact/radial_mapping.h"
#include "geometry/hip_frame.h"
#include "geometry/hip_parameters.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/motion.h"
#include "studies/pipeline/mpi_launch.h"
#include "studies/pipeline/penetration_run.h"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::studies {

struct FaiStudyOptions {
  std::filesystem::path out_dir = "out/fai";
  std::filesystem::path cache_dir = "cache";
  std::vector<double> ce_deg = study_ce_deg();  // the thesis' grid (core/literature.h)
  std::vector<double> alpha_deg = study_alpha_deg();
  double edge_mm = 2.0;                        // surface resolution of the main run
  int sub_motions = 30;
  // How the end pose's angles compose (geometry/hip_frame.h); the default is the joint coordinate
  // system, kFixedAxes the literal reading compared in docs/hip-geometry.md.
  geometry::PoseSequence pose_sequence = geometry::PoseSequence::kJointCoordinateSystem;
  // Where the femur's neutral is (geometry/hip_frame.h): as built (shaft along Z) or at the ISB
  // neutral, the mechanical axis along Z (the femur adducted by kAnatomicMechanicalAngleDeg first).
  geometry::FemoralNeutral femoral_neutral = geometry::FemoralNeutral::kShaftAxis;
  // Generator parameters shared by every hip of the grid (CE, alpha and the edge are the grid's);
  // nullopt: the defaults of geometry/hip_parameters.h. The report lists the fields that differ.
  std::optional<geometry::HipParameters> base_parameters = std::nullopt;
  std::vector<double> resolution_edges_mm;     // extra runs for the accuracy-vs-time table
  contact::RadialMapping mapping = contact::RadialMapping::kCube;
  contact::RadialCrossingRule radial_rule = contact::RadialCrossingRule::kUnion;  // penetration_run.h
  std::int64_t table_size = 20000;
  int threads = 2;
  // Contact tolerance (mm) of the penetration method; negative: max(sagitta bound, sphericity)
  // of each hip's mesh (studies/pipeline/penetration_run.h).
  double contact_tolerance_mm = -1.0;
  // Curvilinear depth sampled also on the border of the striking region (penetration_run.h).
  bool sample_striking_boundary = false;
  bool progress = true;
  // Per-step VTP files (each tissue with that step's depth fields) for these models and steps
  // (1-based; 0 = the last step): <out>/vtp/<model>_<tissue>_stepNNN.vtp.
  std::vector<std::string> vtp_models{"ce40_alpha80", "ce20_alpha80", "ce40_alpha40"};
  std::vector<int> vtp_steps{0};
  // kMpiRanks: the units over the ranks of MPI_COMM_WORLD when there are two or more (every rank
  // calls run_fai_study with the same options); with one rank, as kThisMachine.
  UnitSpread spread = UnitSpread::kThisMachine;
};

// Thesis Table 10 / Fig. 63 classification from the angles: acetabulum dysplastic (CE < 20),
// normal, or over-covered (CE >= 40, pincer); femur normal (alpha <= 50, Nötzli et al. 2002) or
// cam. Returns "normal", "pincer", "cam", "combined cam-pincer", "dysplasia" or
// "combined dysplasia-impingement".
std::string pathology_of(double ce_deg, double alpha_deg);

// Bands of thesis Table 10 ("very low" ... "very high").
std::string curvilinear_band(double depth_mm);
std::string radial_band(double depth_mm);
std::string difference_band(double normalised_difference);

struct FaiModelSummary {
  double ce_deg = 0, alpha_deg = 0;
  double max_curvilinear_mm = 0, max_radial_mm = 0;
  double normalised_difference = 0;  // curvilinear/max(curvilinear) - radial/max(radial)
  double generate_s = 0, penetration_ms = 0;
  double first_contact_deg = 0;  // along the motion's axis, femur bone meets labrum (inf: never)
  std::string pathology;
};

// One model of the grid: its summary, its per-step penetration and the hip it ran on.
struct FaiModelRun {
  FaiModelSummary summary;
  PenetrationRun run;
  LoadedHip hip;
  double seconds = 0;  // wall time of the whole run (hip, penetration, first contact)
};

// The archetypes of thesis Table 10 at several surface resolutions (accuracy vs time).
struct FaiResolutionRow {
  double edge_mm = 0;
  double seconds = 0;
  double penetration_ms_per_step = 0;
  std::map<std::string, std::pair<double, double>> maxima;  // archetype -> (curvilinear, radial) mm
  std::size_t femur_vertices = 0;
};

struct FaiStudyResult {
  // False on the ranks other than 0 of a study spread over MPI ranks: they wrote nothing and the
  // fields below are empty.
  bool holds_results = true;
  // Spread over MPI ranks, the units that failed (the others' results are kept); otherwise a
  // failure throws.
  std::vector<UnitFailure> failed;
  std::vector<FaiModelSummary> models;       // grid order (CE outer, alpha inner)
  std::map<std::string, FaiModelRun> runs;   // parametric_hip_id -> run
  Motion motion;
  std::vector<FaiResolutionRow> resolution;  // coarsest first; the main edge among them
  double total_seconds = 0;                  // computing (not writing)
  std::string report_path;                   // set by write_fai_study_outputs
};

// Name -> (CE, alpha) of the archetypes of thesis Table 10: normal, pincer, cam, combined
// cam-pincer, dysplasia, combined dysplasia-impingement.
const std::vector<std::pair<std::string, std::pair<double, double>>>& fai_archetypes();

// The model at these angles, or nullptr.
const FaiModelSummary* find_fai_model(const std::vector<FaiModelSummary>& models, double ce_deg, double alpha_deg);

FaiStudyResult compute_fai_study(const FaiStudyOptions& options);
FaiStudyResult run_fai_study(const FaiStudyOptions& options);

}  // namespace hipfai::studies
