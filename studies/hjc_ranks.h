// hipfai — the HJC sensitivity study's generated subjects (studies/hjc_study.h) spread over the
// ranks of an MPI job (studies/pipeline/spread_units.h): a worker rank computes a subject alone
// (its centres and the depths about each) and sends it back; rank 0 keeps the subjects in the
// order of the options. A subject that fails is reported with its name; the others are kept.
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "studies/hjc_study.h"

#include <vector>

namespace hipfai::studies {

struct HjcRankRun {
  bool holds_results = false;             // this is rank 0: it has the subjects
  std::vector<HjcSubjectResult> subjects;  // rank 0: those that succeeded, in the options' order
  std::vector<UnitFailure> failed;         // rank 0: the others
};

// Collective over MPI_COMM_WORLD (at least 2 ranks).
HjcRankRun run_hjc_subjects_over_ranks(const HjcStudyOptions& options);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
