// hipfai — the files of `study fai` (studies/fai_study.h) from its result: results.h5, summary.csv,
// steps.csv, resolution.csv, the figures (fig60_*.svg, fig62_*.svg, fig63_*.svg, hip_*.svg and the
// shown hip's *.vtp) and report.md.
#pragma once

#include "studies/fai_study.h"

namespace hipfai::studies {

// Writes into options.out_dir and sets result.report_path.
void write_fai_study_outputs(FaiStudyResult& result, const FaiStudyOptions& options);

}  // namespace hipfai::studies
