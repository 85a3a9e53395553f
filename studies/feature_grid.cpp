// hipfai — the feature grid's text form (see feature_grid.h), kept apart from the feature
// extraction: model files store it.
#include "studies/feature_grid.h"

#include "core/csv.h"
#include "core/error.h"

#include <limits>
#include <sstream>
#include <string>

namespace hipfai::studies {

static_assert(4 * literature::kEstimatorGridPolarSteps * literature::kEstimatorGridAzimuthSteps ==
                  literature::kEstimatorFeatureCount,
              "the default grid gives the thesis' f = 1944 features over 4 tissues");

std::string FeatureGrid::describe() const {
  std::ostringstream out;
  out << polar_steps << 'x' << azimuth_steps << ' ';
  for (std::size_t t = 0; t < tissues.size(); ++t) out << (t ? "," : "") << tissues[t];
  return out.str();
}

FeatureGrid parse_feature_grid(const std::string& text) {
  FeatureGrid grid;
  const auto x = text.find('x');
  const auto space = text.find(' ');
  if (x == std::string::npos || space == std::string::npos || x > space) {
    throw_error("feature grid '", text, "': expected '<polar>x<azimuth> <tissue>,<tissue>...'");
  }
  try {
    grid.polar_steps = std::stoi(text.substr(0, x));
    grid.azimuth_steps = std::stoi(text.substr(x + 1, space - x - 1));
  } catch (const std::exception&) {
    throw_error("feature grid '", text, "': bad step counts");
  }
  grid.tissues = split_csv_line(text.substr(space + 1));
  if (grid.polar_steps < 1 || grid.azimuth_steps < 1 || grid.tissues.empty()) {
    throw_error("feature grid '", text, "': empty grid");
  }
  // FeatureGrid::num_features is an int: a grid whose count does not fit is no grid of ours.
  const double features =
      static_cast<double>(grid.tissues.size()) * grid.polar_steps * grid.azimuth_steps;
  if (features > std::numeric_limits<int>::max()) {
    throw_error("feature grid '", text, "': ", features, " features, too many");
  }
  return grid;
}

}  // namespace hipfai::studies
