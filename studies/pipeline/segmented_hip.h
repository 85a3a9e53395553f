// hipfai — a segmented hip: bones from CT/MRI in the scan's frame (a folder with hip.json, e.g.
// meshes/real-hips/LHDL_CT), read as a HipModel so that the analyses made for generated hips can
// take it where they need only what it has.
//
// hip.json: {"side": "right", "units": "mm", "hjc_mm": [x, y, z],
//            "tissues": {"femur_bone": "femur_r.ply", "pelvis_bone": "pelvis.ply"}, ...}
// The scan has no anatomical landmarks, so the hip frame is approximate (approximate_hip_frame):
// good to a few degrees for directions about the HJC, not for clinical angles.
#pragma once

#include "geometry/hip_model.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>

#include <filesystem>
#include <string>

namespace hipfai::studies {

// Columns X (lateral), Y (anterior), Z (superior) of a RIGHT hip's frame from its bones:
// Z = the femur's principal axis, turned towards the head; X = from the pelvis' centroid towards
// the head centre, made perpendicular to Z (the hip lies lateral of the pelvis' centroid);
// Y = Z x X. Throws hipfai::Error for empty meshes or a head on the femur's axis line.
Eigen::Matrix3d approximate_hip_frame(const geometry::TriMesh& femur, const geometry::TriMesh& pelvis,
                                      const geometry::Vec3& head_centre_mm);

// Reads hip.json and the meshes it names (tissue names as written there; the whole pelvis is
// "pelvis_bone", not the generated hips' "acetabular_bone"). The HJC is hip.json's; the axes are
// approximate_hip_frame's (femur_bone and pelvis_bone required). A left hip is refused (the
// frame above is a right hip's). Throws hipfai::Error naming the file on bad input.
geometry::HipModel load_segmented_hip(const std::filesystem::path& dir);
// Same with hip.json's text given; the meshes it names are still read from `dir`.
geometry::HipModel segmented_hip_from_json(const std::string& text, const std::filesystem::path& dir);

}  // namespace hipfai::studies
