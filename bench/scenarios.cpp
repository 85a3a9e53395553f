#include "bench/scenarios.h"

#include "contact/range_finder.h"
#include "core/error.h"
#include "geometry/hip_generator.h"
#include "geometry/mesh_io.h"
#include "geometry/primitive_meshes.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <utility>

namespace hipfai::bench {

using Eigen::Vector3d;

Eigen::Isometry3d Scenario::pose() const {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(angle_deg * std::numbers::pi / 180.0, axis).toRotationMatrix();
  X.translation() = centre - X.linear() * centre + translation_mm;
  return X;
}

geometry::TriMesh Scenario::posed_mobile() const { return transformed(mobile, pose()); }

geometry::TriMesh transformed(const geometry::TriMesh& mesh, const Eigen::Isometry3d& transform) {
  geometry::TriMesh out;
  out.triangles = mesh.triangles;
  out.vertices.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) out.vertices.push_back(transform * v);
  return out;
}

geometry::TriMesh subdivide_midpoint(const geometry::TriMesh& mesh, int times) {
  geometry::TriMesh current;
  current.vertices = mesh.vertices;
  current.triangles = mesh.triangles;
  for (int pass = 0; pass < times; ++pass) {
    geometry::TriMesh next;
    next.vertices = current.vertices;
    next.triangles.reserve(4 * current.triangles.size());
    std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> midpoint;
    auto mid = [&](std::int32_t a, std::int32_t b) {
      const auto key = a < b ? std::make_pair(a, b) : std::make_pair(b, a);
      const auto found = midpoint.find(key);
      if (found != midpoint.end()) return found->second;
      const auto index = static_cast<std::int32_t>(next.vertices.size());
      next.vertices.push_back(0.5 * (current.vertices[static_cast<std::size_t>(a)] +
                                     current.vertices[static_cast<std::size_t>(b)]));
      midpoint.emplace(key, index);
      return index;
    };
    for (const auto& t : current.triangles) {
      const std::int32_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      next.triangles.push_back({t[0], ab, ca});
      next.triangles.push_back({ab, t[1], bc});
      next.triangles.push_back({ca, bc, t[2]});
      next.triangles.push_back({ab, bc, ca});
    }
    current = std::move(next);
  }
  return current;
}

Scenario make_sphere_cube(int sphere_level) {
  if (sphere_level < 2 || sphere_level > 8) throw_error("sphere_cube: sphere level must be in 2..8");
  // Thesis Table 2: cube faces of 98, 386, 1 538, 6 146, 24 578 vertices (4..64 divisions).
  const int divisions = std::min(64, 4 << (sphere_level - 2));
  constexpr double kRadiusMm = 25.0;
  // Cap area fraction (1 - h / R) / 2 = 0.17 gives the bottom face at h = 0.66 R.
  constexpr double kCapBottom = 0.66;
  Scenario s;
  s.family = "sphere_cube";
  s.name = "sphere_cube_L" + std::to_string(sphere_level);
  s.level = sphere_level;
  s.radial = true;
  s.mobile = geometry::make_octasphere(Vector3d::Zero(), kRadiusMm, sphere_level);
  s.fixed = geometry::make_box(Vector3d(-kRadiusMm, -kRadiusMm, kCapBottom * kRadiusMm),
                               Vector3d(kRadiusMm, kRadiusMm, (2.0 + kCapBottom) * kRadiusMm), divisions);
  s.centre = Vector3d::Zero();
  s.axis = Vector3d(1.0, 2.0, 3.0).normalized();
  s.angle_deg = 23.0;
  s.configuration = contact::RadialConfiguration::kMobileInsideFixed;
  return s;
}

geometry::HipModel make_coarse_hip(double edge_mm) {
  geometry::HipParameters parameters;
  parameters.ce_deg = 30.0;
  parameters.alpha_deg = 60.0;  // a cam, so that impingement happens within the range
  parameters.edge_mm = edge_mm;
  return geometry::generate_hip(parameters).model;
}

namespace {

// The rotation that limits first (the smaller of the two exact ranges) plus a margin, so the
// pose penetrates. Throws when neither direction is limited.
std::pair<Vector3d, double> impinging_pose(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                                           const Vector3d& centre, const std::vector<Vector3d>& axes,
                                           double margin_deg) {
  for (const auto& axis : axes) {
    const auto range = contact::range_of_motion(fixed, mobile, centre, axis);
    if (range.status != contact::QueryStatus::kOk) continue;
    const double ccw = range.anticlockwise_deg, cw = range.clockwise_deg;
    if (std::min(ccw, cw) >= 180.0) continue;
    return ccw <= cw ? std::make_pair(axis.normalized(), ccw + margin_deg)
                     : std::make_pair(axis.normalized(), -(cw + margin_deg));
  }
  throw_error("scenarios: no impinging rotation found about the candidate axes");
}

}  // namespace

Scenario make_lever_stone(int stone_level, int lever_divisions) {
  if (stone_level < 1 || lever_divisions < 1) throw_error("lever_stone: stone level and lever divisions must be >= 1");
  Scenario s;
  s.family = "lever_stone";
  s.name = "lever_stone";
  s.radial = false;
  s.fixed = geometry::make_octasphere(Vector3d(45, 18, 0), 10.0, stone_level);
  s.mobile = geometry::make_box(Vector3d(-60, -2.5, -4), Vector3d(60, 2.5, 4), lever_divisions);
  s.centre = Vector3d::Zero();
  const auto [axis, angle] = impinging_pose(s.fixed, s.mobile, s.centre, {Vector3d::UnitZ()}, 2.0);
  s.axis = axis;
  s.angle_deg = angle;
  return s;
}

Scenario make_torus_rough(int wheel_segments, int tube_segments, double ground_spacing_mm) {
  const double cells_x = 60.0 / ground_spacing_mm, cells_y = 24.0 / ground_spacing_mm;
  if (wheel_segments < 3 || tube_segments < 3 || !(ground_spacing_mm > 0.0) ||
      std::abs(cells_x - std::round(cells_x)) > 1e-9 || std::abs(cells_y - std::round(cells_y)) > 1e-9) {
    throw_error("torus_rough: need >= 3 wheel and tube segments and a ground spacing dividing 60 and 24 mm");
  }
  Scenario s;
  s.family = "torus_rough";
  s.name = "torus_rough";
  s.radial = false;
  // Wheel about the y axis through (0, 0, 25): its lowest rim point touches z = 0.
  Eigen::Isometry3d to_wheel = Eigen::Isometry3d::Identity();
  to_wheel.linear() = Eigen::AngleAxisd(std::numbers::pi / 2.0, Vector3d::UnitX()).toRotationMatrix();
  to_wheel.translation() = Vector3d(0, 0, 25);
  s.mobile = transformed(geometry::make_torus(Vector3d::Zero(), 20.0, 5.0, wheel_segments, tube_segments), to_wheel);
  // Rough ground: a height field over [-30, 30] x [-12, 12] mm (0.5 mm spacing in the benchmark),
  // a sum of incommensurate waves between -0.6 and +1 mm; triangles counter-clockwise seen from
  // above (outward normal +z: the solid is the ground below).
  const int nx = static_cast<int>(std::lround(cells_x)) + 1, ny = static_cast<int>(std::lround(cells_y)) + 1;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = -30.0 + ground_spacing_mm * i, y = -12.0 + ground_spacing_mm * j;
      const double z = 0.2 + 0.5 * std::sin(0.9 * x + 0.3) * std::cos(0.7 * y) + 0.3 * std::sin(2.3 * x - 1.7 * y);
      s.fixed.vertices.emplace_back(x, y, z);
    }
  }
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const std::int32_t a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
      s.fixed.triangles.push_back({a, b, c});
      s.fixed.triangles.push_back({a, c, d});
    }
  }
  s.centre = Vector3d(0, 0, 25);
  s.axis = Vector3d::UnitY();
  s.angle_deg = 7.0;
  return s;
}

std::vector<Scenario> make_striking_hip(const geometry::HipModel& hip, int max_level) {
  const auto& femur = hip.tissue("femur_bone");
  const auto& acetabulum = hip.tissue("acetabular_bone");
  // Abduction (about the anteroposterior axis) brings the neck against the rim first.
  const auto [axis, angle] = impinging_pose(acetabulum, femur, hip.hjc_mm,
                                            {hip.axes.flexion_axis, hip.axes.adduction_axis,
                                             hip.axes.internal_rotation_axis}, 6.0);
  std::vector<Scenario> out;
  for (int level = 0; level <= max_level; ++level) {
    Scenario s;
    s.family = "striking_hip";
    s.name = "striking_hip_L" + std::to_string(level);
    s.level = level;
    s.radial = false;
    s.fixed = subdivide_midpoint(acetabulum, level);
    s.mobile = subdivide_midpoint(femur, level);
    s.centre = hip.hjc_mm;
    s.axis = axis;
    s.angle_deg = angle;
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<Scenario> make_cartilage(const geometry::HipModel& hip, int max_level) {
  const geometry::TriMesh socket =
      geometry::merge_meshes({&hip.tissue("acetabular_cartilage"), &hip.tissue("labrum")});
  const auto& cartilage = hip.tissue("femoral_cartilage");
  std::vector<Scenario> out;
  for (int level = 0; level <= max_level; ++level) {
    Scenario s;
    s.family = "cartilage";
    s.name = "cartilage_L" + std::to_string(level);
    s.level = level;
    s.radial = true;
    s.fixed = subdivide_midpoint(socket, level);
    s.mobile = subdivide_midpoint(cartilage, level);
    s.centre = hip.hjc_mm;
    s.axis = hip.axes.flexion_axis.normalized();
    s.angle_deg = 15.0;
    s.translation_mm = 0.6 * hip.superior.normalized();  // sliding: the head pushed into the socket
    s.configuration = contact::RadialConfiguration::kMobileInsideFixed;
    out.push_back(std::move(s));
  }
  return out;
}

Scenario make_striking_real_ct(const std::string& lhdl_dir) {
  const std::string json_path = lhdl_dir + "/hip.json";
  std::ifstream in(json_path);
  if (!in) throw_error(json_path, ": cannot open the real-bone description");
  nlohmann::json description;
  try {
    description = nlohmann::json::parse(in);
  } catch (const std::exception& error) {
    throw_error(json_path, ": ", error.what());
  }
  const auto hjc = description.at("hjc_mm").get<std::vector<double>>();
  Scenario s;
  s.family = "striking_real_ct";
  s.name = "striking_real_ct";
  s.radial = false;
  s.fixed = geometry::read_mesh(lhdl_dir + "/" + description.at("tissues").at("pelvis_bone").get<std::string>());
  s.mobile = geometry::read_mesh(lhdl_dir + "/" + description.at("tissues").at("femur_bone").get<std::string>());
  s.centre = Vector3d(hjc.at(0), hjc.at(1), hjc.at(2));
  const auto [axis, angle] = impinging_pose(s.fixed, s.mobile, s.centre,
                                            {Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()}, 3.0);
  s.axis = axis;
  s.angle_deg = angle;
  return s;
}

}  // namespace hipfai::bench
