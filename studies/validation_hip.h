// hipfai — one hip of the FAI validation study (studies/validation_study.h): its units and what
// the study keeps of them. The penetration unit makes the hip (generated, cached) and its
// per-step maximum depths; the FE unit is its run in the FE cache, read back per step. Both run
// where the study puts them: this process, its FE worker processes, or a worker rank of an MPI job
// (studies/validation_ranks.h).
#pragma once

#include "studies/pipeline/motion.h"
#include "studies/validation_study.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/pipeline/fe_batch.h"
#endif

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

// What the study keeps of a hip: enough for its rows of steps.csv and timings.csv.
struct ValidationHip {
  double ce = 0, alpha = 0;
  std::string id;                          // parametric_hip_id
  std::filesystem::path dir;               // the generated hip's folder in the cache
  std::vector<double> curvilinear_max_mm;  // per step: the larger of both directions' maxima
  std::vector<double> radial_max_mm;
  ValidationHipTiming timing;
  std::vector<std::vector<double>> fe;     // [measure][step], NaN where the FE step failed
};

// The penetration unit: makes (or takes from the cache) the CE / alpha hip and computes both
// depths over the motion with `threads` threads (the results do not depend on them). The hip of
// thesis Figs. 60-61 also writes its end pose into options.out_dir / "fig61".
ValidationHip run_validation_penetration(double ce, double alpha, const Motion& motion,
                                         const ValidationOptions& options, int threads);

#ifdef HIPFAI_WITH_FEM
// The FE unit of a hip as an FE batch job (standing-to-sitting of the options, the end pose's
// fields kept).
FeBatchJob validation_fe_job(const ValidationHip& hip, const ValidationOptions& options);

// Reads a hip's FE entry back into hip.fe and its timing; the figure's hip gets the FE end pose
// copied into options.out_dir / "fig61". Throws hipfai::Error naming the table when it does not
// fit the motion.
void read_validation_fe_entry(ValidationHip& hip, const FeBatchEntry& entry, const Motion& motion,
                              const ValidationOptions& options);
#endif

}  // namespace hipfai::studies
