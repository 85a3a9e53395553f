#include "geometry/hip_model.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "geometry/hip_measure.h"
#include "geometry/hip_volume_mesh.h"
#include "geometry/mesh_io.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

namespace hipfai::geometry {
namespace {

nlohmann::json to_json(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

Vec3 read_vector(const nlohmann::json& json, const std::string& key, const std::string& what,
                 bool unit) {
  if (!json.contains(key)) throw_error(what, ": missing key '", key, "'");
  const auto& value = json.at(key);
  if (!value.is_array() || value.size() != 3) {
    throw_error(what, ": ", key, ": expected an array of 3 numbers");
  }
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!value[static_cast<std::size_t>(i)].is_number()) {
      throw_error(what, ": ", key, ": expected an array of 3 numbers");
    }
    v[i] = value[static_cast<std::size_t>(i)].get<double>();
  }
  if (!v.allFinite()) throw_error(what, ": ", key, ": non-finite component");
  // 1e-6: the writer stores 17 significant digits, so a unit vector reads back to ~1e-16.
  if (unit && std::abs(v.norm() - 1.0) > 1e-6) {
    throw_error(what, ": ", key, ": not a unit vector (length ", v.norm(), ")");
  }
  return v;
}

double read_number(const nlohmann::json& json, const std::string& key, const std::string& what) {
  if (!json.contains(key)) throw_error(what, ": missing key '", key, "'");
  if (!json.at(key).is_number()) throw_error(what, ": ", key, ": expected a number");
  return json.at(key).get<double>();
}

}  // namespace

const char* to_string(SoftTissueSource source) {
  switch (source) {
    case SoftTissueSource::kGenerated: return "generated";
    case SoftTissueSource::kSynthesised: return "synthesised";
  }
  return "?";
}

const TriMesh& HipModel::tissue(const std::string& name) const {
  const auto it = tissues.find(name);
  if (it == tissues.end()) throw_error("hip model: no tissue '", name, "'");
  return it->second;
}

void write_hip_model(const HipModel& model, const std::filesystem::path& dir,
                     const std::string& format, const HipVolumeMesh* volume) {
  if (format != "ply" && format != "stl" && format != "vtp" && format != "obj") {
    throw_error("--format: unknown mesh format '", format, "' (expected ply, stl, vtp or obj)");
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw_error(dir.string(), ": cannot create directory: ", ec.message());

  nlohmann::ordered_json json;
  json["format"] = "hipfai-hip-model";
  json["version"] = 1;
  json["units"] = "mm, deg";
  json["handedness"] = "right";
  json["ce_deg"] = model.parameters.ce_deg;
  json["alpha_deg"] = model.parameters.alpha_deg;
  json["hjc_mm"] = to_json(model.hjc_mm);
  json["flexion_axis"] = to_json(model.axes.flexion_axis);
  json["adduction_axis"] = to_json(model.axes.adduction_axis);
  json["internal_rotation_axis"] = to_json(model.axes.internal_rotation_axis);
  json["neck_axis"] = to_json(model.neck_axis);
  json["superior"] = to_json(model.superior);
  json["lateral"] = to_json(model.lateral);
  json["acetabular_axis"] = to_json(model.acetabular_axis);
  json["socket_opening_deg"] = model.socket_opening_deg;
  if (std::isfinite(model.measured_ce_deg) || !model.alpha_profile.empty()) {
    nlohmann::ordered_json measured;
    auto number_or_null = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
    measured["ce_deg"] = number_or_null(model.measured_ce_deg);
    measured["alpha_notzli_deg"] = number_or_null(model.measured_alpha_notzli_deg);
    measured["alpha_max_deg"] = number_or_null(model.measured_alpha_max_deg);
    measured["alpha_max_clock"] = std::isfinite(model.measured_alpha_max_clock_deg)
                                      ? nlohmann::ordered_json(clock_label(model.measured_alpha_max_clock_deg))
                                      : nlohmann::ordered_json();
    nlohmann::ordered_json profile = nlohmann::ordered_json::array();
    for (const auto& [clock_deg, alpha] : model.alpha_profile) {
      profile.push_back({{"clock", clock_label(clock_deg)}, {"clock_deg", clock_deg}, {"alpha_deg", number_or_null(alpha)}});
    }
    measured["alpha_profile"] = profile;
    json["measured"] = measured;
  }
  if (model.soft_tissue != SoftTissueSource::kGenerated) json["soft_tissue"] = to_string(model.soft_tissue);
  json["edge_mm"] = model.parameters.edge_mm;
  if (model.surface_algorithm != 0) {
    json["surface_mesh"] = {{"gmsh_algorithm", model.surface_algorithm},
                            {"failed_before", model.mesher_failures}};
  }
  json["parameters"] = nlohmann::ordered_json::parse(hip_parameters_to_json(model.parameters));
  nlohmann::ordered_json tissues = nlohmann::ordered_json::object();
  nlohmann::ordered_json counts = nlohmann::ordered_json::object();
  for (const auto& [name, mesh] : model.tissues) {
    const std::string file = name + "." + format;
    write_mesh(mesh, dir / file);
    tissues[name] = file;
    counts[name] = {{"vertices", mesh.num_vertices()}, {"triangles", mesh.num_triangles()}};
  }
  json["tissues"] = tissues;
  json["counts"] = counts;
  if (volume) {
    write_hex_msh(volume->mesh, dir / "volume.msh");
    nlohmann::ordered_json record;
    record["file"] = "volume.msh";
    record["format"] = "gmsh MSH 2.2 ASCII: hexahedra tagged by tissue, boundary quadrangles by surface";
    record["edge_mm"] = volume->options.edge_mm;
    record["layers"] = volume->options.layers;
    record["min_thickness_mm"] = volume->options.min_thickness_mm;
    record["hexahedra"] = volume->mesh.hexes.size();
    record["nodes"] = volume->mesh.vertices.size();
    record["boundary_quadrangles"] = volume->mesh.quads.size();
    record["min_scaled_jacobian"] = volume->min_scaled_jacobian;
    json["volume"] = record;
  }
  // Last and atomically: a model.json that exists names files that are all complete.
  write_file_atomically(dir / "model.json", json.dump(2) + "\n");
}

HipModel load_hip_model(const std::filesystem::path& dir, const std::set<std::string>& only) {
  const auto path = dir / "model.json";
  std::ifstream in(path);
  if (!in) throw_error(path.string(), ": cannot open");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return hip_model_from_json(buffer.str(), dir, only);
}

HipModel hip_model_from_json(const std::string& text, const std::filesystem::path& dir,
                             const std::set<std::string>& only) {
  const std::string what = (dir / "model.json").string();
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw_error(what, ": invalid JSON: ", e.what());
  }
  if (!json.is_object()) throw_error(what, ": expected a JSON object");
  if (!json.contains("format") || json["format"] != "hipfai-hip-model") {
    throw_error(what, ": format: expected \"hipfai-hip-model\"");
  }

  HipModel model;
  if (!json.contains("parameters") || !json["parameters"].is_object()) {
    throw_error(what, ": parameters: missing or not an object");
  }
  model.parameters = hip_parameters_from_json(json["parameters"].dump(), what + ": parameters");
  model.parameters.ce_deg = read_number(json, "ce_deg", what);
  model.parameters.alpha_deg = read_number(json, "alpha_deg", what);
  model.parameters.edge_mm = read_number(json, "edge_mm", what);
  model.hjc_mm = read_vector(json, "hjc_mm", what, false);
  model.axes.flexion_axis = read_vector(json, "flexion_axis", what, true);
  model.axes.adduction_axis = read_vector(json, "adduction_axis", what, true);
  model.axes.internal_rotation_axis = read_vector(json, "internal_rotation_axis", what, true);
  model.neck_axis = read_vector(json, "neck_axis", what, true);
  model.superior = read_vector(json, "superior", what, true);
  model.lateral = read_vector(json, "lateral", what, true);
  model.acetabular_axis = read_vector(json, "acetabular_axis", what, true);
  if (json.contains("socket_opening_deg")) {
    model.socket_opening_deg = read_number(json, "socket_opening_deg", what);
    if (!(model.socket_opening_deg > 0.0 && model.socket_opening_deg < 180.0)) {
      throw_error(what, ": socket_opening_deg: ", model.socket_opening_deg, " is outside (0, 180)");
    }
  }
  if (json.contains("soft_tissue")) {
    const nlohmann::json& source = json["soft_tissue"];
    if (source == to_string(SoftTissueSource::kGenerated)) {
      model.soft_tissue = SoftTissueSource::kGenerated;
    } else if (source == to_string(SoftTissueSource::kSynthesised)) {
      model.soft_tissue = SoftTissueSource::kSynthesised;
    } else {
      throw_error(what, ": soft_tissue: expected \"generated\" or \"synthesised\"");
    }
  }
  if (json.contains("surface_mesh")) {
    const nlohmann::json& mesher = json["surface_mesh"];
    if (!mesher.is_object() || !mesher.contains("gmsh_algorithm") || !mesher["gmsh_algorithm"].is_number_integer() ||
        mesher["gmsh_algorithm"].get<std::int64_t>() < 1 || mesher["gmsh_algorithm"].get<std::int64_t>() > 11 ||
        !mesher.contains("failed_before") || !mesher["failed_before"].is_string()) {
      throw_error(what, ": surface_mesh: expected {\"gmsh_algorithm\": 1-11, \"failed_before\": text}");
    }
    model.surface_algorithm = static_cast<int>(mesher["gmsh_algorithm"].get<std::int64_t>());
    model.mesher_failures = mesher["failed_before"].get<std::string>();
  }

  if (!json.contains("tissues") || !json["tissues"].is_object() || json["tissues"].empty()) {
    throw_error(what, ": tissues: missing, empty or not an object");
  }
  const nlohmann::json counts = json.value("counts", nlohmann::json::object());
  for (const auto& name : only) {
    if (!json["tissues"].contains(name)) throw_error(what, ": tissues: no tissue '", name, "'");
  }
  for (const auto& [name, file] : json["tissues"].items()) {
    if (!file.is_string()) throw_error(what, ": tissues.", name, ": expected a file name");
    if (!only.empty() && only.count(name) == 0) continue;  // not asked for: not read
    const auto mesh_path = dir / file.get<std::string>();
    std::error_code ec;  // a name the system refuses (too long) is as good as missing
    if (!std::filesystem::exists(mesh_path, ec)) {
      throw_error(what, ": tissues.", name, ": file not found: ", mesh_path.string());
    }
    TriMesh mesh = read_mesh(mesh_path);
    if (counts.contains(name) && counts[name].contains("vertices") &&
        counts[name]["vertices"].is_number_integer() &&
        counts[name]["vertices"].get<std::size_t>() != mesh.num_vertices()) {
      throw_error(what, ": counts.", name, ".vertices: ", counts[name]["vertices"].get<std::size_t>(),
                  " but ", mesh_path.string(), " has ", mesh.num_vertices());
    }
    model.tissues.emplace(name, std::move(mesh));
  }
  return model;
}

}  // namespace hipfai::geometry
