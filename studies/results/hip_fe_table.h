// hipfai — the per-step table of an FE run (fe.csv, written by studies/pipeline/hip_fe_run.h's
// write_hip_fe_csv; columns in docs/results-layout.md, "fem run --csv"), read back once into typed
// step records (studies/results/fe_step_record.h), so that its readers (scenes, the validation study and
// its cache, the estimator's FE sweeps, the soft-tissue study) never look a column up by name.
// Free of the FE module, so the readers of stored results and the fuzzer use it without deal.II.
#pragma once

#include "studies/results/fe_step_record.h"

#include <filesystem>
#include <istream>
#include <string>
#include <vector>

namespace hipfai::studies {

// A per-step table read back. The columns the records do not hold (translations, peak positions,
// surface names, solver counts) are not read.
struct HipFeTable {
  std::vector<FeTissue> tissues;    // the tissues the run has, in the order of their columns
  std::vector<FeStepRecord> steps;  // one per row, in the table's order (step 1 first)
};

// Throws a one-line hipfai::Error naming the file when it is missing or empty, lacks a column the
// records need (naming the column), names a column twice, has a row of the wrong width or a status
// that is not a whole number. A cell of a measure that is not a number reads as NaN.
HipFeTable read_hip_fe_csv(const std::filesystem::path& file);
// The same from a stream; `source` names it in the errors.
HipFeTable parse_hip_fe_csv(std::istream& in, const std::string& source);

}  // namespace hipfai::studies
