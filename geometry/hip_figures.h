// hipfai — section drawings of a hip model (SVG), with the CE and alpha constructions drawn.
//
// Frontal: the model cut by the frontal plane through the HJC (seen from anterior, lateral to the
// right for a right hip), with the vertical through the HJC and the line to the measured lateral
// rim point. Axial: the femur and acetabulum cut by the plane containing the neck axis and the
// measured cam direction, with the fitted head circle, the neck axis and the line to the point
// where the contour leaves the circle. Angles are printed as measured, not as requested.
#pragma once

#include "geometry/hip_measure.h"
#include "geometry/hip_model.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::geometry {

// Axial: the plane of Nötzli's alpha (through the neck axis, towards anterior).
// Writes <dir>/frontal.svg and <dir>/axial.svg; throws hipfai::Error naming the file on failure.
void write_hip_figures(const HipModel& model, const CeMeasurement& ce, const AlphaMeasurement& alpha,
                       const std::filesystem::path& dir);

// One column of the morphology sheet: a label and the model (its angles are measured).
struct MorphologyPanel {
  std::string label;
  const HipModel* model = nullptr;
};

// One SVG with a column per model: its frontal section (CE) above its section in Nötzli's plane
// (alpha), constructions drawn as measured. Written atomically.
void write_morphology_sheet(const std::vector<MorphologyPanel>& panels, const std::filesystem::path& path);

}  // namespace hipfai::geometry
