#include "geometry/hip_parameters.h"

#include "core/error.h"
#include "geometry/hip_frame.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>

namespace hipfai::geometry {
namespace {

struct Field {
  const char* name;
  double HipParameters::*member;
  double min;
  double max;
};

// One row per field: the JSON key, the member, the allowed range (see hip_parameters.h).
constexpr std::array<Field, 29> kFields{{
    {"ce_deg", &HipParameters::ce_deg, 0.0, 45.0},
    {"alpha_deg", &HipParameters::alpha_deg, 35.0, 90.0},
    {"articular_radius_mm", &HipParameters::articular_radius_mm, 20.0, 30.0},
    {"femoral_cartilage_mm", &HipParameters::femoral_cartilage_mm, 0.5, 4.0},
    {"acetabular_cartilage_mm", &HipParameters::acetabular_cartilage_mm, 0.5, 4.0},
    {"labrum_height_mm", &HipParameters::labrum_height_mm, 3.0, 10.0},
    {"labrum_base_mm", &HipParameters::labrum_base_mm, 3.0, 10.0},
    {"labrum_neck_clearance_mm", &HipParameters::labrum_neck_clearance_mm, 0.0, 5.0},
    {"neck_shaft_angle_deg", &HipParameters::neck_shaft_angle_deg, 110.0, 150.0},
    {"femoral_anteversion_deg", &HipParameters::femoral_anteversion_deg, -10.0, 40.0},
    {"acetabular_anteversion_deg", &HipParameters::acetabular_anteversion_deg, 0.0, 35.0},
    {"hemisphere_ce_deg", &HipParameters::hemisphere_ce_deg, 0.0, 45.0},
    {"ce_rim_mode", &HipParameters::ce_rim_mode, 0.0, 1.0},
    {"neck_radius_mm", &HipParameters::neck_radius_mm, 8.0, 20.0},
    {"neck_length_mm", &HipParameters::neck_length_mm, 30.0, 70.0},
    {"shaft_radius_mm", &HipParameters::shaft_radius_mm, 8.0, 25.0},
    {"shaft_length_mm", &HipParameters::shaft_length_mm, 10.0, 120.0},
    {"normal_alpha_deg", &HipParameters::normal_alpha_deg, 30.0, 50.0},
    {"femoral_cartilage_edge_deg", &HipParameters::femoral_cartilage_edge_deg, 32.0, 80.0},
    {"cam_begin_deg", &HipParameters::cam_begin_deg, -90.0, 180.0},
    {"cam_end_deg", &HipParameters::cam_end_deg, -90.0, 180.0},
    {"cam_radius_mm", &HipParameters::cam_radius_mm, 4.0, 20.0},
    {"cam_height_mm", &HipParameters::cam_height_mm, 0.5, 6.0},
    {"pelvis_block_x_mm", &HipParameters::pelvis_block_x_mm, 60.0, 200.0},
    {"pelvis_block_y_mm", &HipParameters::pelvis_block_y_mm, 60.0, 200.0},
    {"pelvis_block_z_mm", &HipParameters::pelvis_block_z_mm, 60.0, 200.0},
    {"fossa_half_angle_deg", &HipParameters::fossa_half_angle_deg, 15.0, 60.0},
    {"notch_width_mm", &HipParameters::notch_width_mm, 5.0, 40.0},
    {"edge_mm", &HipParameters::edge_mm, 0.2, 10.0},
}};

}  // namespace

void validate_hip_parameters(const HipParameters& p, const std::string& what) {
  for (const Field& field : kFields) {
    if (field.member == nullptr) continue;
    const double value = p.*field.member;
    if (!std::isfinite(value) || value < field.min || value > field.max) {
      throw_error(what, ": ", field.name, " = ", value, " is outside [", field.min, ", ",
                  field.max, "]");
    }
  }
  // Relations between fields that keep the construction valid.
  const double junction_deg = std::min(p.alpha_deg, p.normal_alpha_deg);
  if (p.neck_radius_mm >= 0.95 * p.articular_radius_mm * std::sin(junction_deg * kDegToRad)) {
    throw_error(what, ": neck_radius_mm = ", p.neck_radius_mm,
                " must be below 0.95 * articular_radius_mm * sin(min(alpha_deg, normal_alpha_deg))");
  }
  if (p.femoral_cartilage_edge_deg < junction_deg + 2.0) {
    throw_error(what, ": femoral_cartilage_edge_deg = ", p.femoral_cartilage_edge_deg,
                " must be at least min(alpha_deg, normal_alpha_deg) + 2");
  }
  if (p.ce_rim_mode != 0.0 && p.ce_rim_mode != 1.0) {
    throw_error(what, ": ce_rim_mode = ", p.ce_rim_mode, " must be 0 (whole rim) or 1 (tilt)");
  }
  if (p.cam_end_deg < p.cam_begin_deg || p.cam_end_deg - p.cam_begin_deg > 180.0) {
    throw_error(what, ": cam_end_deg = ", p.cam_end_deg, " must be within [cam_begin_deg, cam_begin_deg + 180]");
  }
  {
    // The labrum's tip must stay on the socket side of the acetabular axis.
    const double open = socket_opening_deg(p);
    const double tip = open - std::asin(std::min(1.0, p.labrum_height_mm / p.articular_radius_mm)) * kRadToDeg;
    if (tip < 10.0 || open > 150.0) {
      throw_error(what, ": ce_deg = ", p.ce_deg, " with hemisphere_ce_deg = ", p.hemisphere_ce_deg,
                  " gives a socket opening of ", open, " deg from its axis; outside the range the construction supports");
    }
  }
  if (p.cam_radius_mm <= p.cam_height_mm) {
    throw_error(what, ": cam_radius_mm = ", p.cam_radius_mm, " must exceed cam_height_mm");
  }
  if (p.neck_length_mm < p.articular_radius_mm + 5.0) {
    throw_error(what, ": neck_length_mm = ", p.neck_length_mm,
                " must exceed articular_radius_mm + 5");
  }
}

std::string hip_parameters_to_json(const HipParameters& p, int indent) {
  nlohmann::ordered_json json;
  for (const Field& field : kFields) {
    if (field.member != nullptr) json[field.name] = p.*field.member;
  }
  return json.dump(indent);
}

std::vector<std::pair<std::string, double>> hip_parameters_changed(const HipParameters& p,
                                                                   const HipParameters& reference) {
  std::vector<std::pair<std::string, double>> changed;
  for (const Field& field : kFields) {
    if (field.member != nullptr && p.*field.member != reference.*field.member) {
      changed.emplace_back(field.name, p.*field.member);
    }
  }
  return changed;
}

HipParameters hip_parameters_from_json(const std::string& text, const std::string& what) {
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw_error(what, ": invalid JSON: ", e.what());
  }
  if (!json.is_object()) throw_error(what, ": expected a JSON object of hip parameters");
  HipParameters p;
  for (const auto& [key, value] : json.items()) {
    const Field* found = nullptr;
    for (const Field& field : kFields) {
      if (field.member != nullptr && key == field.name) found = &field;
    }
    if (found == nullptr) throw_error(what, ": unknown parameter '", key, "'");
    if (!value.is_number()) throw_error(what, ": parameter '", key, "' must be a number");
    p.*(found->member) = value.get<double>();
  }
  validate_hip_parameters(p, what);
  return p;
}

HipParameters load_hip_parameters(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw_error(path.string(), ": no such file");
  std::ifstream in(path);
  if (!in) throw_error(path.string(), ": cannot open for reading");
  std::stringstream text;
  text << in.rdbuf();
  return hip_parameters_from_json(text.str(), path.string());
}

Vec3 neck_axis(const HipParameters& p) {
  // The neck makes the neck-shaft angle with the distal shaft axis (-Z), so from the HJC it
  // points (CCD - 90) deg below the horizontal, laterally (n . Z = cos CCD); anteversion puts the head
  // anterior of the shaft, i.e. the neck runs posteriorly from the head to the shaft.
  const double below = (p.neck_shaft_angle_deg - 90.0) * kDegToRad;
  const double version = p.femoral_anteversion_deg * kDegToRad;
  const double horizontal = std::cos(below);
  return Vec3(horizontal * std::cos(version), -horizontal * std::sin(version), -std::sin(below))
      .normalized();
}

Vec3 acetabular_axis(const HipParameters& p) {
  // The axis of the hemisphere whose rim passes through the lateral edge at CE0 (CE0 = ce_deg
  // when CE tilts the socket, hemisphere_ce_deg when it sets the rim's depth): the opening plane
  // through the HJC has its trace in Y = 0 at CE0 from +Z, so the in-plane component of the
  // normal is (cos CE0, 0, -sin CE0); anteversion tilts it anteriorly about Z without moving
  // that trace.
  const double ce = (p.ce_rim_mode == 1.0 ? p.ce_deg : p.hemisphere_ce_deg) * kDegToRad;
  const double version = p.acetabular_anteversion_deg * kDegToRad;
  return Vec3(std::cos(ce) * std::cos(version), std::sin(version), -std::sin(ce) * std::cos(version))
      .normalized();
}

double socket_opening_deg(const HipParameters& p) {
  if (p.ce_rim_mode == 1.0) return 90.0;
  // The lateral edge at CE in the frontal plane, L = (sin CE, 0, cos CE), lies on the rim cone.
  const double ce = p.ce_deg * kDegToRad;
  const Vec3 lateral_edge(std::sin(ce), 0.0, std::cos(ce));
  return std::acos(std::clamp(lateral_edge.dot(acetabular_axis(p)), -1.0, 1.0)) * kRadToDeg;
}

Vec3 neck_superior(const HipParameters& p) {
  const Vec3 n = neck_axis(p);
  return (Vec3::UnitZ() - Vec3::UnitZ().dot(n) * n).normalized();
}

Vec3 neck_anterior(const HipParameters& p) {
  // superior x n: with n lateral-inferior, this points anteriorly (+Y) for a right hip.
  const Vec3 anterior = neck_superior(p).cross(neck_axis(p)).normalized();
  return anterior.dot(Vec3::UnitY()) >= 0.0 ? anterior : Vec3(-anterior);
}

Vec3 clock_direction(const HipParameters& p, double clock_deg) {
  const double angle = clock_deg * kDegToRad;
  return (std::cos(angle) * neck_anterior(p) + std::sin(angle) * neck_superior(p)).normalized();
}

}  // namespace hipfai::geometry
