// hipfai — the tables of the assessment's known-truth study (studies/assessment_truth.h):
// <out_dir>/known_truth.csv (one row per hip, the columns of AssessmentTruthRow) and
// <out_dir>/known_truth.md (the largest differences against their goals), written atomically.
#pragma once

#include "studies/assessment_truth.h"

#include <filesystem>

namespace hipfai::studies {

// Returns the .md path.
std::filesystem::path write_assessment_truth(const AssessmentTruthResult& result);

}  // namespace hipfai::studies
