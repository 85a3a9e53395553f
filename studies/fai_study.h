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
#pragma once

#include "contact/radial_mapping.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

struct FaiStudyOptions {
  std::filesystem::path out_dir = "out/fai";
  std::filesystem::path cache_dir = "cache";
  std::vector<double> ce_deg{0, 10, 20, 30, 40};
  std::vector<double> alpha_deg{40, 50, 60, 70, 80};
  double edge_mm = 2.0;                        // surface resolution of the main run
  int sub_motions = 30;
  std::vector<double> resolution_edges_mm;     // extra runs for the accuracy-vs-time table
  contact::RadialMapping mapping = contact::RadialMapping::kCube;
  std::int64_t table_size = 20000;
  int threads = 2;
  // Contact tolerance (mm) of the penetration method; negative: max(sagitta bound, sphericity)
  // of each hip's mesh (studies/penetration_run.h).
  double contact_tolerance_mm = -1.0;
  bool progress = true;
  // Per-step VTP files (each tissue with that step's depth fields) for these models and steps
  // (1-based; 0 = the last step): <out>/vtp/<model>_<tissue>_stepNNN.vtp.
  std::vector<std::string> vtp_models{"ce40_alpha80", "ce20_alpha80", "ce40_alpha40"};
  std::vector<int> vtp_steps{0};
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

struct FaiStudyResult {
  std::vector<FaiModelSummary> models;
  double total_seconds = 0;
  std::string report_path;
};

FaiStudyResult run_fai_study(const FaiStudyOptions& options);

}  // namespace hipfai::studies
