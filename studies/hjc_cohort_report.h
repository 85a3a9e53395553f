// hipfai — the files of `study hjc-cohort` (studies/hjc_cohort.h) from its result: cohort.csv (one
// row per estimate), cohort_summary.csv (per surface, perturbation and method), cohort.md (per
// surface a table of perturbations by methods with the best method and its margin; the overall
// error per method) and cohort.h5.
#pragma once

#include "studies/hjc_cohort.h"

#include <filesystem>

namespace hipfai::studies {

// Returns the path of cohort.md.
std::filesystem::path write_hjc_cohort_report(const HjcCohortResult& result, const std::filesystem::path& dir);

}  // namespace hipfai::studies
