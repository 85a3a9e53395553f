#include "studies/pipeline/segmented_hip.h"

#include "core/error.h"
#include "geometry/hjc_regions.h"
#include "geometry/mesh_io.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace hipfai::studies {

Eigen::Matrix3d approximate_hip_frame(const geometry::TriMesh& femur, const geometry::TriMesh& pelvis,
                                      const geometry::Vec3& head_centre_mm) {
  if (femur.vertices.empty() || pelvis.vertices.empty()) throw_error("hip frame: empty femur or pelvis mesh");
  geometry::Vec3 femur_centroid, pelvis_centroid;
  Eigen::Vector3d z = geometry::principal_axis(femur, &femur_centroid);
  geometry::principal_axis(pelvis, &pelvis_centroid);
  if ((head_centre_mm - femur_centroid).dot(z) < 0.0) z = -z;
  Eigen::Vector3d x = head_centre_mm - pelvis_centroid;
  x -= x.dot(z) * z;
  if (x.norm() < 1e-6) throw_error("hip frame: the head centre lies on the line of the femur's axis through the pelvis");
  x.normalize();
  Eigen::Matrix3d frame;
  frame << x, z.cross(x), z;
  return frame;
}

geometry::HipModel load_segmented_hip(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "hip.json";
  std::ifstream in(file, std::ios::binary);
  if (!in) throw_error(file.string(), ": cannot read");
  std::ostringstream text;
  text << in.rdbuf();
  return segmented_hip_from_json(text.str(), dir);
}

geometry::HipModel segmented_hip_from_json(const std::string& text, const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "hip.json";
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    throw_error(file.string(), ": not JSON (", error.what(), ")");
  }
  if (!json.is_object() || !json.contains("hjc_mm") || !json.contains("tissues") || !json["tissues"].is_object()) {
    throw_error(file.string(), ": needs hjc_mm and tissues");
  }
  for (const char* key : {"side", "units"}) {
    if (json.contains(key) && !json[key].is_string()) throw_error(file.string(), ": ", key, " must be a string");
  }
  if (json.value("side", std::string("right")) != "right") {
    throw_error(file.string(), ": a ", json.value("side", std::string()), " hip; only right hips are supported (mirror it)");
  }
  if (json.value("units", std::string("mm")) != "mm") throw_error(file.string(), ": units must be mm");
  const auto& hjc = json["hjc_mm"];
  if (!hjc.is_array() || hjc.size() != 3 || !hjc[0].is_number() || !hjc[1].is_number() || !hjc[2].is_number()) {
    throw_error(file.string(), ": hjc_mm must be three numbers");
  }
  geometry::HipModel model;
  model.hjc_mm = geometry::Vec3(hjc[0].get<double>(), hjc[1].get<double>(), hjc[2].get<double>());
  for (const auto& [tissue, name] : json["tissues"].items()) {
    if (!name.is_string()) throw_error(file.string(), ": tissues.", tissue, " must be a file name");
    model.tissues[tissue] = geometry::read_mesh(dir / name.get<std::string>());
  }
  if (!model.tissues.count("femur_bone") || !model.tissues.count("pelvis_bone")) {
    throw_error(file.string(), ": the hip frame needs tissues femur_bone and pelvis_bone");
  }
  const Eigen::Matrix3d frame =
      approximate_hip_frame(model.tissues.at("femur_bone"), model.tissues.at("pelvis_bone"), model.hjc_mm);
  model.axes.flexion_axis = frame.col(0);
  model.axes.adduction_axis = frame.col(1);
  model.axes.internal_rotation_axis = frame.col(2);
  model.lateral = frame.col(0);
  model.superior = frame.col(2);
  return model;
}

}  // namespace hipfai::studies
