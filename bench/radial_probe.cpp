#include "bench/radial_probe.h"

#include "bench/peer_embree.h"
#include "bench/scenarios.h"
#include "bench/timing.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_table.h"
#include "core/error.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace hipfai::bench {

namespace {

Scenario probe_scenario(const RadialProbeOptions& options) {
  if (options.family == "sphere_cube") {
    if (options.level < 2 || options.level > 8) throw_error("bench radial: --level must be 2..8 for sphere_cube");
    return make_sphere_cube(options.level);
  }
  if (options.family == "cartilage") {
    if (options.level < 0 || options.level > 3) throw_error("bench radial: --level must be 0..3 for cartilage");
    auto levels = make_cartilage(make_coarse_hip(), options.level);
    return levels.back();
  }
  throw_error("bench radial: unknown --scenario '", options.family, "' (cartilage or sphere_cube)");
}

std::string ms(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4g", value);
  return buffer;
}

// Mean number of fixed triangles a vertex's ray is tested against (its cell + the always list).
double mean_candidates(const contact::RadialTable& table, const geometry::TriMesh& posed) {
  double total = 0.0;
  for (const auto& v : posed.vertices) {
    const Eigen::Vector3d direction = v - table.centre;
    if (direction.isZero(0.0)) continue;
    total += static_cast<double>(table.cell(contact::cell_of_direction(table.grid, direction)).size() +
                                 table.always_candidates.size());
  }
  return posed.vertices.empty() ? 0.0 : total / static_cast<double>(posed.vertices.size());
}

}  // namespace

RadialProbeReport run_radial_probe(const RadialProbeOptions& options) {
  const Scenario s = probe_scenario(options);
  const geometry::TriMesh posed = s.posed_mobile();
  std::ostringstream out;
  RadialProbeReport report;
  out << s.name << ": " << s.mobile.num_vertices() << " mobile vertices, " << s.fixed.num_triangles()
      << " fixed triangles, " << options.threads << " thread(s)\n\n"
      << "| method | pre ms | query ms (median [min-max]) | reported | always-checked | candidates per vertex | same vertices as embree |\n"
      << "|---|---|---|---|---|---|---|\n";
  EmbreeRadialCaster caster(s.fixed, s.centre, options.threads);
  contact::PenetrationResult reference;
  const TimingStats embree = time_repeated([&] { reference = caster.query(posed, s.configuration, options.threads); },
                                           options.repeats, options.repeats, 1e12);
  auto vertices_of = [](const contact::PenetrationResult& r) {
    std::vector<std::int32_t> v;
    for (const auto& p : r.pairs) v.push_back(p.mobile_vertex);
    return v;
  };
  for (auto mapping : {contact::RadialMapping::kCube, contact::RadialMapping::kCartesian,
                       contact::RadialMapping::kSpherical}) {
    contact::RadialTableOptions table_options;
    table_options.mapping = mapping;
    // As in the full benchmark: about two cells per fixed triangle.
    table_options.table_size = std::max<std::int64_t>(4096, 2 * static_cast<std::int64_t>(s.fixed.num_triangles()));
    contact::RadialTable table;
    const TimingStats pre = time_repeated([&] { table = contact::build_radial_table(s.fixed, s.centre, table_options); },
                                          1, 1, 0.0);
    contact::RadialQueryOptions q;
    q.configuration = s.configuration;
    q.num_threads = options.threads;
    contact::PenetrationResult result;
    const TimingStats query = time_repeated([&] { result = contact::radial_segmenting(table, s.fixed, posed, q); },
                                            options.repeats, options.repeats, 1e12);
    const bool same = vertices_of(result) == vertices_of(reference);
    if (!same) report.mismatched.push_back(std::string("radial_") + contact::to_string(mapping));
    out << "| radial_" << contact::to_string(mapping) << " | " << ms(pre.median_ms) << " | " << ms(query.median_ms)
        << " [" << ms(query.min_ms) << "-" << ms(query.max_ms) << "] | " << result.pairs.size() << " | "
        << table.always_candidates.size() << " | " << ms(mean_candidates(table, posed)) << " | " << (same ? "yes" : "NO")
        << " |\n";
  }
  out << "| embree | - | " << ms(embree.median_ms) << " [" << ms(embree.min_ms) << "-" << ms(embree.max_ms)
      << "] | " << reference.pairs.size() << " | - | - | - |\n";
  report.table = out.str();
  return report;
}

}  // namespace hipfai::bench
