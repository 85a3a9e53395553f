#include "bench/collision_bench_targets.h"

#include "bench/bench_format.h"
#include "core/numbers.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace hipfai::bench {

namespace {

using hipfai::kNaN;

// The targets of the collision benchmark measured on its rows (collision_bench_targets.h).
class Targets {
 public:
  explicit Targets(const CollisionBenchResults& results)
      : results_(results),
        size_note_(results.quick ? " (quick sizes: indicative only, the targets are for ~100 k+ vertices)" : "") {}

  TargetVerdict fcl_all_contacts() const;
  TargetVerdict radial_vs_embree() const;
  TargetVerdict radial_vs_spatial_hashing() const;
  TargetVerdict rom_vs_stepping() const;
  TargetVerdict rom_every_hip_level() const;
  TargetVerdict radial_vs_embree_per_family() const;
  TargetVerdict pose_cache_vs_fcl() const;
  TargetVerdict bandwidth_floor() const;
  TargetVerdict exactness() const;

 private:
  // The scenario of `family` with the most vertices ("" when there is none).
  std::string largest(const std::string& family) const {
    const BenchRow* best = nullptr;
    for (const auto& r : results_.rows) {
      if (r.family == family && (best == nullptr || r.vertices > best->vertices)) best = &r;
    }
    return best == nullptr ? std::string() : best->scenario;
  }
  // The peer's median query time over ours on `scenario` (FCL has one thread: its 1-thread row
  // stands for 2); NaN when a row is missing.
  double query_ratio(const std::string& scenario, const std::string& peer, const std::string& ours, int threads) const {
    const BenchRow* p = find_row(results_.rows, scenario, peer, threads == 2 && peer.rfind("fcl", 0) == 0 ? 1 : threads);
    const BenchRow* o = find_row(results_.rows, scenario, ours, threads);
    if (p == nullptr || o == nullptr || !(o->query.median_ms > 0.0)) return kNaN;
    return p->query.median_ms / o->query.median_ms;
  }

  const CollisionBenchResults& results_;
  const std::string size_note_;
};

// The per-pose query against FCL collide-with-all-contacts on the largest scenario of each family.
TargetVerdict Targets::fcl_all_contacts() const {
  TargetVerdict t;
  t.target = "Per-pose query >= 50x faster than FCL collide-with-all-contacts (largest sizes)" + size_note_;
  bool met = true;
  std::ostringstream m;
  for (const std::string family : {"striking_hip", "striking_real_ct", "sphere_cube", "cartilage"}) {
    const std::string sc = largest(family);
    if (sc.empty()) continue;
    const std::string ours = family.rfind("striking", 0) == 0 ? "cylindrical_pose_cache" : "radial_cube";
    const double obbrss = query_ratio(sc, "fcl_OBBRSS", ours, 1);
    const double obb = query_ratio(sc, "fcl_OBB", ours, 1);
    const double worst = std::isnan(obb) ? obbrss : std::min(obbrss, obb);
    const double two = query_ratio(sc, "fcl_OBBRSS", ours, 2);
    met = met && worst >= 50.0;
    m << sc << " (" << find_row(results_.rows, sc, ours, 1)->vertices << " v): " << fmt(worst) << "x (1 thread), FCL/ours-2-threads "
      << fmt(two) << "x";
    if (family.rfind("striking", 0) == 0) {
      m << ", vs the one-pass query on the posed mesh " << fmt(query_ratio(sc, "fcl_OBBRSS", "cylindrical", 1)) << "x";
    }
    m << "; ";
  }
  t.met = met;
  t.measured = m.str();
  return t;
}

// The radial query against Embree's radial ray casting, with Embree's exactness.
TargetVerdict Targets::radial_vs_embree() const {
  TargetVerdict t;
  t.target = "Radial query >= 10x faster than Embree radial ray casting, identical results" + size_note_;
  bool met = true;
  std::ostringstream m;
  for (const std::string family : {"sphere_cube", "cartilage"}) {
    const std::string sc = largest(family);
    if (sc.empty()) continue;
    const double r1 = query_ratio(sc, "embree", "radial_cube", 1), r2 = query_ratio(sc, "embree", "radial_cube", 2);
    const BenchRow* e = find_row(results_.rows, sc, "embree", 1);
    const bool identical = e != nullptr && e->exact.false_negatives == 0 && e->exact.false_positives == 0;
    met = met && r1 >= 10.0 && identical;
    m << sc << ": " << fmt(r1) << "x (1 thread), " << fmt(r2) << "x (2 threads), Embree FN/FP vs oracle "
      << (e ? std::to_string(e->exact.false_negatives) + "/" + std::to_string(e->exact.false_positives) : "?")
      << ", max depth diff " << (e ? fmt(e->exact.max_depth_error_mm) : "?") << " mm; ";
  }
  t.met = met;
  t.measured = m.str();
  return t;
}

// The radial query against spatial hashing's main stage.
TargetVerdict Targets::radial_vs_spatial_hashing() const {
  TargetVerdict t;
  t.target = "Radial query >= 100x faster than spatial hashing's main stage (largest sphere-cube)" + size_note_;
  const std::string sc = largest("sphere_cube");
  const double tets = query_ratio(sc, "spatial_hash_tets", "radial_cube", 1);
  const double surface = query_ratio(sc, "spatial_hash_surface", "radial_cube", 1);
  t.met = tets >= 100.0;
  t.measured = sc + ": tetrahedra " + fmt(tets) + "x, surface (exact radial depth) " + fmt(surface) + "x (1 thread); 2 threads: " +
               fmt(query_ratio(sc, "spatial_hash_tets", "radial_cube", 2)) + "x / " +
               fmt(query_ratio(sc, "spatial_hash_surface", "radial_cube", 2)) + "x";
  return t;
}

// The one-pass range finder against 1 degree stepping.
TargetVerdict Targets::rom_vs_stepping() const {
  TargetVerdict t;
  t.target = "One-pass ROM >= 10x faster than 1 degree stepping with either detector, and exact";
  bool met = !results_.rom_table.empty();
  std::ostringstream m;
  for (const auto& row : results_.rom_table) {
    const double rf = row.fcl_ms / row.finder_ms, rh = row.hash_ms / row.finder_ms;
    met = met && rf >= 10.0 && rh >= 10.0 && row.finder_exact.find("NOT within") == std::string::npos;
    m << row.scenario << " (" << row.vertices << " v): FCL " << fmt(rf) << "x, hashing " << fmt(rh) << "x, " << row.finder_exact << "; ";
  }
  t.met = met;
  t.measured = m.str();
  return t;
}

// The one-pass ROM >= 10x faster than 1 degree stepping with FCL and with hashing at
// every hip level and on the real CT, exact (the lever of §3.7.2 is not a hip: above).
TargetVerdict Targets::rom_every_hip_level() const {
  TargetVerdict t;
  t.target = "one-pass ROM >= 10x faster than 1 degree stepping (FCL and hashing), every striking_hip level and the real CT, exact";
  bool any = false, all = true;
  std::ostringstream m;
  for (const auto& row : results_.rom_table) {
    if (row.scenario.rfind("striking_", 0) != 0) continue;
    const double rf = row.fcl_ms / row.finder_ms, rh = row.hash_ms / row.finder_ms;
    const bool exact = row.finder_exact.find("NOT within") == std::string::npos;
    any = true;
    all = all && rf >= 10.0 && rh >= 10.0 && exact;
    m << row.scenario << ": " << fmt(row.finder_ms) << " ms, FCL " << fmt(rf) << "x, hashing " << fmt(rh) << "x"
      << (exact ? "" : " (NOT exact)") << "; ";
  }
  t.met = any && all;
  t.measured = m.str();
  return t;
}

// Radial >= 3x Embree on the hip (cartilage) and >= 1.5x on sphere_cube, 1 thread;
// 2 threads >= 1.7x faster than 1. Ours = the faster of the posed-mesh query and the pose query.
TargetVerdict Targets::radial_vs_embree_per_family() const {
  TargetVerdict t;
  t.target = "radial query >= 3x Embree (cartilage), >= 1.5x (sphere_cube), 1 thread; 2 threads >= 1.7x faster than 1" + size_note_;
  bool met = true;
  std::ostringstream m;
  for (const std::string family : {"sphere_cube", "cartilage"}) {
    const std::string sc = largest(family);
    if (sc.empty()) continue;
    const double goal = family == "cartilage" ? 3.0 : 1.5;
    const double posed = query_ratio(sc, "embree", "radial_cube", 1);
    const double prepared = query_ratio(sc, "embree", "radial_cube_pose", 1);
    const BenchRow* one = find_row(results_.rows, sc, "radial_cube_pose", 1);
    const BenchRow* two = find_row(results_.rows, sc, "radial_cube_pose", 2);
    const double speedup = one && two && two->query.median_ms > 0.0 ? one->query.median_ms / two->query.median_ms : kNaN;
    met = met && std::max(posed, prepared) >= goal && speedup >= 1.7;
    m << sc << ": radial_cube " << fmt(posed) << "x, radial_cube_pose " << fmt(prepared) << "x (goal " << fmt(goal)
      << "x); 2 threads / 1 thread (pose query) " << fmt(speedup) << "x; ";
  }
  t.met = met;
  t.measured = m.str();
  return t;
}

// The cylindrical per-pose query with the pose cache >= 50x FCL all-contacts at
// striking_hip_L3 and >= 10x on the real CT bones; the one-pass query on a posed mesh (no
// cache) at least as fast as FCL. 1 thread, the slower of FCL's two bounding volumes taken
// as FCL's time would flatter us, so the faster one is.
TargetVerdict Targets::pose_cache_vs_fcl() const {
  TargetVerdict t;
  t.target = "pose cache >= 50x FCL (striking_hip_L3), >= 10x (real CT); one-pass query on the posed mesh >= 1x FCL" + size_note_;
  bool met = true, any = false;
  std::ostringstream m;
  for (const std::string family : {"striking_hip", "striking_real_ct"}) {
    const std::string sc = largest(family);
    if (sc.empty()) continue;
    any = true;
    const double goal = family == "striking_hip" ? 50.0 : 10.0;
    const auto fcl_over = [&](const std::string& ours) {
      const double obbrss = query_ratio(sc, "fcl_OBBRSS", ours, 1), obb = query_ratio(sc, "fcl_OBB", ours, 1);
      return std::isnan(obb) ? obbrss : std::min(obbrss, obb);
    };
    const double cache = fcl_over("cylindrical_pose_cache");
    const double scan = fcl_over("cylindrical_pose_cache_scan");
    const double posed = fcl_over("cylindrical");
    const double pose_given = fcl_over("cylindrical_pose");
    const double clustered = fcl_over("cylindrical_clusters");
    const double no_clusters = fcl_over("cylindrical_no_clusters");
    const double no_regions = fcl_over("cylindrical_no_regions");
    const double every = fcl_over("cylindrical_every_candidate");
    met = met && cache >= goal && posed >= 1.0;
    m << sc << ": pose cache " << fmt(cache) << "x (goal " << fmt(goal) << "x; without its arc index " << fmt(scan)
      << "x), one-pass on the posed mesh " << fmt(posed) << "x (goal 1x; over vertex clusters, given the pose, "
      << fmt(clustered) << "x; given the pose " << fmt(pose_given)
      << "x; without the table's mobile clusters " << fmt(no_clusters) << "x; without the outside regions either "
      << fmt(no_regions) << "x; without the walk either " << fmt(every)
      << "x); ";
  }
  t.met = any && met;
  t.measured = m.str();
  return t;
}

// Not a target with a threshold: how far each largest scenario's query is from streaming its
// mobile vertices once.
TargetVerdict Targets::bandwidth_floor() const {
  TargetVerdict t;
  t.target = "Bandwidth floor (stream the mobile vertex positions once): ours / floor, 1 thread";
  std::ostringstream m;
  for (const std::string family : {"striking_hip", "striking_real_ct", "sphere_cube", "cartilage"}) {
    const std::string sc = largest(family);
    if (sc.empty()) continue;
    const BenchRow* floor = find_row(results_.rows, sc, "bandwidth_floor", 1);
    if (floor == nullptr || !(floor->query.median_ms > 0.0)) continue;
    m << sc << ": floor " << fmt(floor->query.median_ms) << " ms";
    for (const std::string ours : {"cylindrical_pose_cache", "cylindrical", "cylindrical_clusters", "radial_cube", "radial_cube_pose", "embree"}) {
      const BenchRow* o = find_row(results_.rows, sc, ours, 1);
      if (o != nullptr) m << ", " << ours << " " << fmt(o->query.median_ms / floor->query.median_ms) << "x";
    }
    m << "; ";
  }
  t.informational = true;
  t.measured = m.str();
  return t;
}

// No false pairs against the oracle in any row of the thesis' methods.
TargetVerdict Targets::exactness() const {
  TargetVerdict t;
  t.target = "Zero false negatives and false positives vs the oracle, both thesis methods, every size";
  long fn = 0, fp = 0;
  std::size_t rows = 0, sampled = 0;
  for (const auto& r : results_.rows) {
    if (r.method.rfind("cylindrical", 0) != 0 && r.method.rfind("radial_", 0) != 0) continue;
    ++rows;
    fn += std::max(0L, r.exact.false_negatives);
    fp += std::max(0L, r.exact.false_positives);
    if (r.reference != "oracle") ++sampled;
  }
  t.met = rows > 0 && fn == 0 && fp == 0;
  t.measured = std::to_string(rows) + " rows: " + std::to_string(fn) + " FN, " + std::to_string(fp) + " FP (" +
               std::to_string(sampled) + " rows checked on an oracle sample)";
  return t;
}

}  // namespace

std::vector<TargetVerdict> evaluate_targets(const CollisionBenchResults& results) {
  const Targets targets(results);
  return {targets.fcl_all_contacts(),      targets.radial_vs_embree(),           targets.radial_vs_spatial_hashing(),
          targets.rom_vs_stepping(),       targets.rom_every_hip_level(),        targets.radial_vs_embree_per_family(),
          targets.pose_cache_vs_fcl(),     targets.bandwidth_floor(),            targets.exactness()};
}

}  // namespace hipfai::bench
