// hipfai — a hip model: its tissues as closed surfaces, its frame, and model.json.
//
// A model directory holds one surface file per tissue and model.json:
//   { "format": "hipfai-hip-model", "version": 1, "units": "mm, deg",
//     "ce_deg", "alpha_deg"            requested clinical angles (generated hips),
//     "hjc_mm"                         [x, y, z] hip joint centre,
//     "flexion_axis", "adduction_axis", "internal_rotation_axis", "neck_axis", "superior",
//     "lateral", "acetabular_axis"     unit vectors (hip frame, geometry/hip_frame.h),
//     "edge_mm"                        target surface edge length,
//     "parameters"                     every HipParameters field,
//     "tissues"                        name -> file name relative to the directory,
//     "counts"                         name -> {"vertices", "triangles"} }
// Tissue names of generated hips: femur_bone, femoral_cartilage, acetabular_bone,
// acetabular_cartilage, labrum (kHipTissueNames).
#pragma once

#include "geometry/hip_frame.h"
#include "geometry/hip_parameters.h"
#include "geometry/tri_mesh.h"

#include <array>
#include <filesystem>
#include <map>
#include <set>
#include <string>

namespace hipfai::geometry {

inline constexpr std::array<const char*, 5> kHipTissueNames{
    "femur_bone", "femoral_cartilage", "acetabular_bone", "acetabular_cartilage", "labrum"};

struct HipModel {
  HipParameters parameters;
  Vec3 hjc_mm = Vec3::Zero();
  HipFrameAxes axes;
  Vec3 neck_axis = Vec3::UnitX();       // from the HJC towards the neck
  Vec3 superior = Vec3::UnitZ();
  Vec3 lateral = Vec3::UnitX();
  Vec3 acetabular_axis = Vec3::UnitX();  // out of the socket opening
  std::map<std::string, TriMesh> tissues;

  // The tissue named `name`; throws hipfai::Error when the model has none.
  const TriMesh& tissue(const std::string& name) const;
};

// Writes every tissue as <dir>/<name>.<format> (format: ply, stl, vtp or obj) and model.json.
// Creates `dir` if needed. Throws hipfai::Error naming the file on failure.
void write_hip_model(const HipModel& model, const std::filesystem::path& dir,
                     const std::string& format = "ply");

// Reads <dir>/model.json and the tissue files it names. Throws hipfai::Error
// "<dir>/model.json: <key>: <problem>" on a missing or malformed key (non-unit axis, wrong
// length vector, missing tissue file, vertex count differing from "counts").
// `only`: read just these tissues (an unknown name is an error); empty = all of them.
HipModel load_hip_model(const std::filesystem::path& dir, const std::set<std::string>& only = {});

}  // namespace hipfai::geometry
