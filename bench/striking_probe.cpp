#include "bench/striking_probe.h"

#include "bench/bench_format.h"
#include "bench/peer_fcl.h"
#include "bench/scenarios.h"
#include "bench/timing.h"
#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "contact/detail/ablation.h"
#include "core/error.h"

#include <cmath>
#include <sstream>

namespace hipfai::bench {

namespace {

Scenario probe_scenario(const StrikingProbeOptions& options) {
  if (options.family == "hip") {
    if (options.level < 0 || options.level > 3) throw_error("bench striking: --level must be 0..3 for hip");
    return make_striking_hip(make_coarse_hip(), options.level).back();
  }
  if (options.family == "real_ct") return make_striking_real_ct(options.lhdl_dir);
  throw_error("bench striking: unknown --scenario '", options.family, "' (hip or real_ct)");
}

bool same_pairs(const contact::PenetrationResult& a, const contact::PenetrationResult& b) {
  if (a.status != b.status || a.pairs.size() != b.pairs.size()) return false;
  for (std::size_t i = 0; i < a.pairs.size(); ++i) {
    const auto& p = a.pairs[i];
    const auto& q = b.pairs[i];
    if (p.mobile_vertex != q.mobile_vertex || p.fixed_triangle != q.fixed_triangle || p.depth_mm != q.depth_mm ||
        p.angle_deg != q.angle_deg) {
      return false;
    }
  }
  return true;
}

// Mobile vertices (posed) that pass the distance filter, that reach a non-empty cell, and the
// mean number of candidates of their cells, and how many of those lie in an outside region.
struct CellCounts {
  std::size_t within_distance = 0, with_candidates = 0, in_outside_region = 0;
  double mean_candidates = 0.0;
};

CellCounts cell_counts(const contact::CylindricalTable& table, const geometry::TriMesh& posed) {
  CellCounts counts;
  double total = 0.0;
  for (const auto& p : posed.vertices) {
    const contact::Vec3 local = table.frame().to_local(p);
    if (!table.distance_may_touch(local.norm())) continue;
    ++counts.within_distance;
    const double r = std::hypot(local.x(), local.y());
    if (!table.has_candidates(r, local.z())) continue;
    ++counts.with_candidates;
    table.for_each_candidate(r, local.z(), [&](std::int32_t) { total += 1.0; });
    const contact::Cylindrical cyl = contact::to_cylindrical(local);
    if (table.outside_every_shell(cyl.r, cyl.z, cyl.theta)) ++counts.in_outside_region;
  }
  if (counts.with_candidates > 0) counts.mean_candidates = total / static_cast<double>(counts.with_candidates);
  return counts;
}

}  // namespace

StrikingProbeReport run_striking_probe(const StrikingProbeOptions& options) {
  const Scenario s = probe_scenario(options);
  StrikingProbeReport report;
  std::ostringstream out;
  out << s.name << ": " << s.mobile.num_vertices() << " mobile vertices, " << s.fixed.num_triangles()
      << " fixed triangles, pose " << fmt(s.angle_deg, 4) << " deg, " << options.threads << " thread(s)\n\n"
      << "| method | query ms (median [min-max]) | pairs | same pairs as every-candidate |\n|---|---|---|---|\n";
  const contact::CylindricalTable table = contact::CylindricalTable::build(s.fixed, s.centre, s.axis, {}, &s.mobile);
  const int repeats = options.repeats;
  contact::CylindricalQueryOptions q;
  q.num_threads = options.threads;
  contact::detail::CylindricalAblation every;
  every.angular_walk = false;
  every.outside_regions = false;
  every.mobile_clusters = false;
  contact::detail::CylindricalAblation walk = every;
  walk.angular_walk = true;

  contact::PenetrationResult reference;
  const TimingStats reference_time = time_repeated(
      [&] { reference = contact::detail::cylindrical_segmenting(table, s.posed_mobile(), q, every); }, repeats, repeats, 1e12);
  const auto row = [&](const std::string& name, const TimingStats& time, const contact::PenetrationResult& result) {
    const bool same = same_pairs(result, reference);
    if (!same) report.mismatched.push_back(name);
    out << "| " << name << " | " << fmt_ms(time) << " | " << result.pairs.size() << " | " << (same ? "yes" : "NO") << " |\n";
  };
  row("cylindrical, posed copy, every candidate", reference_time, reference);
  contact::detail::CylindricalAblation regions = walk;
  regions.outside_regions = true;
  contact::detail::CylindricalAblation clustered = regions;
  clustered.mobile_clusters = true;
  const Eigen::Isometry3d pose = s.pose();
  contact::PenetrationResult result;
  TimingStats time;
  const std::pair<const char*, const contact::detail::CylindricalAblation*> methods[] = {
      {"every candidate", &every},
      {"angular walk", &walk},
      {"angular walk + outside regions", &regions},
      {"angular walk + outside regions + the table's mobile clusters", &clustered}};
  for (const auto& [method, ablation] : methods) {
    if (ablation != &every) {
      time = time_repeated([&] { result = contact::detail::cylindrical_segmenting(table, s.posed_mobile(), q, *ablation); },
                           repeats, repeats, 1e12);
      row(std::string("cylindrical, posed copy, ") + method, time, result);
    }
    time = time_repeated([&] { result = contact::detail::cylindrical_segmenting(table, s.mobile, pose, q, *ablation); },
                         repeats, repeats, 1e12);
    row(std::string("cylindrical, pose given, ") + method, time, result);
  }
  const contact::VertexClusters clusters = contact::VertexClusters::build(s.mobile);
  time = time_repeated([&] { result = contact::detail::cylindrical_segmenting(table, clusters, pose, q, regions); }, repeats,
                       repeats, 1e12);
  row("cylindrical, vertex clusters at rest and pose, angular walk + outside regions", time, result);
  geometry::TriMesh posed;
  time = time_repeated([&] { posed = s.posed_mobile(); }, repeats, repeats, 1e12);
  out << "| (posing a copy of the mobile mesh) | " << fmt_ms(time) << " | - | - |\n";
  const FclModel fixed_model(s.fixed, FclBoundingVolume::kObbRss);
  const FclModel mobile_model(s.mobile, FclBoundingVolume::kObbRss);
  FclCollideResult fcl;
  time = time_repeated([&] { fcl = fixed_model.collide(mobile_model, pose); }, repeats, repeats, 1e12);
  out << "| fcl_OBBRSS, all contacts (1 thread) | " << fmt_ms(time) << " | " << fcl.triangle_pairs.size() << " triangle pairs | - |\n";
  const CellCounts counts = cell_counts(table, posed);
  out << "\nmobile vertices within the fixed distance range: " << counts.within_distance
      << "; in a non-empty ring cell: " << counts.with_candidates << ", " << fmt(counts.mean_candidates)
      << " candidates per such vertex, " << counts.in_outside_region << " of them in an outside region ("
      << table.num_outside_regions() << " regions); table " << table.num_r_cells() << " x " << table.num_z_cells() << " cells of "
      << fmt(table.resolution_r_mm()) << " mm\n";
  report.table = out.str();
  return report;
}

}  // namespace hipfai::bench
