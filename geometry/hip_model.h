// hipfai — a hip model: its tissues as closed surfaces, its frame, and model.json.
//
// A model directory holds one surface file per tissue and model.json:
//   { "format": "hipfai-hip-model", "version": 1, "units": "mm, deg",
//     "ce_deg", "alpha_deg"            requested clinical angles (generated hips),
//     "hjc_mm"                         [x, y, z] hip joint centre,
//     "flexion_axis", "adduction_axis", "internal_rotation_axis", "neck_axis", "superior",
//     "lateral", "acetabular_axis"     unit vectors (hip frame, geometry/hip_frame.h),
//     "socket_opening_deg"             rim cone angle from acetabular_axis (90: hemisphere),
//     "measured"                       {"ce_deg", "alpha_notzli_deg", "alpha_max_deg",
//                                       "alpha_max_clock", "alpha_profile": [{"clock",
//                                       "clock_deg", "alpha_deg"}, ...]} (generated hips),
//     "soft_tissue"                    "generated" or "synthesised" (SoftTissueSource; absent:
//                                       generated),
//     "edge_mm"                        target surface edge length,
//     "parameters"                     every HipParameters field,
//     "tissues"                        name -> file name relative to the directory,
//     "counts"                         name -> {"vertices", "triangles"},
//     "volume"                         (when a volume mesh was written) {"file", "format", "edge_mm",
//                                       "layers", "min_thickness_mm", "hexahedra", "nodes",
//                                       "boundary_quadrangles", "min_scaled_jacobian"} }
// Tissue names of generated hips: femur_bone, femoral_cartilage, acetabular_bone,
// acetabular_cartilage, labrum (kHipTissueNames).
#pragma once

#include "geometry/hip_frame.h"
#include "geometry/hip_parameters.h"
#include "geometry/tri_mesh.h"

#include <array>
#include <limits>
#include <utility>
#include <vector>
#include <filesystem>
#include <map>
#include <set>
#include <string>

namespace hipfai::geometry {

struct HipVolumeMesh;  // geometry/hip_volume_mesh.h

inline constexpr std::array<const char*, 5> kHipTissueNames{
    "femur_bone", "femoral_cartilage", "acetabular_bone", "acetabular_cartilage", "labrum"};

// Where a model's cartilage and labrum come from: the parametric generator (exact spheres and
// cones about the HJC), or synthesised on segmented bones (anatomy/soft_tissue.h: radial layers
// over a bone's own triangles, a labrum swept along a measured rim). The volume mesher treats
// their boundaries differently (geometry/hip_volume_mesh.h). model.json "soft_tissue": "generated"
// (the default when absent) or "synthesised".
enum class SoftTissueSource { kGenerated, kSynthesised };
const char* to_string(SoftTissueSource source);

struct HipModel {
  HipParameters parameters;
  SoftTissueSource soft_tissue = SoftTissueSource::kGenerated;
  Vec3 hjc_mm = Vec3::Zero();
  HipFrameAxes axes;
  Vec3 neck_axis = Vec3::UnitX();       // from the HJC towards the neck
  Vec3 superior = Vec3::UnitZ();
  Vec3 lateral = Vec3::UnitX();
  Vec3 acetabular_axis = Vec3::UnitX();  // out of the socket opening
  // Angle between acetabular_axis and every rim direction (the rim is a cone through the HJC);
  // 90 = a hemispherical socket (models written before this key default to it).
  double socket_opening_deg = 90.0;
  // Angles measured back on the meshes by the generator (geometry/hip_measure.h); NaN when not
  // measured. alpha_profile: (clock angle from anterior towards superior, alpha) every 15 deg.
  double measured_ce_deg = std::numeric_limits<double>::quiet_NaN();
  double measured_alpha_notzli_deg = std::numeric_limits<double>::quiet_NaN();
  double measured_alpha_max_deg = std::numeric_limits<double>::quiet_NaN();
  double measured_alpha_max_clock_deg = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::pair<double, double>> alpha_profile;
  // How gmsh meshed the surfaces (generated hips; written to model.json's "surface_mesh"):
  // its Mesh.Algorithm (0: not recorded) and the algorithms that failed before it, with why.
  int surface_algorithm = 0;
  std::string mesher_failures;
  std::map<std::string, TriMesh> tissues;

  // The tissue named `name`; throws hipfai::Error when the model has none.
  const TriMesh& tissue(const std::string& name) const;
};

// Writes every tissue as <dir>/<name>.<format> (format: ply, stl, vtp or obj), with `volume`
// also <dir>/volume.msh (write_hex_msh), and model.json last, recording all of them: the one
// writer of model.json. Creates `dir` if needed. Throws hipfai::Error naming the file on failure.
void write_hip_model(const HipModel& model, const std::filesystem::path& dir,
                     const std::string& format = "ply", const HipVolumeMesh* volume = nullptr);

// Reads <dir>/model.json and the tissue files it names. Throws hipfai::Error
// "<dir>/model.json: <key>: <problem>" on a missing or malformed key (non-unit axis, wrong
// length vector, missing tissue file, vertex count differing from "counts").
// `only`: read just these tissues (an unknown name is an error); empty = all of them.
HipModel load_hip_model(const std::filesystem::path& dir, const std::set<std::string>& only = {});
// Same with model.json's text given; the tissue files are still read from `dir`.
HipModel hip_model_from_json(const std::string& text, const std::filesystem::path& dir,
                             const std::set<std::string>& only = {});

}  // namespace hipfai::geometry
