// hipfai — the spherical grid on which the estimator samples a hip's tissues
// (studies/pressure_features.h has the sampling), and its text form stored in model files.
#pragma once

#include "core/literature.h"

#include <string>
#include <vector>

namespace hipfai::studies {

struct FeatureGrid {
  // Thesis: f = 1944 features from the femur bone, cartilage and acetabular soft tissues; the grid
  // itself is not given. 4 tissues x 18 polar x 27 azimuth = 1944 (literature.h).
  int polar_steps = literature::kEstimatorGridPolarSteps;
  int azimuth_steps = literature::kEstimatorGridAzimuthSteps;
  std::vector<std::string> tissues{"femur_bone", "femoral_cartilage", "acetabular_cartilage", "labrum"};

  int num_features() const { return static_cast<int>(tissues.size()) * polar_steps * azimuth_steps; }
  // "18x27 femur_bone,femoral_cartilage,acetabular_cartilage,labrum" (stored in model files and
  // compared on retraining).
  std::string describe() const;
};

// Parses describe()'s text back; throws hipfai::Error on a malformed one.
FeatureGrid parse_feature_grid(const std::string& text);

}  // namespace hipfai::studies
