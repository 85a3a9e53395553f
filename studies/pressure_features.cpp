#include "studies/pressure_features.h"

#include "contact/radial_table.h"
#include "contact/ray_triangle.h"
#include "core/error.h"
#include "core/hash.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

namespace hipfai::studies {

namespace {

// Distance from the centre to the farthest crossing along unit `direction`, or 0 for a miss.
double farthest_crossing_mm(const contact::RadialTable& table, const geometry::TriMesh& mesh,
                            const contact::Vec3& direction) {
  double farthest = 0.0;
  const auto visit = [&](std::int32_t index) {
    const auto& triangle = mesh.triangles[static_cast<std::size_t>(index)];
    const contact::RayCrossing crossing = contact::ray_triangle_crossing(
        direction, mesh.vertices[static_cast<std::size_t>(triangle[0])] - table.centre,
        mesh.vertices[static_cast<std::size_t>(triangle[1])] - table.centre,
        mesh.vertices[static_cast<std::size_t>(triangle[2])] - table.centre);
    if (crossing.hit) farthest = std::max(farthest, crossing.t);
  };
  for (const std::int32_t index : table.cell(contact::cell_of_direction(table.grid, direction))) visit(index);
  for (const std::int32_t index : table.always_candidates) visit(index);
  return farthest;
}

}  // namespace

HipFeatures extract_hip_features(const geometry::HipModel& model, const FeatureGrid& grid) {
  if (grid.polar_steps < 1 || grid.azimuth_steps < 1 || grid.tissues.empty()) {
    throw_error("feature grid ", grid.describe(), ": empty");
  }
  const auto start = std::chrono::steady_clock::now();
  // Directions in the hip frame, mapped to the model's coordinates through its axes.
  std::vector<contact::Vec3> directions;
  directions.reserve(static_cast<std::size_t>(grid.polar_steps * grid.azimuth_steps));
  for (int i = 0; i < grid.polar_steps; ++i) {
    const double theta = (i + 0.5) * std::numbers::pi / grid.polar_steps;
    for (int j = 0; j < grid.azimuth_steps; ++j) {
      const double phi = (j + 0.5) * 2.0 * std::numbers::pi / grid.azimuth_steps;
      directions.push_back((std::sin(theta) * std::cos(phi) * model.axes.flexion_axis +
                            std::sin(theta) * std::sin(phi) * model.axes.adduction_axis +
                            std::cos(theta) * model.axes.internal_rotation_axis)
                               .normalized());
    }
  }
  HipFeatures features;
  features.values.resize(grid.num_features());
  Eigen::Index next = 0;
  for (const std::string& name : grid.tissues) {
    const auto found = model.tissues.find(name);
    if (found == model.tissues.end()) {
      throw_error("hip (CE ", model.parameters.ce_deg, ", alpha ", model.parameters.alpha_deg, ") has no tissue '",
                  name, "', which the feature grid samples");
    }
    const geometry::TriMesh& mesh = found->second;
    // About one triangle per cell (thesis §3.3.3.1.4's advice for table size).
    const contact::RadialTableOptions options{contact::RadialMapping::kSpherical,
                                              std::max<std::int64_t>(64, static_cast<std::int64_t>(mesh.num_triangles()))};
    const contact::RadialTable table = contact::build_radial_table(mesh, model.hjc_mm, options);
    for (const contact::Vec3& direction : directions) {
      const double r = farthest_crossing_mm(table, mesh, direction);
      if (r == 0.0) ++features.misses;
      features.values(next++) = r;
    }
  }
  features.extraction_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return features;
}

std::string hip_content_hash(const geometry::HipModel& model, const FeatureGrid& grid) {
  Hasher hasher;
  for (int axis = 0; axis < 3; ++axis) hasher.add(model.hjc_mm(axis));
  for (const auto* v : {&model.axes.flexion_axis, &model.axes.adduction_axis, &model.axes.internal_rotation_axis}) {
    for (int axis = 0; axis < 3; ++axis) hasher.add((*v)(axis));
  }
  for (const std::string& name : grid.tissues) {
    hasher.add(name);
    const auto found = model.tissues.find(name);
    if (found == model.tissues.end()) continue;
    for (const auto& vertex : found->second.vertices) {
      for (int axis = 0; axis < 3; ++axis) hasher.add(vertex(axis));
    }
    for (const auto& triangle : found->second.triangles) {
      for (int corner = 0; corner < 3; ++corner) hasher.add(static_cast<std::int64_t>(triangle[corner]));
    }
  }
  return hasher.hex();
}

}  // namespace hipfai::studies
