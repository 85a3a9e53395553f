#include "studies/pipeline/scene.h"

#include "core/error.h"
#include "studies/pipeline/motion.h"
#include "studies/pipeline/radial_mapping_name.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <system_error>

namespace hipfai::studies {

namespace {

struct Context {
  std::string file;
  [[noreturn]] void fail(const YAML::Node& node, const std::string& key,
                         const std::string& problem) const {
    const int line = node.Mark().line >= 0 ? node.Mark().line + 1 : 0;
    throw_error(file, ":", line, ": ", key, ": ", problem);
  }

  void only_keys(const YAML::Node& map, const std::string& where,
                 const std::vector<std::string>& allowed) const {
    if (!map.IsMap()) fail(map, where, "expected a mapping");
    for (const auto& entry : map) {
      if (!entry.first.IsScalar()) fail(entry.first, where, "keys must be plain names");
      const auto key = entry.first.as<std::string>();
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(entry.first, where.empty() ? key : where + "." + key,
             "unknown key (expected one of: " + list + ")");
      }
    }
  }

  double number(const YAML::Node& node, const std::string& key, double min, double max) const {
    double value = 0.0;
    try {
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      fail(node, key, "expected a number, got '" + node.Scalar() + "'");
    }
    if (!(value >= min && value <= max)) {
      std::ostringstream range;
      range << value << " is outside [" << min << ", " << max << "]";
      fail(node, key, range.str());
    }
    return value;
  }

  std::string text(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) fail(node, key, "expected a string");
    return node.as<std::string>();
  }
};

std::filesystem::path resolve(const std::filesystem::path& origin, const std::string& relative) {
  const std::filesystem::path path(relative);
  return path.is_absolute() ? path : origin.parent_path() / path;
}

}  // namespace

const char* output_name(Output output) {
  switch (output) {
    case Output::kCurvilinearDepth: return "curvilinear_depth";
    case Output::kRadialDepth: return "radial_depth";
    case Output::kRom: return "rom";
    case Output::kVonMises: return "von_mises";
    case Output::kContactPressure: return "contact_pressure";
    case Output::kAssessment: return "assessment";
  }
  return "?";
}

std::optional<Output> parse_output(const std::string& name) {
  for (Output o : {Output::kCurvilinearDepth, Output::kRadialDepth, Output::kRom,
                   Output::kVonMises, Output::kContactPressure, Output::kAssessment}) {
    if (name == output_name(o)) return o;
  }
  return std::nullopt;
}

const std::vector<std::string>& tissue_names() {
  static const std::vector<std::string> names{"femur_bone", "femoral_cartilage", "acetabular_bone",
                                              "acetabular_cartilage", "labrum"};
  return names;
}

std::set<std::string> tissues_for(Output output) {
  switch (output) {
    case Output::kCurvilinearDepth: return {"femur_bone", "labrum"};
    case Output::kRadialDepth: return {"femur_bone", "femoral_cartilage", "acetabular_cartilage", "labrum"};
    case Output::kRom: return {"femur_bone", "acetabular_bone"};
    case Output::kAssessment: return {"femur_bone", "acetabular_bone"};
    case Output::kVonMises:
    case Output::kContactPressure:
      // The hip FE model (studies/pipeline/hip_fe_run.cpp): deformable cartilage and labrum, the femoral
      // bone as the rigid body the rotation is applied to; the pelvis is a fixed boundary.
      return {"femur_bone", "femoral_cartilage", "acetabular_cartilage", "labrum"};
  }
  return {};
}

bool needs_fe(const Scene& scene) {
  return scene.outputs.count(Output::kVonMises) != 0 || scene.outputs.count(Output::kContactPressure) != 0;
}

bool needs_penetration(const Scene& scene) {
  return scene.outputs.count(Output::kCurvilinearDepth) != 0 || scene.outputs.count(Output::kRadialDepth) != 0 ||
         scene.outputs.count(Output::kRom) != 0;
}

namespace {

void parse_version_and_units(const Context& ctx, const YAML::Node& root) {
  if (!root["schema_version"]) ctx.fail(root, "schema_version", "missing (this reader knows 1)");
  if (ctx.number(root["schema_version"], "schema_version", 1, 1) != 1) {
    ctx.fail(root["schema_version"], "schema_version", "unsupported");
  }
  const YAML::Node units = root["units"];
  if (!units) ctx.fail(root, "units", "missing: declare {length: mm, angle: deg}");
  ctx.only_keys(units, "units", {"length", "angle"});
  if (!units["length"] || ctx.text(units["length"], "units.length") != "mm") {
    ctx.fail(units, "units.length", "must be 'mm' (hipfai works in millimetres)");
  }
  if (!units["angle"] || ctx.text(units["angle"], "units.angle") != "deg") {
    ctx.fail(units, "units.angle", "must be 'deg' (angles at interfaces are in degrees)");
  }
}

ParametricHip parse_parametric(const Context& ctx, const YAML::Node& p) {
  ctx.only_keys(p, "hip.parametric", {"ce_deg", "alpha_deg", "edge_mm"});
  ParametricHip parametric;
  if (p["ce_deg"]) parametric.ce_deg = ctx.number(p["ce_deg"], "hip.parametric.ce_deg", 0, 45);
  if (p["alpha_deg"]) {
    parametric.alpha_deg = ctx.number(p["alpha_deg"], "hip.parametric.alpha_deg", 35, 90);
  }
  if (p["edge_mm"]) parametric.edge_mm = ctx.number(p["edge_mm"], "hip.parametric.edge_mm", 0.2, 10);
  return parametric;
}

SceneBones parse_bones(const Context& ctx, const YAML::Node& b, const std::filesystem::path& origin) {
  ctx.only_keys(b, "hip.bones", {"femur", "pelvis", "side", "frame"});
  SceneBones bones;
  const auto existing = [&](const char* key) {
    if (!b[key]) ctx.fail(b, std::string("hip.bones.") + key, "missing");
    const std::filesystem::path path = resolve(origin, ctx.text(b[key], std::string("hip.bones.") + key));
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
      ctx.fail(b[key], std::string("hip.bones.") + key, "file not found: " + path.string());
    }
    return path;
  };
  bones.femur = existing("femur");
  bones.pelvis = existing("pelvis");
  if (b["frame"]) bones.frame = existing("frame");
  if (b["side"]) {
    const std::string side = ctx.text(b["side"], "hip.bones.side");
    if (side == anatomy::side_name(anatomy::Side::kRight)) bones.side = anatomy::Side::kRight;
    else if (side == anatomy::side_name(anatomy::Side::kLeft)) bones.side = anatomy::Side::kLeft;
    else ctx.fail(b["side"], "hip.bones.side", "expected right or left");
  }
  return bones;
}

void parse_hip(const Context& ctx, const YAML::Node& root, const std::filesystem::path& origin, Scene& scene) {
  const YAML::Node hip = root["hip"];
  if (!hip) ctx.fail(root, "hip", "missing: give parametric: {...}, model_dir: path or bones: {...}");
  ctx.only_keys(hip, "hip", {"parametric", "model_dir", "bones"});
  if ((hip["parametric"] ? 1 : 0) + (hip["model_dir"] ? 1 : 0) + (hip["bones"] ? 1 : 0) > 1) {
    ctx.fail(hip, "hip", "give one of parametric, model_dir and bones");
  }
  if (const YAML::Node p = hip["parametric"]) {
    scene.parametric = parse_parametric(ctx, p);
  } else if (const YAML::Node dir = hip["model_dir"]) {
    scene.model_dir = resolve(origin, ctx.text(dir, "hip.model_dir"));
    std::error_code ec;  // a path the system refuses (too long, looping links) is as good as missing
    if (!std::filesystem::exists(scene.model_dir / "model.json", ec)) {
      ctx.fail(dir, "hip.model_dir", "no model.json in " + scene.model_dir.string());
    }
  } else if (const YAML::Node b = hip["bones"]) {
    scene.bones = parse_bones(ctx, b, origin);
  } else {
    ctx.fail(hip, "hip", "give parametric: {...}, model_dir: path or bones: {...}");
  }
}

void parse_outputs(const Context& ctx, const YAML::Node& root, Scene& scene) {
  const YAML::Node outputs = root["outputs"];
  if (!outputs || !outputs.IsSequence() || outputs.size() == 0) {
    ctx.fail(outputs ? outputs : root, "outputs", "expected a non-empty list");
  }
  for (const auto& item : outputs) {
    const auto name = ctx.text(item, "outputs");
    const auto output = parse_output(name);
    if (!output) {
      ctx.fail(item, "outputs", "unknown output '" + name +
                                    "' (expected curvilinear_depth, radial_depth, rom, von_mises, "
                                    "contact_pressure)");
    }
    scene.outputs.insert(*output);
  }
}

// The tissues listed (each output's must be among them), or those the outputs need.
void parse_tissues(const Context& ctx, const YAML::Node& root, Scene& scene) {
  if (const YAML::Node tissues = root["tissues"]) {
    if (!tissues.IsSequence()) ctx.fail(tissues, "tissues", "expected a list");
    for (const auto& item : tissues) {
      const auto name = ctx.text(item, "tissues");
      if (std::find(tissue_names().begin(), tissue_names().end(), name) == tissue_names().end()) {
        ctx.fail(item, "tissues", "unknown tissue '" + name + "'");
      }
      scene.tissues.insert(name);
    }
    for (Output output : scene.outputs) {
      for (const auto& needed : tissues_for(output)) {
        if (!scene.tissues.count(needed)) {
          ctx.fail(tissues, "tissues", std::string("output ") + output_name(output) + " needs '" +
                                           needed + "', which the list leaves out");
        }
      }
    }
  } else {
    for (Output output : scene.outputs) {
      const auto needed = tissues_for(output);
      scene.tissues.insert(needed.begin(), needed.end());
    }
  }
}

void parse_motion(const Context& ctx, const YAML::Node& root, const std::filesystem::path& origin, Scene& scene) {
  const YAML::Node motion = root["motion"];
  if (!motion) ctx.fail(root, "motion", "missing");
  ctx.only_keys(motion, "motion", {"builtin", "sub_motions", "medical", "max_deg", "steps", "csv"});
  const int kinds = (motion["builtin"] ? 1 : 0) + (motion["medical"] ? 1 : 0) + (motion["csv"] ? 1 : 0);
  if (kinds != 1) ctx.fail(motion, "motion", "give exactly one of builtin, medical, csv");
  if (motion["builtin"]) {
    if (ctx.text(motion["builtin"], "motion.builtin") != "standing_to_sitting") {
      ctx.fail(motion["builtin"], "motion.builtin", "unknown (expected standing_to_sitting)");
    }
    scene.motion.kind = MotionSpec::Kind::kStandingToSitting;
    if (motion["sub_motions"]) {
      scene.motion.sub_motions =
          static_cast<int>(ctx.number(motion["sub_motions"], "motion.sub_motions", 1, 1000));
    }
  } else if (motion["medical"]) {
    scene.motion.kind = MotionSpec::Kind::kMedical;
    scene.motion.medical = ctx.text(motion["medical"], "motion.medical");
    const auto& names = medical_rotation_names();
    if (std::find(names.begin(), names.end(), scene.motion.medical) == names.end()) {
      ctx.fail(motion["medical"], "motion.medical", "unknown rotation '" + scene.motion.medical + "'");
    }
    if (!motion["max_deg"] || !motion["steps"]) {
      ctx.fail(motion, "motion", "medical rotation needs max_deg and steps");
    }
    scene.motion.max_deg = ctx.number(motion["max_deg"], "motion.max_deg", 1e-6, 180);
    scene.motion.steps = static_cast<int>(ctx.number(motion["steps"], "motion.steps", 1, 1000));
  } else {
    scene.motion.kind = MotionSpec::Kind::kCsv;
    scene.motion.csv = resolve(origin, ctx.text(motion["csv"], "motion.csv"));
    std::error_code ec;  // as for hip.model_dir
    if (!std::filesystem::exists(scene.motion.csv, ec)) {
      ctx.fail(motion["csv"], "motion.csv", "file not found: " + scene.motion.csv.string());
    }
  }
}

void parse_options(const Context& ctx, const YAML::Node& options, Scene& scene) {
  ctx.only_keys(options, "options", {"mapping", "table_size", "swap_roles"});
  if (options["mapping"]) {
    const auto mapping = radial_mapping_from_name(ctx.text(options["mapping"], "options.mapping"));
    if (!mapping) ctx.fail(options["mapping"], "options.mapping", "expected spherical, cartesian or cube");
    scene.options.mapping = *mapping;
  }
  if (options["table_size"]) {
    scene.options.table_size =
        static_cast<int>(ctx.number(options["table_size"], "options.table_size", 6, 1e8));
  }
  if (options["swap_roles"]) {
    try {
      scene.options.swap_roles = options["swap_roles"].as<bool>();
    } catch (const YAML::Exception&) {
      ctx.fail(options["swap_roles"], "options.swap_roles", "expected true or false");
    }
  }
}

void parse_fe(const Context& ctx, const YAML::Node& fe, Scene& scene) {
  ctx.only_keys(fe, "fe", {"level", "body_weight_n"});
  if (fe["level"]) {
    const std::string name = ctx.text(fe["level"], "fe.level");
    const std::optional<FeLevel> level = fe_level_from_name(name);
    if (!level) ctx.fail(fe["level"], "fe.level", "unknown level '" + name + "' (expected coarse, default or fine)");
    scene.fe.level = *level;
  }
  if (fe["body_weight_n"]) {
    scene.fe.body_weight_n = ctx.number(fe["body_weight_n"], "fe.body_weight_n", 0, 10000);
    if (scene.fe.body_weight_n <= 0) ctx.fail(fe["body_weight_n"], "fe.body_weight_n", "must be positive");
  }
}

}  // namespace

Scene parse_scene(const std::string& text, const std::filesystem::path& origin) {
  const Context ctx{origin.string()};
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw_error(origin.string(), ":", e.mark.line + 1, ": YAML syntax error: ", e.msg);
  }
  if (!root.IsMap()) throw_error(origin.string(), ":1: a scene must be a YAML mapping");
  ctx.only_keys(root, "", {"schema_version", "units", "name", "hip", "tissues", "motion", "outputs",
                           "options", "fe"});
  Scene scene;
  scene.file = origin;
  parse_version_and_units(ctx, root);
  scene.name = root["name"] ? ctx.text(root["name"], "name") : origin.stem().string();
  parse_hip(ctx, root, origin, scene);
  parse_outputs(ctx, root, scene);
  parse_tissues(ctx, root, scene);
  parse_motion(ctx, root, origin, scene);
  if (const YAML::Node options = root["options"]) parse_options(ctx, options, scene);
  if (const YAML::Node fe = root["fe"]) parse_fe(ctx, fe, scene);
  return scene;
}

Scene read_scene(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw_error(path.string(), ": cannot open scene file");
  std::stringstream text;
  text << in.rdbuf();
  return parse_scene(text.str(), path);
}

}  // namespace hipfai::studies
