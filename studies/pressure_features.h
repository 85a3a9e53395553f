// hipfai — the geometric features of a hip for the contact-pressure estimator (thesis §4.5.2.1,
// Eq. 17): each tissue sampled on a fixed spherical grid about the hip joint centre.
//
// Grid: `polar_steps` x `azimuth_steps` directions at the cell centres of an equal-angle grid in
// the HIP FRAME of the model (geometry/hip_frame.h): polar angle theta_i = (i + 1/2) 180 / n_polar
// deg from +Z (superior), azimuth phi_j = (j + 1/2) 360 / n_azimuth deg from +X (lateral) towards
// +Y (anterior). The same directions for every hip whatever its mesh resolution (the point of the
// thesis' sampling: raw vertices cannot be compared across resolutions). Features are ordered
// tissue-major, then polar, then azimuth.
//
// R (the feature): the distance from the HJC to the FARTHEST crossing of the ray with the tissue's
// closed surface, i.e. the tissue's outermost boundary in that direction: the articulating surface
// of the femoral cartilage and the bone's outline (head, cam, neck) for the femur, the bone-side
// boundary of the acetabular cartilage and labrum (their articulating surfaces lie a constant
// thickness inside it, so either carries the same shape, and the outer one does not depend on
// the cartilage's inner rim triangles). A MISS (no tissue in that direction: outside the
// horseshoe, beyond the rim) gives R = 0: the tissue's extent along the ray is zero. The
// hit/miss pattern of the acetabular tissues is what encodes coverage (CE); 0 keeps the matrix
// finite for the PCA and its jump (0 vs ~27 mm) weighs coverage strongly after normalisation.
//
// The crossings are found with contact/'s radial machinery: a radial table of the tissue about
// the HJC (contact/radial_table.h, spherical mapping) gives the candidate triangles of each
// direction's cell, and the watertight ray test of contact/ray_triangle.h decides the crossings.
#pragma once

#include "geometry/hip_model.h"
#include "studies/feature_grid.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace hipfai::studies {

struct HipFeatures {
  Eigen::VectorXd values;   // f features, mm
  int misses = 0;           // directions without any crossing (R = 0), over all tissues
  double extraction_ms = 0; // tables + rays, not the mesh loading
};

// Throws hipfai::Error naming the hip when a grid tissue is missing or the grid is degenerate.
HipFeatures extract_hip_features(const geometry::HipModel& model, const FeatureGrid& grid);

// Content hash of what the features depend on: the grid tissues' vertices and triangles, the HJC
// and the frame axes (16 hex digits, core/hash.h). Identifies a training hip in a model file.
std::string hip_content_hash(const geometry::HipModel& model, const FeatureGrid& grid);

}  // namespace hipfai::studies
