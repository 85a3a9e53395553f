// hipfai — the per-step table of an FE run (fe.csv, written by studies/hip_fe_run.h's
// write_hip_fe_csv; columns in docs/results-layout.md, "fem run --csv"), read back. Free of the FE
// module, so the readers of stored results (the estimator's FE sweep, the validation study's
// cache) and the fuzzer use it without deal.II.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace hipfai::studies {

// A per-step table read back: column name -> one value per step (NaN where a cell is not a
// number, e.g. the surface-name columns). Throws hipfai::Error naming the file when it is
// missing, empty or has rows of the wrong width.
struct HipFeTable {
  std::vector<std::string> columns;
  std::map<std::string, std::vector<double>> values;
  std::size_t rows = 0;
  const std::vector<double>& column(const std::string& name) const;  // throws when missing
};
HipFeTable read_hip_fe_csv(const std::filesystem::path& file);

}  // namespace hipfai::studies
