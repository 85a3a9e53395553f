// hipfai — the report of `hipfai fem levels` (studies/fem_levels_study.h) from its result:
// levels.csv, levels_accuracy.svg, levels_time.svg and levels.md, the finest level run being the
// reference of every difference.
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "studies/fem_levels_study.h"

namespace hipfai::studies {

// levels.csv, the two SVG plots and levels.md in options.out_dir (nothing on ranks other than 0).
void write_fem_levels_report(const FemLevelsResult& result, const FemLevelsOptions& options);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
