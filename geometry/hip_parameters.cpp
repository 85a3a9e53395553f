#include "geometry/hip_parameters.h"

#include "core/error.h"
#include "geometry/hip_frame.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>

namespace hipfai::geometry {
namespace {

struct Field {
  const char* name;
  double HipParameters::*member;
  double min;
  double max;
};

// One row per field: the JSON key, the member, the allowed range (see hip_parameters.h).
constexpr std::array<Field, 26> kFields{{
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
    {"neck_radius_mm", &HipParameters::neck_radius_mm, 8.0, 20.0},
    {"neck_length_mm", &HipParameters::neck_length_mm, 30.0, 70.0},
    {"shaft_radius_mm", &HipParameters::shaft_radius_mm, 8.0, 25.0},
    {"shaft_length_mm", &HipParameters::shaft_length_mm, 10.0, 120.0},
    {"normal_alpha_deg", &HipParameters::normal_alpha_deg, 30.0, 50.0},
    {"femoral_cartilage_edge_deg", &HipParameters::femoral_cartilage_edge_deg, 32.0, 80.0},
    {"cam_position_deg", &HipParameters::cam_position_deg, 0.0, 90.0},
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
  // Opening plane through the HJC; its trace in Y = 0 is the line at ce_deg from +Z, so the
  // in-plane component of the normal is (cos CE, 0, -sin CE); anteversion tilts it anteriorly
  // about Z without moving that trace.
  const double ce = p.ce_deg * kDegToRad;
  const double version = p.acetabular_anteversion_deg * kDegToRad;
  return Vec3(std::cos(ce) * std::cos(version), std::sin(version), -std::sin(ce) * std::cos(version))
      .normalized();
}

Vec3 cam_direction(const HipParameters& p) {
  const Vec3 n = neck_axis(p);
  const Vec3 superior = (Vec3::UnitZ() - Vec3::UnitZ().dot(n) * n).normalized();
  const Vec3 anterior = superior.cross(n).normalized();
  // superior x n: with n lateral-inferior, this points anteriorly (+Y) for a right hip.
  const double angle = p.cam_position_deg * kDegToRad;
  const Vec3 a = anterior.dot(Vec3::UnitY()) >= 0.0 ? anterior : Vec3(-anterior);
  return (std::cos(angle) * a + std::sin(angle) * superior).normalized();
}

}  // namespace hipfai::geometry
