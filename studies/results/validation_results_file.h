// hipfai — the stored results of a validation study, read back: <dir>/steps.csv (one row per hip
// and step: CE, alpha, step, angle, the two maximum depths, then one column per FE measure) and
// <dir>/timings.csv (one row per hip). Written by studies/validation_study.h; read by the
// correlation report (studies/validation_report.h), which is why it is re-made in seconds.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

// One hip's series, as read from steps.csv.
struct ValidationHipSeries {
  double ce_deg = 0, alpha_deg = 0;
  std::vector<double> angle_deg, curvilinear_mm, radial_mm;
  std::vector<std::vector<double>> fe;  // [measure][step]; NaN where the FE step did not converge
  const std::vector<double>& depth(const std::string& kind) const;  // "curvilinear" | "radial"
};

// One row of timings.csv.
struct ValidationHipTimingRow {
  double ce_deg = 0, alpha_deg = 0, edge_mm = 0;
  int steps = 0;
  std::string fe_level;
  double generate_s = 0, penetration_tables_ms = 0, penetration_query_ms = 0, fe_s = 0, fe_step_s = 0;
  bool fe_reused = false;
  int fe_steps_failed = 0;
  double fe_dofs = 0;
};

struct ValidationData {
  std::vector<std::string> measures;  // FE measure columns of steps.csv, in order
  std::vector<ValidationHipSeries> hips;
  std::vector<ValidationHipTimingRow> timings;  // empty when timings.csv is absent
};

// Reads <dir>/steps.csv (required) and <dir>/timings.csv (optional). Throws hipfai::Error naming
// the file and line for a missing file, a missing required column, or a malformed number.
ValidationData read_validation_results(const std::filesystem::path& dir);

}  // namespace hipfai::studies
