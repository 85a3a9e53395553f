// hipfai — the files of `study hjc` (studies/hjc_study.h) from its result. Generated subjects:
// report.md (centre errors; differences to dref and to the true centre, thesis Eq. 13-15; the
// effect of a known centre error; the sensitivity ranking), steps.csv, results.h5 and the Fig. 67-71
// analogues (fig67_radial.svg, fig67_curvilinear.svg, fig68-71.svg). Bones-only mode: bones.md,
// bones.csv and bones.h5 (centres, fit residuals, range of motion per method and rotation).
#pragma once

#include "studies/hjc_study.h"

#include <filesystem>

namespace hipfai::studies {

// Returns the path of the report (report.md, or bones.md in bones-only mode).
std::filesystem::path write_hjc_study_report(const HjcStudyResult& result, const std::filesystem::path& dir);

}  // namespace hipfai::studies
