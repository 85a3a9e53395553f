#include "bench/radial_probe.h"

#include "bench/peer_embree.h"
#include "bench/scenarios.h"
#include "bench/timing.h"
#include "contact/detail/ablation.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_table.h"
#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
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

double min_distance(const geometry::TriMesh& mesh, const Eigen::Vector3d& centre) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& v : mesh.vertices) best = std::min(best, (v - centre).norm());
  return best;
}

double max_distance(const geometry::TriMesh& mesh, const Eigen::Vector3d& centre) {
  double best = 0.0;
  for (const auto& v : mesh.vertices) best = std::max(best, (v - centre).norm());
  return best;
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
  const TimingStats embree = time_repeated([&] { reference = caster.query(s.mobile, s.pose(), s.configuration, options.threads); },
                                           options.repeats, options.repeats, 1e12);
  auto vertices_of = [](const contact::PenetrationResult& r) {
    std::vector<std::int32_t> v;
    for (const auto& p : r.pairs) v.push_back(p.mobile_vertex);
    return v;
  };
  struct Variant {
    contact::RadialMapping mapping;
    bool cull;
  };
  // The cube mapping also without radial spans (every vertex tested): the culling's own effect.
  for (const Variant variant : {Variant{contact::RadialMapping::kCube, true}, Variant{contact::RadialMapping::kCube, false},
                                Variant{contact::RadialMapping::kCartesian, true},
                                Variant{contact::RadialMapping::kSpherical, true}}) {
    const auto mapping = variant.mapping;
    const std::string name = std::string("radial_") + contact::to_string(mapping) + (variant.cull ? "" : " (no spans)");
    contact::RadialTableOptions table_options;
    table_options.mapping = mapping;
    // As in the full benchmark: about one cell per fixed triangle.
    table_options.table_size = std::max<std::int64_t>(4096, static_cast<std::int64_t>(s.fixed.num_triangles()));
    contact::RadialTable table;
    const TimingStats pre = time_repeated([&] { table = contact::build_radial_table(s.fixed, s.centre, table_options); },
                                          1, 1, 0.0);
    contact::RadialQueryOptions q;
    q.configuration = s.configuration;
    q.num_threads = options.threads;
    contact::detail::RadialAblation ablation;
    ablation.cull = variant.cull;
    contact::PenetrationResult result;
    const TimingStats query =
        time_repeated([&] { result = contact::detail::radial_segmenting(table, s.fixed, posed, q, ablation); },
                                            options.repeats, options.repeats, 1e12);
    const bool same = vertices_of(result) == vertices_of(reference);
    if (!same) report.mismatched.push_back(name);
    out << "| " << name << " | " << ms(pre.median_ms) << " | " << ms(query.median_ms)
        << " [" << ms(query.min_ms) << "-" << ms(query.max_ms) << "] | " << result.pairs.size() << " | "
        << table.always_candidates.size() << " | " << ms(mean_candidates(table, posed)) << " | " << (same ? "yes" : "NO")
        << " |\n";
  }
  std::string spans_note;
  {
    // The body pair prepared once (contact::RadialPoseQuery): takes the pose, poses what it keeps.
    contact::RadialTableOptions table_options;
    table_options.table_size = std::max<std::int64_t>(4096, static_cast<std::int64_t>(s.fixed.num_triangles()));
    const contact::RadialTable table = contact::build_radial_table(s.fixed, s.centre, table_options);
    contact::RadialQueryOptions q;
    q.configuration = s.configuration;
    q.num_threads = options.threads;
    std::unique_ptr<contact::RadialPoseQuery> prepared;
    const TimingStats pre = time_repeated([&] { prepared = std::make_unique<contact::RadialPoseQuery>(table, s.fixed, s.mobile, q); },
                                          1, 1, 0.0);
    contact::PenetrationResult result;
    const TimingStats query = time_repeated([&] { result = prepared->query(s.pose()); }, options.repeats, options.repeats, 1e12);
    const bool same = vertices_of(result) == vertices_of(reference);
    if (!same) report.mismatched.push_back("radial_cube_pose");
    spans_note = "radial spans (cube table): mobile within " + ms(min_distance(s.mobile, s.centre)) + "-" +
                 ms(max_distance(s.mobile, s.centre)) + " mm of O, fixed span " + ms(table.spans.lo) + "-" +
                 ms(table.spans.hi) + " mm (" + std::to_string(std::count(table.spans.triangle_hi.begin(), table.spans.triangle_hi.end(), contact::RadialSpans::kInfinity)) +
                 " triangles without a span), cap half-angle " +
                 (table.spans.cap_cos > -1.0 ? ms(std::acos(table.spans.cap_cos) * 180.0 / 3.14159265358979323846) : std::string("none")) + " deg\n";
    out << "| radial_cube_pose (" << prepared->num_kept_vertices() << " kept) | " << ms(pre.median_ms) << " | "
        << ms(query.median_ms) << " [" << ms(query.min_ms) << "-" << ms(query.max_ms) << "] | " << result.pairs.size()
        << " | " << table.always_candidates.size() << " | - | " << (same ? "yes" : "NO") << " |\n";
  }
  out << "| embree | - | " << ms(embree.median_ms) << " [" << ms(embree.min_ms) << "-" << ms(embree.max_ms)
      << "] | " << reference.pairs.size() << " | - | - | - |\n";
  out << "\n" << spans_note;
  report.table = out.str();
  return report;
}

}  // namespace hipfai::bench
