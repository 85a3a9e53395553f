// hipfai — the tables of the soft-tissue known-truth study (studies/soft_tissue_truth.h):
// <out_dir>/soft_tissue_truth.csv (one row per hip, the columns of SoftTissueTruthRow) and
// <out_dir>/soft_tissue_truth.md (per hip: volumes and depths generated vs synthesised; the
// penetrate / no-penetrate pattern; the depth goals), written atomically.
#pragma once

#include "studies/soft_tissue_truth.h"

#include <filesystem>

namespace hipfai::studies {

// Returns the .md path.
std::filesystem::path write_soft_tissue_truth(const SoftTissueTruthResult& result);

}  // namespace hipfai::studies
