// hipfai — the HDF5 file of a trained estimator model (studies/estimator_study.h); docs/estimator.md
// has the layout: format and version, the feature grid and settings, the motion, normalisation and
// PCA, and the training hips with their FE values (and penetration depths when known).
#pragma once

#include "studies/estimator_study.h"

#include <filesystem>

namespace hipfai::studies {

// Written atomically.
void write_estimator_model(const EstimatorModel& model, const std::filesystem::path& path);
// Throws a one-line hipfai::Error for a missing, corrupt or foreign file, or a newer format.
EstimatorModel read_estimator_model(const std::filesystem::path& path);

}  // namespace hipfai::studies
