#include "contact/hybrid_segmenting.h"

#include <algorithm>
#include <string>

namespace hipfai::contact {

namespace {

HybridMethod method_of_band(const HybridOptions& options, std::size_t band) {
  if (!options.band_methods.empty()) return options.band_methods[band];
  return band % 2 == 0 ? HybridMethod::kRadial : HybridMethod::kCylindrical;
}

std::string check_options(const HybridOptions& options) {
  for (std::size_t i = 0; i < options.thresholds_mm.size(); ++i) {
    if (!(options.thresholds_mm[i] > 0.0) ||
        (i > 0 && !(options.thresholds_mm[i] > options.thresholds_mm[i - 1]))) {
      return "hybrid: thresholds must be positive and strictly increasing";
    }
  }
  if (!options.band_methods.empty() &&
      options.band_methods.size() != options.thresholds_mm.size() + 1) {
    return "hybrid: need one method per band (" + std::to_string(options.thresholds_mm.size() + 1) +
           "), got " + std::to_string(options.band_methods.size());
  }
  return {};
}

}  // namespace

HybridResult hybrid_segmenting(const CylindricalTable& cylindrical_table,
                               const RadialTable& radial_table, const geometry::TriMesh& fixed,
                               const geometry::TriMesh& posed_mobile, const HybridOptions& options) {
  HybridResult hybrid;
  if (const std::string problem = check_options(options); !problem.empty()) {
    hybrid.result.status = QueryStatus::kInvalidInput;
    hybrid.result.message = problem;
    return hybrid;
  }
  // Split the vertices: the queries read only the mobile vertices, so each part is a
  // vertex-only mesh, with a map back to the original indices.
  geometry::TriMesh part[2];
  std::vector<std::int32_t> original[2];
  hybrid.vertex_method.resize(posed_mobile.num_vertices());
  for (std::size_t v = 0; v < posed_mobile.num_vertices(); ++v) {
    const double distance = (posed_mobile.vertices[v] - radial_table.centre).norm();
    const auto band = static_cast<std::size_t>(
        std::upper_bound(options.thresholds_mm.begin(), options.thresholds_mm.end(), distance) -
        options.thresholds_mm.begin());
    const HybridMethod method = method_of_band(options, band);
    hybrid.vertex_method[v] = method;
    const int which = method == HybridMethod::kRadial ? 0 : 1;
    part[which].vertices.push_back(posed_mobile.vertices[v]);
    original[which].push_back(static_cast<std::int32_t>(v));
  }
  PenetrationResult results[2];
  if (!part[0].vertices.empty()) {
    results[0] = radial_segmenting(radial_table, fixed, part[0], options.radial);
  }
  if (!part[1].vertices.empty()) {
    results[1] = cylindrical_segmenting(cylindrical_table, part[1], options.cylindrical);
  }
  for (int which = 0; which < 2; ++which) {
    if (results[which].status == QueryStatus::kInvalidInput) {
      hybrid.result.status = QueryStatus::kInvalidInput;
      hybrid.result.message = results[which].message;
      return hybrid;
    }
    for (PenetrationPair pair : results[which].pairs) {
      pair.mobile_vertex = original[which][static_cast<std::size_t>(pair.mobile_vertex)];
      hybrid.result.pairs.push_back(pair);
    }
  }
  sort_by_mobile_vertex(hybrid.result.pairs);
  return hybrid;
}

}  // namespace hipfai::contact
