// hipfai — scene files: what to simulate and which outputs are wanted.
//
// A scene is a YAML file (schema_version 1, units declared) naming the hip, the tissues taking
// part, the motion and the outputs. Example (meshes/scenes/normal_hip.yaml):
//
//   schema_version: 1
//   units: {length: mm, angle: deg}
//   name: normal-hip
//   hip:
//     parametric: {ce_deg: 20, alpha_deg: 40, edge_mm: 2.0}   # or  model_dir: path/with/model.json
//                                     # or  bones: {femur: f.ply, pelvis: p.ply, side: right, frame: f.json}
//                                     #     (a segmented hip, dressed with synthesised cartilage and
//                                     #     labrum into the cache first: studies/pipeline/soft_tissue_model.h)
//   tissues: [femur_bone, labrum, femoral_cartilage, acetabular_cartilage]
//   motion: {builtin: standing_to_sitting, sub_motions: 30}  # or {medical: flexion, max_deg: 90,
//                                                            #      steps: 18}  or  {csv: file.csv}
//   outputs: [curvilinear_depth, radial_depth]       # also rom, von_mises, contact_pressure,
//                                                    # assessment (hipfai assess on the bones)
//   options: {mapping: cube, table_size: 20000, swap_roles: true}
//
// FE outputs (von_mises, contact_pressure) run the contact FE of fem/ over the motion
// (studies/pipeline/hip_fe_run.h, cached under <cache>/fe/). Its settings, all optional, are in the
// top-level `fe` block (ignored when no output needs the FE):
//
//   fe: {level: coarse, body_weight_n: 700}
//     level          coarse | default | fine (core/fe_choices.h, docs/fem-levels.md);
//                    default "default"
//     body_weight_n  body weight (N), (0, 10000]; default 700. The joint force scales with it:
//                    standing-to-sitting gets the sitting-down load (studies/pipeline/motion.h,
//                    attach_sitting_down_load), other motions the constant joint force
//                    (fem::constant_joint_force_n) on every step whose CSV row gives no force.
//
// Every problem (unknown key, missing file, wrong unit, angle out of range) is reported before any
// work starts, as "<file>:<line>: <key>: <problem>". Relative paths are relative to the scene file.
#pragma once

#include "anatomy/side.h"
#include "core/fe_choices.h"

#include "contact/radial_mapping.h"
#include "geometry/hip_parameters.h"

#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace hipfai::studies {

enum class Output {
  kCurvilinearDepth,  // cylindrical segmenting, femur bone vs labrum (thesis §4.3.2.1)
  kRadialDepth,       // radial segmenting, femur (bone + cartilage) vs acetabular cartilage + labrum
  kRom,               // exact range of motion about each motion axis, femur vs acetabular bone
  kVonMises,          // FE ground truth (fem/)
  kContactPressure,   // FE ground truth (fem/)
  kAssessment,        // patient-specific assessment of the bones (studies/pipeline/assessment.h), in assessment/
};

const char* output_name(Output output);
std::optional<Output> parse_output(const std::string& name);

// Tissue names shared with the generator and model.json.
const std::vector<std::string>& tissue_names();

struct ParametricHip {
  double ce_deg = 20.0;
  double alpha_deg = 40.0;
  double edge_mm = 2.0;
  // Every other generator parameter (geometry/hip_parameters.h); nullopt: the defaults. CE, alpha
  // and the edge above replace the base's own.
  std::optional<geometry::HipParameters> base = std::nullopt;
};

struct MotionSpec {
  enum class Kind { kStandingToSitting, kMedical, kCsv } kind = Kind::kStandingToSitting;
  int sub_motions = 30;             // standing to sitting
  std::string medical;              // one of medical_rotation_names()
  double max_deg = 0.0;             // medical
  int steps = 0;                    // medical
  std::filesystem::path csv;        // csv
};

struct SceneOptions {
  contact::RadialMapping mapping = contact::RadialMapping::kCube;  // spherical | cartesian | cube
  int table_size = 20000;         // radial table cells (thesis Eq. 8)
  bool swap_roles = true;         // also run each method with mobile and fixed exchanged (§4.3.2.1)
};

// A segmented hip (hip.bones): the two bone files, and the side and frame file when given (as
// `hipfai soft-tissue --side --frame`).
struct SceneBones {
  std::filesystem::path femur, pelvis, frame;  // frame empty: found on the bones
  std::optional<anatomy::Side> side;
};

// The `fe` block (see the top of this file).
struct FeSpec {
  FeLevel level = FeLevel::kDefault;  // core/fe_choices.h
  double body_weight_n = 700.0;     // N; the same default as fem::kDefaultBodyWeightN
};

struct Scene {
  std::filesystem::path file;           // where it was read from (for messages)
  std::string name;
  std::optional<ParametricHip> parametric;
  std::filesystem::path model_dir;      // set when the hip is a folder with model.json
  std::optional<SceneBones> bones;      // set when the hip is a segmented femur and pelvis
  std::set<std::string> tissues;        // as named in the scene
  MotionSpec motion;
  std::set<Output> outputs;
  SceneOptions options;
  FeSpec fe;
};

// True when the scene asks for an FE output (von_mises or contact_pressure).
bool needs_fe(const Scene& scene);
// True when the scene asks for a penetration output (curvilinear_depth, radial_depth or rom).
bool needs_penetration(const Scene& scene);

// Parses and validates a scene; throws hipfai::Error "<file>:<line>: ..." on the first problem.
Scene read_scene(const std::filesystem::path& path);
// Same from text (for tests); `origin` is used in messages and to resolve relative paths.
Scene parse_scene(const std::string& text, const std::filesystem::path& origin);

// Tissues an output needs (thesis §4.3.2.1 pairs; the FE outputs: the tissues of the hip FE
// model, femur bone, femoral and acetabular cartilage and labrum, not the rigid pelvis).
std::set<std::string> tissues_for(Output output);

}  // namespace hipfai::studies
