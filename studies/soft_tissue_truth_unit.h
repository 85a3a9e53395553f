// hipfai — one hip of the soft-tissue known-truth study (studies/soft_tissue_truth.h), as a unit
// that runs the same in this process or on a worker rank of an MPI job: the generated hip written
// to <out>/hips/<hip>/generated, stripped to its bones and re-dressed into .../synthesised, both
// tissue sets' volumes and depths over the motion; and the FE runs of the two tissue sets and the
// peaks read back from their cache entries.
#pragma once

#include "studies/pipeline/motion.h"
#include "studies/soft_tissue_truth.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/pipeline/fe_entry.h"
#endif

#include <array>
#include <filesystem>
#include <utility>
#include <vector>

namespace hipfai::studies {

// The study's hips, (CE, alpha) in order: options.hips, else the 25 of the grid or --quick's two.
std::vector<std::pair<double, double>> soft_tissue_truth_grid(const SoftTissueTruthOptions& options);

// Standing to sitting in the study's sub-motions (--quick: 10).
Motion soft_tissue_truth_motion(const SoftTissueTruthOptions& options);

// One hip compared (everything of its row but the FE). Widens `tolerance_mm` to the contact
// tolerances used.
SoftTissueTruthRow compare_soft_tissue_hip(double ce, double alpha, const SoftTissueTruthOptions& options,
                                           const Motion& motion, double& tolerance_mm);

#ifdef HIPFAI_WITH_FEM
// The FE runs of a compared hip: its generated tissues, then its synthesised ones, over `motion` at
// options.fe_level (the end pose's fields kept, as `study validate` keeps them: the two studies
// share cache entries).
std::array<FeBatchJob, 2> soft_tissue_fe_jobs(const SoftTissueTruthRow& row, const SoftTissueTruthOptions& options,
                                              const Motion& motion);

// Peaks over the motion of a finished FE run (its cache entry's fe.csv and timing.txt).
SoftTissueFePeaks soft_tissue_fe_peaks(const std::filesystem::path& entry);
#endif

}  // namespace hipfai::studies
