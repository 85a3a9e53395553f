// hipfai — the tables of the hip sensitivity study (studies/hip_sensitivity.h): sensitivity.csv for
// tools, sensitivity.md for people.
#pragma once

#include "studies/hip_sensitivity.h"

#include <string>

namespace hipfai::studies {

// Writes <dir>/sensitivity.csv and <dir>/sensitivity.md (atomically, each).
void write_sensitivity_report(const SensitivityResult& result, const std::string& dir);

}  // namespace hipfai::studies
