// hipfai — where a scene's hip comes from: generated (and cached) or a user's model folder.
#pragma once

#include "studies/pipeline/plan.h"
#include "studies/pipeline/scene.h"
#include "geometry/hip_frame.h"
#include "geometry/hip_model.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::studies {

// Stages actually executed and stages answered from the cache during a run.
struct StageLog {
  std::map<StageKind, int> executed;
  std::map<StageKind, int> reused;
  void ran(StageKind kind) { ++executed[kind]; }
  void hit(StageKind kind) { ++reused[kind]; }
  int executed_count(StageKind kind) const {
    const auto it = executed.find(kind);
    return it == executed.end() ? 0 : it->second;
  }
  int reused_count(StageKind kind) const {
    const auto it = reused.find(kind);
    return it == reused.end() ? 0 : it->second;
  }
};

struct LoadedHip {
  std::string id;                     // "ce20_alpha40" or the model folder's name
  std::filesystem::path dir;          // folder with model.json and the tissue files
  geometry::Vec3 hjc_mm = geometry::Vec3::Zero();
  // Columns: flexion, adduction and internal-rotation axes of the hip frame, in model coordinates.
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  double ce_deg = 0.0, alpha_deg = 0.0;              // as recorded in model.json
  double articular_radius_mm = 25.0;                 // radius of the articulating surfaces
  std::map<std::string, geometry::TriMesh> tissues;  // only the tissues asked for
  std::map<std::string, std::string> mesh_hash;      // tissue -> content hash of its file
};

// A loaded hip from a model in memory: frame, angles, radius and `tissues` (empty: all of them)
// with their content hashes. `id` names it in outputs.
LoadedHip loaded_hip_from_model(const geometry::HipModel& model, const std::string& id,
                                const std::set<std::string>& tissues = {});

// The name of a parametric hip in outputs and figures: "ce20_alpha40" (angles in degrees, printed
// as the shortest decimal, so 22.5 stays "22.5").
std::string parametric_hip_id(double ce_deg, double alpha_deg);

// The thesis' study grid (§4.3.2.2, core/literature.h): the 25 (CE, alpha) pairs, CE 0-40 and alpha
// 40-80 deg in 10 deg steps, CE-major.
std::vector<std::pair<double, double>> study_grid_angles();
// The grid's axes: CE 0, 10, ..., 40 and alpha 40, 50, ..., 80 deg.
std::vector<double> study_ce_deg();
std::vector<double> study_alpha_deg();

// Folder of the cached generated hip for these parameters under `cache_dir` (key: parameters and
// a content hash of core/ and geometry/, kHipSourceHash).
std::filesystem::path generated_hip_dir(const ParametricHip& hip, const std::filesystem::path& cache_dir);

// Generates the hip into the cache if it is not there (stage kGenerateHip, or a cache hit), then
// loads only `tissues` (one kLoadTissue stage each).
LoadedHip acquire_hip(const Scene& scene, const std::set<std::string>& tissues,
                      const std::filesystem::path& cache_dir, StageLog& log);

// Puts the femur at the neutral asked for (geometry/hip_frame.h): at the ISB neutral the femur's
// tissues (femur_bone, femoral_cartilage, those loaded) turn once by kAnatomicMechanicalAngleDeg
// about the hip frame's adduction axis through the HJC (the knee moves medially); their hashes
// change with them, so caches keyed by a tissue's hash never mix the two. kShaftAxis: unchanged.
void put_femur_at_neutral(LoadedHip& hip, geometry::FemoralNeutral neutral);

}  // namespace hipfai::studies
