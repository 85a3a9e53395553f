// hipfai — the demand-driven plan: the stages a scene's outputs need, and nothing else.
//
// "Simulate only the effects a scene calls for": a radial-only scene builds no cylindrical table,
// tissues no output needs are not loaded, the FE runs only for von_mises / contact_pressure.
// `hipfai run SCENE --plan` prints this plan without running it.
#pragma once

#include "studies/pipeline/motion.h"
#include "studies/pipeline/scene.h"

#include <string>
#include <vector>

namespace hipfai::studies {

enum class StageKind {
  kGenerateHip,        // parametric hip -> meshes (cached by parameter hash)
  kLocateHip,          // user model folder with model.json
  kDressBones,         // segmented bones -> synthesised cartilage and labrum (cached by content)
  kLoadTissue,         // read one tissue mesh
  kCylindricalTable,   // ring table + pose cache (crossings) about one motion axis (cached)
  kCylindricalQuery,   // per step: curvilinear depth of the mobile vertices
  kRadialTable,        // radial table of the fixed tissue(s) about the HJC
  kRadialQuery,        // per step: radial depth
  kRangeOfMotion,      // exact ROM about one motion axis
  kFiniteElement,      // FE contact solve over the motion
  kAssessment,         // patient-specific assessment of the bones (studies/pipeline/assessment.h)
  kWriteResults,       // results.h5 + CSV
};

const char* stage_kind_name(StageKind kind);

struct Stage {
  StageKind kind;
  std::string label;    // e.g. "radial table: acetabular_cartilage+labrum (cube, 20000 cells)"
  int repeat = 1;       // per-step stages run once per motion step
};

struct Plan {
  std::vector<Stage> stages;
  int count(StageKind kind) const;
  std::string describe() const;  // one line per stage, in execution order
};

// Distinct rotation axes of a motion (steps whose axes agree to 1e-9 share a table).
std::vector<Eigen::Vector3d> distinct_axes(const Motion& motion);

Plan plan_scene(const Scene& scene, const Motion& motion);

// The joint force the FE applies to `motion` (the scene's, before any load is attached), in
// words: "sitting-down load, body weight 700 N" for standing-to-sitting, the constant joint force
// for other motions, the motion's own forces where its CSV gives them (scene_runner.h,
// fe_motion_of).
std::string fe_load_description(const Scene& scene, const Motion& motion);

}  // namespace hipfai::studies
