// hipfai — the contact-pressure estimator of thesis §4.5 as a pipeline: FE results and hip folders
// in, a model file out (train), a hip in and per-step estimates out (predict), and the
// leave-one-out validation of Tables 12-13 and Figs. 72-74 with baselines (validate: computed in
// studies/estimator_validate.h, written by studies/estimator_validate_report.h). The maths are in stats/ (pca, pca_nn_estimator, knn_regression,
// ridge_regression, pressure_estimator); the features in studies/pressure_features.h.
//
// INPUTS ACCEPTED
//   --fe   a `hipfai study validate` output folder (its steps.csv: one row per hip and step,
//          FE measures in columns ending in _mpa, empty where a step failed; its timings.csv, if
//          present, gives each hip's edge length), or a steps.csv file itself. Every hip must
//          have the same steps at the same angles (one motion). scripts/fem-sweep folders are not
//          read (run `hipfai study validate` instead; it caches the same FE runs).
//   --hips a folder of hip model folders (each with model.json, e.g. `hipfai generate --grid`
//          or the validation cache's hip-ce*_alpha*-<hash> folders; *.partial is skipped), or a
//          single hip folder. A row of the FE table is matched to the folder whose model.json
//          records the same CE and alpha (and the same edge_mm when timings.csv gives one);
//          none or several matches is an error naming them.
#pragma once

#include "core/literature.h"
#include "stats/pressure_estimator.h"
#include "studies/pipeline/mpi_launch.h"
#include "studies/pressure_features.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

// One hip's FE values over the motion (NaN where the step failed or is absent).
struct FeSweepHip {
  double ce_deg = 0, alpha_deg = 0;
  double edge_mm = 0;  // NaN when the sweep does not say
  std::vector<double> values;
  // The penetration method's depths at each step (mm), from the table's max_curvilinear_mm /
  // max_radial_mm columns; NaN where the table has none, empty for tables without the columns.
  std::vector<double> curvilinear_mm, radial_mm;
};

struct FeSweep {
  std::string measure;               // e.g. pressure_max_mpa
  std::vector<double> angle_deg;     // per step
  std::vector<FeSweepHip> hips;
};

// Throws hipfai::Error naming the file on a missing file or column, a malformed row, or hips
// whose steps or angles differ.
FeSweep read_fe_sweep(const std::filesystem::path& fe, const std::string& measure);

struct TrainingHip {
  std::string name;                  // "ce20_alpha40"
  double ce_deg = 0, alpha_deg = 0, edge_mm = 0;
  std::string hash;                  // hip_content_hash
  std::filesystem::path dir;
  Eigen::VectorXd features;
  std::vector<double> values;
  // FeSweepHip::curvilinear_mm / radial_mm; stored in the model file (depth_nn) when every hip
  // has both at every step.
  std::vector<double> curvilinear_mm, radial_mm;
  double load_ms = 0, feature_ms = 0;
  int misses = 0;
};

// The hips' penetration depths as the estimator takes them: hips x steps each when every hip has
// both depths at every one of the `steps`, empty otherwise (then depth_nn is unavailable).
stats::PenetrationDepths training_depths(const std::vector<TrainingHip>& hips, Eigen::Index steps);

struct EstimatorTrainOptions {
  std::vector<std::filesystem::path> fe;   // one or more sweeps (same motion)
  std::filesystem::path hips;
  std::filesystem::path base_model;        // retraining: start from this model's training hips
  // Hips added one by one, any hip model folder (a segmented hip with synthesised soft tissue,
  // `hipfai soft-tissue`): (folder, its `fem run --csv` table; the run's HDF5, --out, beside it
  // with the same name and .h5). Their penetration depths are computed over the motion.
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> fe_hips;
  std::string measure = "pressure_max_mpa";
  FeatureGrid grid;
  bool grid_given = false;                 // the user chose the grid (compared with base_model's)
  // Normalisation floor = the project's sphericity tolerance (literature::kSphericityToleranceMm):
  // features varying less than that across hips are treated as mesh noise, not z-scored up.
  stats::EstimatorSettings settings{
      .pca = {.components = literature::kEstimatorEffectiveFeatures, .scale_floor = literature::kSphericityToleranceMm}};
  bool progress = true;
};

// Everything a model file holds.
struct EstimatorModel {
  FeatureGrid grid;
  std::string measure;
  std::vector<double> angle_deg;           // the motion's steps
  std::vector<TrainingHip> hips;           // features and values (dir, times empty when read back)
  stats::TrainedEstimator estimator;
  std::string code_version;                // of the program that trained it
};

// Matches, extracts features and trains. Throws hipfai::Error (one line) on any mismatch.
EstimatorModel train_estimator_model(const EstimatorTrainOptions& options, std::vector<std::string>* notes = nullptr);

// A training hip from its model folder (features on `grid`, content hash) and its FE values and
// depths (fe.ce_deg / alpha_deg are taken from the folder's model.json).
TrainingHip training_hip_from_folder(const std::filesystem::path& dir, FeSweepHip fe, const FeatureGrid& grid);

// Fits model.estimator to model.hips with `settings` (PCA, derived members, depths when every hip
// has them). Throws hipfai::Error with fewer than 3 hips.
void fit_estimator_model(EstimatorModel& model, const stats::EstimatorSettings& settings);

// The model's HDF5 file: write_estimator_model and read_estimator_model in
// studies/estimator_model_file.h.

struct HipPrediction {
  stats::EstimateResult result;
  double load_ms = 0, feature_ms = 0, predict_ms = 0;
  int misses = 0;
  // A segmented hip (hip.json): its hip frame is approximate (studies/pipeline/segmented_hip.h).
  bool approximate_frame = false;
  // depth_nn only: the target's penetration depths over the model's motion (thesis §4.3, the
  // study's own method, studies/pipeline/penetration_run.h), 1 x steps each, and their time.
  stats::PenetrationDepths depths;
  double penetration_ms = 0;
};

// Loads the hip folder — a model folder (model.json) or a segmented hip (hip.json, bones in the
// scan's frame, studies/pipeline/segmented_hip.h) — refusing, with what is missing, one the model's
// features cannot be taken from; extracts its features on the model's grid and estimates every step.
// depth_nn also computes the hip's penetration depths over the model's motion, which must then be
// standing-to-sitting (studies/pipeline/motion.h: the motion of `hipfai study validate`, recognised by its
// angles); another motion, or a hip without the four tissues, is refused.
HipPrediction predict_hip(const EstimatorModel& model, const std::filesystem::path& hip_dir,
                          stats::EstimatorMethod method, int e_prime);

// e' for `method` chosen among the model's training hips alone, over the whole motion: the
// smallest leave-one-out error for e' = 1..components (stats::select_e_prime).
stats::EPrimeSelection choose_e_prime(const EstimatorModel& model, stats::EstimatorMethod method);

struct EstimatorValidateOptions {
  EstimatorTrainOptions train;
  std::filesystem::path out_dir = "out/estimator";
  int max_e_prime = 10;
  // --quick: when quick_program is set, the FE results are first made by
  // studies::run_validation_study (5 hips, 3 mm, 6 steps, FE coarse) into <out_dir>/fe with its
  // hips in quick_cache, and train.fe / train.hips point there.
  std::filesystem::path quick_program;
  std::filesystem::path quick_cache = "cache";
  // kMpiRanks: the --quick FE's hips and the leave-one-out folds over the ranks of MPI_COMM_WORLD
  // when there are two or more (every rank calls validate_estimator with the same options); with
  // one rank, as kThisMachine.
  UnitSpread spread = UnitSpread::kThisMachine;
};

struct EstimatorValidateSummary {
  // Mean over eligible hips of the per-hip mean |error| % at e' = max, per case (0: first half,
  // 1: whole motion) and method (index of stats::kEstimatorMethods).
  // NaN for depth_nn when the FE table has no penetration depths.
  double mean_error[2][stats::kNumEstimatorMethods] = {};
  double interior_error[2][stats::kNumEstimatorMethods] = {};        // hips off the CE/alpha grid's border (thesis §4.5.4)
  int hips[2] = {};
  int bordering[2] = {};                   // flagged hips
  // Hips the penetration method finds impinging within the case's steps (depth > 0 at a step),
  // of those whose FE table gave depths.
  int impinging[2] = {};
  // pca_nn with e' chosen on the training hips of each held-out hip (stats::select_e_prime).
  double chosen_e_prime_error[2] = {};
  double chosen_e_prime_interior_error[2] = {};
  std::filesystem::path report;
  // False on the ranks other than 0 of a validation spread over MPI ranks: they wrote nothing and
  // the fields above are empty.
  bool wrote_report = true;
};

EstimatorValidateSummary validate_estimator(const EstimatorValidateOptions& options);

}  // namespace hipfai::studies
