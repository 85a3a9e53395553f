#include "geometry/hjc.h"

#include "core/error.h"

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace hipfai::geometry {
namespace {

bool wants(const HjcRequest& request, const std::string& name) {
  return request.methods.empty() ||
         std::find(request.methods.begin(), request.methods.end(), name) != request.methods.end();
}

HjcMethodResult method_result(const std::string& name, bool ok, const std::string& message, const Vec3& center_mm,
                              double rms_mm, double max_mm) {
  HjcMethodResult r;
  r.name = name;
  r.ok = ok;
  r.message = message;
  r.center_mm = center_mm;
  r.rms_mm = rms_mm;
  r.max_mm = max_mm;
  return r;
}

HjcMethodResult from_sphere(const std::string& name, const SphereFit& fit) {
  HjcMethodResult r = method_result(name, fit.ok(), fit.message, fit.center_mm, fit.rms_mm, fit.max_abs_mm);
  r.radius_mm = fit.radius_mm;
  return r;
}

nlohmann::json vec(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

nlohmann::json number_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace

const std::vector<std::string>& hjc_method_names() {
  static const std::vector<std::string> names{"femoralheadsphere", "acetabulumsphere", "doublesphere",
                                              "dconst", "dref"};
  return names;
}

const HjcMethodResult& HjcResult::method(const std::string& name) const {
  for (const auto& m : methods) if (m.name == name) return m;
  throw_error("HJC method '", name, "' was not computed");
}

HjcResult estimate_hjc(const HjcRequest& request) {
  if (request.femur == nullptr || request.pelvis == nullptr) {
    throw_error("hjc: both a femur and a pelvis are needed");
  }
  validate_mesh(*request.femur, request.femur_name);
  validate_mesh(*request.pelvis, request.pelvis_name);
  for (const auto& name : request.methods) {
    const auto& all = hjc_method_names();
    if (std::find(all.begin(), all.end(), name) == all.end()) {
      throw_error("hjc: unknown method '", name, "' (femoralheadsphere, acetabulumsphere, doublesphere, dconst, dref)");
    }
  }
  HjcResult result;
  result.head = request.head_region
                    ? *request.head_region
                    : find_femoral_head(*request.femur, request.pelvis, request.head_options, request.femur_name);
  if (result.head.patch.num_vertices() < 4) {
    throw_error(request.femur_name, ": the femoral head region has ", result.head.patch.num_vertices(),
                " vertices (need at least 4)");
  }
  const SphereFit head_fit = fit_sphere(result.head.patch.vertices);
  if (!head_fit.ok()) throw_error(request.femur_name, ": femoral head region: ", head_fit.message);

  result.lunate = request.lunate_region
                      ? *request.lunate_region
                      : find_lunate_surface(*request.pelvis, head_fit.center_mm, head_fit.radius_mm,
                                            request.lunate_options, request.pelvis_name);
  if (result.lunate.patch.num_vertices() < 4) {
    throw_error(request.pelvis_name, ": the lunate region has ", result.lunate.patch.num_vertices(),
                " vertices (need at least 4)");
  }
  const SphereFit lunate_fit = fit_sphere(result.lunate.patch.vertices);
  if (!lunate_fit.ok()) throw_error(request.pelvis_name, ": lunate region: ", lunate_fit.message);
  result.head_source = result.head.source;
  result.lunate_source = result.lunate.source;
  result.head_vertices = result.head.patch.num_vertices();
  result.lunate_vertices = result.lunate.patch.num_vertices();

  for (const auto& name : hjc_method_names()) {
    if (!wants(request, name)) continue;
    if (name == "femoralheadsphere") {
      result.methods.push_back(from_sphere(name, head_fit));
    } else if (name == "acetabulumsphere") {
      result.methods.push_back(from_sphere(name, lunate_fit));
    } else if (name == "doublesphere") {
      const ConcentricSphereFit fit = fit_concentric_spheres(result.head.patch.vertices, result.lunate.patch.vertices);
      HjcMethodResult r = method_result(name, fit.ok(), fit.message, fit.center_mm, fit.rms_mm, fit.max_abs_mm);
      r.radius_mm = fit.radius_a_mm;
      r.radius_b_mm = fit.radius_b_mm;
      result.methods.push_back(r);
    } else {
      const bool constant = name == "dconst";
      if (result.head.patch.num_triangles() == 0) {
        throw_error(request.femur_name, ": the femoral head region has no triangles: the functional methods need its surface");
      }
      const Vec3 axis = request.femur_long_axis ? *request.femur_long_axis : principal_axis(*request.femur);
      const FunctionalHjc fit = functional_hjc(
          result.head.patch, result.head.normals, result.lunate.patch.vertices, head_fit.center_mm, axis,
          constant ? FunctionalTarget::kConstant : FunctionalTarget::kReference,
          lunate_fit.radius_mm - head_fit.radius_mm, request.functional);
      HjcMethodResult r =
          method_result(name, fit.ok, fit.message, fit.center_mm, fit.distance_rms_mm, fit.distance_max_mm);
      r.residual_motion_rms_mm = fit.residual_motion_rms_mm;
      r.residual_motion_max_mm = fit.residual_motion_max_mm;
      r.poses = fit.poses_used;
      if (constant) r.target_distance_mm = fit.target_mm;
      result.methods.push_back(r);
    }
  }
  return result;
}

std::string hjc_result_json(const HjcResult& result, int indent) {
  nlohmann::json methods = nlohmann::json::object();
  for (const auto& m : result.methods) {
    nlohmann::json j;
    j["ok"] = m.ok;
    if (!m.message.empty()) j["message"] = m.message;
    j["center_mm"] = vec(m.center_mm);
    const bool functional = m.name == "dconst" || m.name == "dref";
    j["radius_mm"] = functional ? nlohmann::json(nullptr) : number_or_null(m.radius_mm);
    j["rms_mm"] = m.rms_mm;
    j["max_mm"] = m.max_mm;
    if (m.name == "doublesphere") {
      j["radius_head_mm"] = m.radius_mm;
      j["radius_acetabulum_mm"] = m.radius_b_mm;
    }
    if (functional) {
      j["residual_kind"] = "inter-articular distance minus its target, over all poses";
      j["residual_motion_rms_mm"] = number_or_null(m.residual_motion_rms_mm);
      j["residual_motion_max_mm"] = number_or_null(m.residual_motion_max_mm);
      j["poses"] = m.poses;
      if (m.name == "dconst") j["target_distance_mm"] = m.target_distance_mm;
    } else {
      j["residual_kind"] = "distance to the fitted sphere";
    }
    methods[m.name] = j;
  }
  nlohmann::json out;
  out["methods"] = methods;
  out["units"] = "mm";
  out["regions"] = {{"femoral_head", {{"source", result.head_source}, {"vertices", result.head_vertices}}},
                    {"lunate", {{"source", result.lunate_source}, {"vertices", result.lunate_vertices}}}};
  return out.dump(indent);
}

}  // namespace hipfai::geometry
