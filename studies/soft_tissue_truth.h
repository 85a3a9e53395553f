// hipfai — synthesised soft tissue against known truth: each of the 25 generated hips of the study
// grid (thesis §4.3.2.2) is stripped to its two bones, its cartilage and labrum are synthesised
// from them (studies/pipeline/soft_tissue_model.h, the hip's model.json as the frame), and the thesis'
// penetration depths over standing-to-sitting (30 sub-motions; curvilinear: femur bone vs labrum,
// radial: femur bone and cartilage vs acetabular cartilage and labrum, both roles) are computed on
// the generated and on the synthesised tissues (studies/pipeline/penetration_run.h), both with the generated
// hip's contact tolerance. Per hip: the tissues' volumes and both maxima, generated vs synthesised,
// and whether each penetrates. With an FE level, also the FE of both tissue sets over the same
// motion (studies/pipeline/fe_batch.h, cached like `study validate`'s): the peaks over the motion of the
// contact pressure and of the von Mises stress per tissue, raw and ball-averaged.
//
// Started by mpirun or srun (options.spread kMpiRanks) with two ranks or more, the hips are spread
// over the ranks (studies/soft_tissue_truth_ranks.h): each worker rank compares a hip and solves its
// two FE runs alone, rank 0 gets the rows; the same rows as the one-process run.
#pragma once

#include "core/fe_choices.h"
#include "studies/pipeline/mpi_launch.h"
#include "studies/results/fe_step_record.h"

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::studies {

struct SoftTissueTruthOptions {
  double edge_mm = 2.0;           // surface edge length of the generated hips
  int sub_motions = 30;           // standing to sitting
  std::filesystem::path out_dir = "out/soft-tissue-truth";
  bool quick = false;             // two hips (CE 20 alpha 80, CE 40 alpha 40) at 3 mm, 10 sub-motions
  // (CE, alpha) of the hips, in order; empty: the 25 of the grid, or --quick's two.
  std::vector<std::pair<double, double>> hips;
  int threads = 2;
  // FE of both tissue sets at this level; none: no FE (the CLI's default is the default level in
  // a build with the FE module).
  std::optional<FeLevel> fe_level;
  std::filesystem::path cache_dir = "cache";
  std::filesystem::path program;  // the hipfai executable of the FE workers; empty: in this process
  int jobs = 2;                   // FE worker processes at once
  bool progress = true;           // progress bar / lines on stdout
  // kMpiRanks: the hips over the ranks of MPI_COMM_WORLD when there are two or more (every rank
  // calls run_soft_tissue_truth; rank 0 alone holds the results).
  UnitSpread spread = UnitSpread::kThisMachine;
};

// Peaks over the motion of one FE run (MPa), over its converged steps.
struct SoftTissueFePeaks {
  double pressure_mpa = 0.0, ball_pressure_mpa = 0.0;
  // Per tissue, indexed by FeTissue (0 for a tissue the run lacks).
  std::array<double, kFeTissues.size()> von_mises_mpa{}, ball_von_mises_mpa{};
  int steps = 0, unconverged = 0;
  double seconds = 0.0;  // the run's wall time (from its cache entry)
};

struct SoftTissueTruthRow {
  std::string hip;  // "ce20_alpha80"
  double generated_femoral_cartilage_mm3 = 0.0, synthesised_femoral_cartilage_mm3 = 0.0;
  double generated_acetabular_cartilage_mm3 = 0.0, synthesised_acetabular_cartilage_mm3 = 0.0;
  double generated_labrum_mm3 = 0.0, synthesised_labrum_mm3 = 0.0;
  double synthesised_femoral_mean_thickness_mm = 0.0, synthesised_acetabular_mean_thickness_mm = 0.0;
  double generated_curvilinear_mm = 0.0, synthesised_curvilinear_mm = 0.0;  // max over the motion
  double generated_radial_mm = 0.0, synthesised_radial_mm = 0.0;
  double synthesis_seconds = 0.0;
  std::optional<SoftTissueFePeaks> generated_fe, synthesised_fe;  // with an FE level, when solved
  std::string fe_error;  // why an FE run of this hip failed (empty: none did)
};

struct SoftTissueTruthResult {
  SoftTissueTruthOptions options;
  bool holds_results = true;  // false on the worker ranks of a spread run
  std::vector<SoftTissueTruthRow> rows;  // in the grid's order (spread: the hips that did not fail)
  // Spread over MPI ranks, the hips that failed (the others' rows are kept); otherwise a failure
  // stops the study.
  std::vector<UnitFailure> failed;
  double contact_tolerance_mm = 0.0;  // the generated hips' (applied to both runs), largest over the hips
  double seconds = 0.0;
};

SoftTissueTruthResult run_soft_tissue_truth(const SoftTissueTruthOptions& options);

}  // namespace hipfai::studies
