#include "bench/collision_bench.h"

#include "bench/bench_format.h"
#include "bench/collision_bench_report.h"
#include "bench/collision_bench_results.h"
#include "bench/collision_bench_targets.h"

#include "bench/peer_cgal.h"
#include "bench/peer_embree.h"
#include "bench/peer_fcl.h"
#include "bench/scenarios.h"
#include "bench/spatial_hashing.h"
#include "bench/stepping_rom.h"
#include "bench/timing.h"
#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "contact/detail/ablation.h"
#include "contact/oracle_cylindrical.h"
#include "contact/oracle_radial.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_table.h"
#include "contact/range_finder.h"
#include "contact/ray_sampling.h"
#include "core/error.h"
#include "core/numbers.h"
#include "core/parallel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <set>

namespace hipfai::bench {

namespace {

using Eigen::Vector3d;
using geometry::TriMesh;
using hipfai::kNaN;

// ------------------------------------------------------------------ configuration

struct Budget {
  int min_repeats, max_repeats;
  double query_budget_ms, pre_budget_ms;
  double oracle_pairs;        // #V x #T above which the oracle is sampled
  std::size_t oracle_sample;  // sampled mobile vertices
  int sphere_max_level, hip_max_level;
  std::size_t tet_max_triangles;  // tetrahedralize fixed meshes up to this size
};

Budget budget_for(bool quick) {
  if (quick) return {2, 5, 100.0, 200.0, 3e8, 1500, 4, 1, 6000};
  return {3, 9, 1500.0, 3000.0, 4e8, 4000, 8, 3, 120000};
}

// ------------------------------------------------------------------ exactness

// The oracle's answer on a set of checked mobile vertices.
struct Reference {
  std::map<std::int32_t, double> depth;  // penetrating vertex -> depth (among checked)
  std::vector<char> checked;             // per mobile vertex
  std::string kind;                      // "oracle" or "oracle sample (n)"
  std::size_t num_checked = 0;
  double ms = 0.0;                       // wall time of the oracle run (2 threads)
};

Exactness compare(const Reference& reference, const std::vector<std::int32_t>& vertices,
                  const std::vector<double>* depths) {
  Exactness e;
  e.reported = vertices.size();
  e.false_negatives = 0;
  e.false_positives = 0;
  std::set<std::int32_t> reported(vertices.begin(), vertices.end());
  for (const auto& [v, d] : reference.depth) {
    (void)d;
    if (!reported.count(v)) ++e.false_negatives;
  }
  double max_error = 0.0;
  bool any_depth = false;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const auto v = vertices[i];
    if (!reference.checked[static_cast<std::size_t>(v)]) continue;
    const auto found = reference.depth.find(v);
    if (found == reference.depth.end()) {
      ++e.false_positives;
    } else if (depths != nullptr) {
      max_error = std::max(max_error, std::abs((*depths)[i] - found->second));
      any_depth = true;
    }
  }
  e.max_depth_error_mm = depths != nullptr && any_depth ? max_error : (depths != nullptr ? 0.0 : kNaN);
  return e;
}

Exactness compare(const Reference& reference, const contact::PenetrationResult& result) {
  std::vector<std::int32_t> vertices;
  std::vector<double> depths;
  for (const auto& p : result.pairs) {
    vertices.push_back(p.mobile_vertex);
    depths.push_back(p.depth_mm);
  }
  return compare(reference, vertices, &depths);
}

// Runs `oracle` (on a vertex-only mesh) over the chosen vertices on two threads.
Reference make_reference(const Scenario& s, const TriMesh& posed, const std::vector<std::int32_t>& must_check,
                         const Budget& budget) {
  Reference ref;
  ref.checked.assign(posed.num_vertices(), 0);
  std::vector<std::int32_t> chosen;
  const double pairs = static_cast<double>(posed.num_vertices()) * static_cast<double>(s.fixed.num_triangles());
  if (pairs <= budget.oracle_pairs) {
    chosen.resize(posed.num_vertices());
    for (std::size_t i = 0; i < chosen.size(); ++i) chosen[i] = static_cast<std::int32_t>(i);
    ref.kind = "oracle";
  } else {
    // The sample is sized so that the oracle costs about half the exhaustive budget.
    const std::size_t affordable = static_cast<std::size_t>(
        0.25 * budget.oracle_pairs / std::max<double>(1.0, static_cast<double>(s.fixed.num_triangles())));
    const std::size_t sample = std::max<std::size_t>(200, std::min(budget.oracle_sample, affordable));
    std::mt19937 random(12345);
    std::uniform_int_distribution<std::int32_t> pick(0, static_cast<std::int32_t>(posed.num_vertices()) - 1);
    std::set<std::int32_t> set;
    for (std::size_t i = 0; i < sample; ++i) set.insert(pick(random));
    // Every vertex our method reports is checked too (so its false positives are counted in
    // full) unless there are many; then a random subset of them of the same size.
    if (must_check.size() <= sample) {
      set.insert(must_check.begin(), must_check.end());
      ref.kind = "oracle on " + std::to_string(sample) + " random + all reported vertices";
    } else {
      std::uniform_int_distribution<std::size_t> pick_reported(0, must_check.size() - 1);
      for (std::size_t i = 0; i < sample; ++i) set.insert(must_check[pick_reported(random)]);
      ref.kind = "oracle on " + std::to_string(sample) + " random + " + std::to_string(sample) +
                 " random reported vertices";
    }
    chosen.assign(set.begin(), set.end());
  }
  for (auto v : chosen) ref.checked[static_cast<std::size_t>(v)] = 1;
  ref.num_checked = chosen.size();
  const auto start = std::chrono::steady_clock::now();
  const int threads = 2;
  std::vector<contact::PenetrationResult> parts(threads);
  parallel_chunks(chosen.size(), threads, [&](std::size_t begin, std::size_t end, int chunk) {
    TriMesh subset;
    for (std::size_t i = begin; i < end; ++i) subset.vertices.push_back(posed.vertices[static_cast<std::size_t>(chosen[i])]);
    auto result = s.radial ? contact::oracle_radial(s.fixed, subset, s.centre, s.configuration)
                           : contact::oracle_cylindrical(s.fixed, subset, s.centre, s.axis);
    for (auto& p : result.pairs) p.mobile_vertex = chosen[begin + static_cast<std::size_t>(p.mobile_vertex)];
    parts[static_cast<std::size_t>(chunk)] = std::move(result);
  });
  for (const auto& part : parts) {
    for (const auto& p : part.pairs) ref.depth[p.mobile_vertex] = p.depth_mm;
  }
  ref.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return ref;
}

// ------------------------------------------------------------------ result rows

class Bench {
 public:
  explicit Bench(const CollisionBenchOptions& options)
      : options_(options), budget_(budget_for(options.quick)) {}

  CollisionBenchReport run();

 private:
  void log(const std::string& line) const {
    if (options_.verbose) {
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
      std::printf("[bench %6.1f s] %s\n", seconds, line.c_str());
      std::fflush(stdout);
    }
  }
  TimingStats time_query(const std::function<void()>& fn) const {
    return time_repeated(fn, budget_.min_repeats, budget_.max_repeats, budget_.query_budget_ms);
  }
  TimingStats time_pre(const std::function<void()>& fn) const {
    return time_repeated(fn, 1, 3, budget_.pre_budget_ms);
  }
  BenchRow base_row(const Scenario& s, const std::string& method, int threads) const {
    BenchRow row;
    row.family = s.family;
    row.scenario = s.name;
    row.level = s.level;
    row.vertices = s.total_vertices();
    row.mobile_vertices = s.mobile.num_vertices();
    row.fixed_triangles = s.fixed.num_triangles();
    row.method = method;
    row.threads = threads;
    return row;
  }

  void bench_striking(const Scenario& s);
  // Ours on a striking scenario at `threads`: the one-pass query (its vertices into
  // ours_vertices once), its ablations, and the pose cache.
  void bench_one_pass(const Scenario& s, int threads, std::vector<std::int32_t>& ours_vertices);
  void bench_one_pass_ablations(const Scenario& s, const contact::CylindricalTable& table, const BenchRow& row,
                                const contact::CylindricalQueryOptions& q);
  void bench_pose_cache(const Scenario& s, int threads, const contact::CylindricalQueryOptions& q);
  void bench_radial(const Scenario& s);
  // Ours on a radial scenario: the query on the posed mesh with each mapping's table, and the
  // pose query (the body pair prepared once).
  void bench_radial_table(const Scenario& s, contact::RadialMapping mapping, int threads,
                          std::vector<std::int32_t>& ours_vertices);
  void bench_radial_pose_query(const Scenario& s, int threads);
  // The radial peers: Embree and CGAL ray casting, spatial hashing of the surface, Maciel's ray sampling.
  void bench_radial_casters(const Scenario& s);
  void bench_ray_sampling(const Scenario& s);
  // Peers of both kinds of scenario, checked against the reference as they run.
  void bench_fcl(const Scenario& s, const Reference& reference, FclBoundingVolume bv);
  void bench_tet_hashing(const Scenario& s, const Reference& reference);
  // Exactness of the scenario's rows against the reference, the oracle's own row, and the
  // scenario's results let go.
  void finish_scenario(const Scenario& s, const Reference& reference);
  void bench_bandwidth_floor(const Scenario& s);
  void sweep_radial_table(const Scenario& s);
  void sweep_cylindrical_resolution(const Scenario& s);
  void stepping(const Scenario& s, bool full_sweep);
  void fill_ratios();

  CollisionBenchOptions options_;
  Budget budget_;
  CollisionBenchResults measured_;  // what the run measured, filled stage by stage
  std::map<std::string, contact::PenetrationResult> results_;  // per scenario, for exactness
  std::map<std::string, std::pair<std::shared_ptr<TetMesh>, double>> tet_cache_;  // mesh hash -> tets, gmsh ms
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  // gmsh tetrahedra of a fixed mesh, computed once per distinct mesh (the sphere-cube levels 6-8
  // share one cube).
  std::pair<std::shared_ptr<TetMesh>, double> tets_of(const TriMesh& mesh) {
    const std::string key = geometry::mesh_hash(mesh);
    auto found = tet_cache_.find(key);
    if (found != tet_cache_.end()) return found->second;
    const auto start = std::chrono::steady_clock::now();
    auto tets = std::make_shared<TetMesh>(tetrahedralize(mesh));
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return tet_cache_[key] = {tets, ms};
  }
};

// ------------------------------------------------------------------ striking (cylindrical)

void Bench::bench_striking(const Scenario& s) {
  log(s.name + ": " + std::to_string(s.total_vertices()) + " vertices, pose " + fmt(s.angle_deg) + " deg");
  const TriMesh posed = s.posed_mobile();
  std::vector<std::int32_t> ours_vertices;
  for (int threads : options_.thread_counts) bench_one_pass(s, threads, ours_vertices);
  bench_bandwidth_floor(s);
  const Reference reference = make_reference(s, posed, ours_vertices, budget_);
  // FCL, both bounding volumes, all contacts with contact data (the configuration the goals name).
  for (auto bv : {FclBoundingVolume::kObbRss, FclBoundingVolume::kObb}) bench_fcl(s, reference, bv);
  // Spatial hashing on gmsh tetrahedra of the fixed solid.
  if (s.fixed.num_triangles() <= budget_.tet_max_triangles) bench_tet_hashing(s, reference);
  finish_scenario(s, reference);
}

void Bench::bench_one_pass(const Scenario& s, int threads, std::vector<std::int32_t>& ours_vertices) {
  // Ours: ring table (pre-processing) + one pass over the posed mesh (query).
  BenchRow row = base_row(s, "cylindrical", threads);
  contact::CylindricalTable table;
  row.memory = measure_memory([&] { table = contact::CylindricalTable::build(s.fixed, s.centre, s.axis, {}, &s.mobile); });
  row.pre = time_pre([&] { table = contact::CylindricalTable::build(s.fixed, s.centre, s.axis, {}, &s.mobile); });
  contact::CylindricalQueryOptions q;
  q.num_threads = threads;
  contact::PenetrationResult result;
  row.query = time_query([&] { result = contact::cylindrical_segmenting(table, s.posed_mobile(), q); });
  if (ours_vertices.empty()) {
    for (const auto& p : result.pairs) ours_vertices.push_back(p.mobile_vertex);
  }
  measured_.rows.push_back(row);
  // The same table and query taking the pose (each vertex posed as it is visited, no posed copy:
  // FCL too takes a transform), and the ablation without the angular walk.
  BenchRow pose_row = row;
  pose_row.method = "cylindrical_pose";
  contact::PenetrationResult posed_result;
  const Eigen::Isometry3d pose = s.pose();
  pose_row.query = time_query([&] { posed_result = contact::cylindrical_segmenting(table, s.mobile, pose, q); });
  pose_row.note = "the one-pass query given the pose instead of a posed copy";
  measured_.rows.push_back(pose_row);
  // The query over the mobile mesh's vertex clusters (built once per body, as FCL builds its
  // hierarchy of the mobile mesh), given the pose: pre-processing is the table and the clusters.
  BenchRow cluster_row = row;
  cluster_row.method = "cylindrical_clusters";
  contact::VertexClusters clusters;
  const TimingStats cluster_pre = time_pre([&] { clusters = contact::VertexClusters::build(s.mobile); });
  add_stage(cluster_row.pre, cluster_pre);
  contact::PenetrationResult cluster_result;
  cluster_row.query = time_query([&] { cluster_result = contact::cylindrical_segmenting(table, clusters, pose, q); });
  cluster_row.note = "the one-pass query over vertex clusters of the mobile mesh, given the pose";
  measured_.rows.push_back(cluster_row);
  // Exactness is filled in finish_scenario for every row of this scenario.
  results_[s.name + "/cylindrical/" + std::to_string(threads)] = result;
  results_[s.name + "/cylindrical_pose/" + std::to_string(threads)] = posed_result;
  results_[s.name + "/cylindrical_clusters/" + std::to_string(threads)] = cluster_result;
  bench_one_pass_ablations(s, table, row, q);
  bench_pose_cache(s, threads, q);
}

void Bench::bench_one_pass_ablations(const Scenario& s, const contact::CylindricalTable& table, const BenchRow& row,
                                     const contact::CylindricalQueryOptions& q) {
  const auto ablate = [&](const std::string& method, const contact::detail::CylindricalAblation& ablation,
                          const std::string& note) {
    BenchRow ablated = row;
    ablated.method = method;
    contact::PenetrationResult result;
    ablated.query =
        time_query([&] { result = contact::detail::cylindrical_segmenting(table, s.posed_mobile(), q, ablation); });
    ablated.note = note;
    measured_.rows.push_back(ablated);
    results_[s.name + "/" + method + "/" + std::to_string(row.threads)] = result;
  };
  contact::detail::CylindricalAblation plain;
  plain.mobile_clusters = false;
  ablate("cylindrical_no_clusters", plain,
         "the one-pass query without the table's mobile clusters (every vertex on its own)");
  contact::detail::CylindricalAblation walk = plain;
  walk.outside_regions = false;
  ablate("cylindrical_no_regions", walk,
         "the one-pass query without the clusters or the outside regions (every circle in a non-empty cell walked)");
  contact::detail::CylindricalAblation every = walk;
  every.angular_walk = false;
  ablate("cylindrical_every_candidate", every,
         "the one-pass query without the angular walk, the regions or the clusters (every candidate of the ring cell "
         "tested)");
}

void Bench::bench_pose_cache(const Scenario& s, int threads, const contact::CylindricalQueryOptions& q) {
  // The pose cache (§3.2.3.2): crossings pre-computed per axis, the query is a pass over them.
  // It reads every crossing, so its table is built without the angular index.
  contact::CylindricalTableOptions cache_table_options;
  cache_table_options.angular_index = false;
  const auto build_cache_table = [&] {
    return contact::CylindricalTable::build(s.fixed, s.centre, s.axis, cache_table_options, &s.mobile);
  };
  contact::CylindricalTable cache_table;
  BenchRow cache_row = base_row(s, "cylindrical_pose_cache", threads);
  std::unique_ptr<contact::CylindricalPoseCache> cache;
  cache_row.memory = measure_memory([&] {
    cache_table = build_cache_table();
    cache = std::make_unique<contact::CylindricalPoseCache>(cache_table, s.mobile, q);
  });
  const TimingStats cache_table_pre = time_pre([&] { cache_table = build_cache_table(); });
  const TimingStats cache_pre = time_pre([&] { cache = std::make_unique<contact::CylindricalPoseCache>(cache_table, s.mobile, q); });
  cache_row.pre = cache_table_pre;
  add_stage(cache_row.pre, cache_pre);
  contact::PenetrationResult cached;
  cache_row.query = time_query([&] { cached = cache->query(s.angle_deg); });
  measured_.rows.push_back(cache_row);
  // Ablation: the same cache without its arc index, the exact test of every tracked vertex.
  BenchRow scan_row = cache_row;
  scan_row.method = "cylindrical_pose_cache_scan";
  contact::PenetrationResult scanned;
  scan_row.query = time_query([&] { scanned = cache->query_every_vertex(s.angle_deg); });
  scan_row.note = "the pose cache without its arc index (every tracked vertex tested)";
  measured_.rows.push_back(scan_row);
  results_[s.name + "/cylindrical_pose_cache/" + std::to_string(threads)] = cached;
  results_[s.name + "/cylindrical_pose_cache_scan/" + std::to_string(threads)] = scanned;
}

void Bench::bench_fcl(const Scenario& s, const Reference& reference, FclBoundingVolume bv) {
  BenchRow row = base_row(s, std::string("fcl_") + to_string(bv), 1);
  FclModel fixed_model, mobile_model;
  row.memory = measure_memory([&] {
    fixed_model = FclModel(s.fixed, bv);
    mobile_model = FclModel(s.mobile, bv);
  });
  row.pre = time_pre([&] {
    fixed_model = FclModel(s.fixed, bv);
    mobile_model = FclModel(s.mobile, bv);
  });
  FclCollideResult result;
  row.query = time_query([&] { result = fixed_model.collide(mobile_model, s.pose()); });
  row.exact = compare(reference, implied_mobile_vertices(s.mobile, result), nullptr);
  row.reference = reference.kind;
  row.note = std::to_string(result.triangle_pairs.size()) + " triangle pairs; vertices of the mobile triangles";
  measured_.rows.push_back(row);
}

void Bench::bench_tet_hashing(const Scenario& s, const Reference& reference) {
  try {
    const auto [tet_mesh, tet_ms] = tets_of(s.fixed);
    const TetMesh& tets = *tet_mesh;
    const std::size_t num_tets = tets.tets.size();
    for (int threads : options_.thread_counts) {
      BenchRow row = base_row(s, "spatial_hash_tets", threads);
      std::unique_ptr<TetSpatialHash> hash;
      row.memory = measure_memory([&] { hash = std::make_unique<TetSpatialHash>(tets); });
      row.pre = time_pre([&] { hash = std::make_unique<TetSpatialHash>(tets); });
      std::vector<std::int32_t> found;
      row.query = time_query([&] { found = hash->penetrating_vertices(s.posed_mobile(), threads); });
      row.exact = compare(reference, found, nullptr);
      row.reference = reference.kind;
      row.note = std::to_string(num_tets) + " tets (gmsh " + fmt(tet_ms) + " ms, not in pre); no depth";
      measured_.rows.push_back(row);
    }
  } catch (const Error& error) {
    measured_.notes.push_back(s.name + ": spatial hashing on tetrahedra skipped: " + error.what());
  }
}

void Bench::finish_scenario(const Scenario& s, const Reference& reference) {
  for (auto& row : measured_.rows) {
    if (row.scenario != s.name) continue;
    const auto found = results_.find(s.name + "/" + row.method + "/" + std::to_string(row.threads));
    if (found == results_.end()) continue;
    row.exact = compare(reference, found->second);
    row.reference = reference.kind;
    if (row.method == "maciel_ray_sampling" && !reference.depth.empty()) {
      row.note += "; miss rate " + fmt(100.0 * static_cast<double>(row.exact.false_negatives) /
                                           static_cast<double>(reference.depth.size())) + " %";
    }
  }
  // The oracle itself (one run), where it is exhaustive.
  if (reference.kind == "oracle") {
    BenchRow row = base_row(s, "oracle", 2);
    row.query = summarise({reference.ms});
    row.note = "exhaustive, every vertex x every triangle (one run)";
    measured_.rows.push_back(row);
  }
  results_.clear();
}

// ------------------------------------------------------------------ bandwidth floor

// The time to stream the mobile vertex positions once (a sum over their coordinates): no per-pose
// query that looks at every vertex can be faster, so ours / floor says how far from it we are.
void Bench::bench_bandwidth_floor(const Scenario& s) {
  BenchRow row = base_row(s, "bandwidth_floor", 1);
  const TriMesh posed = s.posed_mobile();
  volatile double sink = 0.0;
  row.query = time_query([&] {
    double sum = 0.0;
    for (const auto& v : posed.vertices) sum += v.x() + v.y() + v.z();
    sink = sum;
  });
  (void)sink;
  row.note = "streaming the " + std::to_string(posed.num_vertices()) + " mobile vertex positions once (" +
             fmt(static_cast<double>(posed.num_vertices()) * 24.0 / 1048576.0) + " MiB)";
  measured_.rows.push_back(row);
}

// ------------------------------------------------------------------ sliding (radial)

contact::RadialTableOptions radial_table_options(const Scenario& s, contact::RadialMapping mapping) {
  contact::RadialTableOptions options;
  options.mapping = mapping;
  // About one cell per fixed triangle, as the thesis advises (a cell about a triangle's size); on
  // cartilage_L3 the pose query is faster there than with twice the cells
  // (docs/collision-performance-history.md).
  options.table_size = std::max<std::int64_t>(4096, static_cast<std::int64_t>(s.fixed.num_triangles()));
  return options;
}

void Bench::bench_radial(const Scenario& s) {
  log(s.name + ": " + std::to_string(s.total_vertices()) + " vertices");
  const TriMesh posed = s.posed_mobile();
  std::vector<std::int32_t> ours_vertices;
  const std::vector<contact::RadialMapping> mappings{contact::RadialMapping::kCube, contact::RadialMapping::kCartesian,
                                                     contact::RadialMapping::kSpherical};
  for (auto mapping : mappings) {
    for (int threads : options_.thread_counts) bench_radial_table(s, mapping, threads, ours_vertices);
  }
  for (int threads : options_.thread_counts) bench_radial_pose_query(s, threads);
  bench_bandwidth_floor(s);
  const Reference reference = make_reference(s, posed, ours_vertices, budget_);
  bench_radial_casters(s);
  if (s.family == "sphere_cube" && s.fixed.num_triangles() <= budget_.tet_max_triangles) bench_tet_hashing(s, reference);
  bench_fcl(s, reference, FclBoundingVolume::kObbRss);
  bench_ray_sampling(s);
  finish_scenario(s, reference);
}

void Bench::bench_radial_table(const Scenario& s, contact::RadialMapping mapping, int threads,
                               std::vector<std::int32_t>& ours_vertices) {
  BenchRow row = base_row(s, std::string("radial_") + contact::to_string(mapping), threads);
  contact::RadialTable table;
  const auto table_options = radial_table_options(s, mapping);
  row.memory = measure_memory([&] { table = contact::build_radial_table(s.fixed, s.centre, table_options); });
  row.pre = time_pre([&] { table = contact::build_radial_table(s.fixed, s.centre, table_options); });
  contact::RadialQueryOptions q;
  q.configuration = s.configuration;
  q.num_threads = threads;
  contact::PenetrationResult result;
  row.query = time_query([&] { result = contact::radial_segmenting(table, s.fixed, s.posed_mobile(), q); });
  if (ours_vertices.empty()) {
    for (const auto& p : result.pairs) ours_vertices.push_back(p.mobile_vertex);
  }
  row.note = "table " + std::to_string(table.grid.num_cells()) + " cells, " +
             std::to_string(table.always_candidates.size()) + " always-checked triangles (plane through O)";
  results_[s.name + "/" + row.method + "/" + std::to_string(threads)] = result;
  measured_.rows.push_back(row);
}

// The same query prepared once per body pair (RadialPoseQuery): vertices the radial spans rule
// out at every pose are dropped once; the query takes the pose, like FCL, and poses the rest.
void Bench::bench_radial_pose_query(const Scenario& s, int threads) {
  BenchRow row = base_row(s, "radial_cube_pose", threads);
  contact::RadialTable table = contact::build_radial_table(s.fixed, s.centre, radial_table_options(s, contact::RadialMapping::kCube));
  contact::RadialQueryOptions q;
  q.configuration = s.configuration;
  q.num_threads = threads;
  std::unique_ptr<contact::RadialPoseQuery> prepared;
  row.memory = measure_memory([&] { prepared = std::make_unique<contact::RadialPoseQuery>(table, s.fixed, s.mobile, q); });
  const TimingStats prepare = time_pre([&] { prepared = std::make_unique<contact::RadialPoseQuery>(table, s.fixed, s.mobile, q); });
  row.pre = time_pre([&] { table = contact::build_radial_table(s.fixed, s.centre, radial_table_options(s, contact::RadialMapping::kCube)); });
  add_stage(row.pre, prepare);
  prepared = std::make_unique<contact::RadialPoseQuery>(table, s.fixed, s.mobile, q);
  contact::PenetrationResult result;
  row.query = time_query([&] { result = prepared->query(s.pose()); });
  row.note = std::to_string(prepared->num_kept_vertices()) + " of " + std::to_string(s.mobile.num_vertices()) +
             " mobile vertices kept for the body pair";
  results_[s.name + "/" + row.method + "/" + std::to_string(threads)] = result;
  measured_.rows.push_back(row);
}

void Bench::bench_radial_casters(const Scenario& s) {
  for (int threads : options_.thread_counts) {
    BenchRow row = base_row(s, "embree", threads);
    std::unique_ptr<EmbreeRadialCaster> caster;
    row.memory = measure_memory([&] { caster = std::make_unique<EmbreeRadialCaster>(s.fixed, s.centre, threads); });
    row.pre = time_pre([&] { caster = std::make_unique<EmbreeRadialCaster>(s.fixed, s.centre, threads); });
    contact::PenetrationResult result;
    row.query = time_query([&] { result = caster->query(s.mobile, s.pose(), s.configuration, threads); });
    results_[s.name + "/embree/" + std::to_string(threads)] = result;
    row.note = "single precision";
    measured_.rows.push_back(row);
  }
  for (int threads : options_.thread_counts) {
    BenchRow row = base_row(s, "cgal_aabb", threads);
    std::unique_ptr<CgalRadialCaster> caster;
    row.memory = measure_memory([&] { caster = std::make_unique<CgalRadialCaster>(s.fixed, s.centre); });
    row.pre = time_pre([&] { caster = std::make_unique<CgalRadialCaster>(s.fixed, s.centre); });
    contact::PenetrationResult result;
    row.query = time_query([&] { result = caster->query(s.posed_mobile(), s.configuration, threads); });
    results_[s.name + "/cgal_aabb/" + std::to_string(threads)] = result;
    measured_.rows.push_back(row);
  }
  for (int threads : options_.thread_counts) {
    BenchRow row = base_row(s, "spatial_hash_surface", threads);
    std::unique_ptr<SurfaceSpatialHash> hash;
    row.memory = measure_memory([&] { hash = std::make_unique<SurfaceSpatialHash>(s.fixed); });
    row.pre = time_pre([&] { hash = std::make_unique<SurfaceSpatialHash>(s.fixed); });
    contact::PenetrationResult result;
    row.query = time_query([&] { result = hash->radial_query(s.posed_mobile(), s.centre, s.configuration, threads); });
    results_[s.name + "/spatial_hash_surface/" + std::to_string(threads)] = result;
    row.note = "cells walked along each ray";
    measured_.rows.push_back(row);
  }
}

void Bench::bench_ray_sampling(const Scenario& s) {
  BenchRow row = base_row(s, "maciel_ray_sampling", 1);
  const auto table_options = radial_table_options(s, contact::RadialMapping::kCube);
  contact::RaySamplingTable table;
  row.memory = measure_memory([&] { table = contact::build_ray_sampling_table(s.fixed, s.centre, table_options, s.configuration); });
  row.pre = time_pre([&] { table = contact::build_ray_sampling_table(s.fixed, s.centre, table_options, s.configuration); });
  contact::PenetrationResult result;
  row.query = time_query([&] { result = contact::ray_sampling(table, s.fixed, s.posed_mobile()); });
  results_[s.name + "/maciel_ray_sampling/1"] = result;
  row.note = "cube mapping, same table size; pre uses the exact table as accelerator";
  measured_.rows.push_back(row);
}

// ------------------------------------------------------------------ sweeps

void Bench::sweep_radial_table(const Scenario& s) {
  log("radial table-size sweep on " + s.name);
  const TriMesh posed = s.posed_mobile();
  const Reference reference = make_reference(s, posed, {}, budget_);
  std::vector<std::int64_t> sizes{256, 1024, 4096, 16384, 65536};
  if (!options_.quick) {
    sizes.push_back(262144);
    sizes.push_back(1048576);
  }
  measured_.sweep_radial_table_csv.push_back("scenario,method,table_size,cells,pre_ms,query_ms,false_negatives,false_positives,miss_rate_pct,reference");
  for (auto mapping : {contact::RadialMapping::kCube, contact::RadialMapping::kCartesian, contact::RadialMapping::kSpherical}) {
    for (auto size : sizes) {
      contact::RadialTableOptions table_options;
      table_options.mapping = mapping;
      table_options.table_size = size;
      contact::RadialTable table;
      const TimingStats pre = time_pre([&] { table = contact::build_radial_table(s.fixed, s.centre, table_options); });
      contact::RadialQueryOptions q;
      q.configuration = s.configuration;
      contact::PenetrationResult result;
      const TimingStats query = time_query([&] { result = contact::radial_segmenting(table, s.fixed, s.posed_mobile(), q); });
      const Exactness e = compare(reference, result);
      const std::string method = std::string("radial_") + contact::to_string(mapping);
      measured_.sweep_radial_table_csv.push_back(s.name + "," + method + "," + std::to_string(size) + "," +
                                  std::to_string(table.grid.num_cells()) + "," + fmt(pre.median_ms, 6) + "," +
                                  fmt(query.median_ms, 6) + "," + std::to_string(e.false_negatives) + "," +
                                  std::to_string(e.false_positives) + ",0," + reference.kind);
      measured_.radial_sweep_query[method].emplace_back(static_cast<double>(table.grid.num_cells()), query.median_ms);
      measured_.radial_sweep_pre[method].emplace_back(static_cast<double>(table.grid.num_cells()), pre.median_ms);
    }
  }
  for (auto size : sizes) {
    contact::RadialTableOptions table_options;
    table_options.mapping = contact::RadialMapping::kCube;
    table_options.table_size = size;
    contact::RaySamplingTable table;
    const TimingStats pre = time_pre([&] { table = contact::build_ray_sampling_table(s.fixed, s.centre, table_options, s.configuration); });
    contact::PenetrationResult result;
    const TimingStats query = time_query([&] { result = contact::ray_sampling(table, s.fixed, s.posed_mobile()); });
    const Exactness e = compare(reference, result);
    const double miss = reference.depth.empty() ? 0.0 : 100.0 * static_cast<double>(e.false_negatives) / static_cast<double>(reference.depth.size());
    measured_.sweep_radial_table_csv.push_back(s.name + ",maciel_ray_sampling," + std::to_string(size) + "," +
                                std::to_string(table.grid.num_cells()) + "," + fmt(pre.median_ms, 6) + "," +
                                fmt(query.median_ms, 6) + "," + std::to_string(e.false_negatives) + "," +
                                std::to_string(e.false_positives) + "," + fmt(miss, 6) + "," + reference.kind);
    measured_.maciel_miss.emplace_back(static_cast<double>(table.grid.num_cells()), miss);
    measured_.maciel_query.emplace_back(static_cast<double>(table.grid.num_cells()), query.median_ms);
  }
}

void Bench::sweep_cylindrical_resolution(const Scenario& s) {
  log("cylindrical resolution sweep on " + s.name);
  const TriMesh posed = s.posed_mobile();
  const Reference reference = make_reference(s, posed, {}, budget_);
  const double edge = geometry::mean_edge_length(s.fixed);
  measured_.sweep_cylindrical_csv.push_back("scenario,resolution_factor,resolution_mm,cells,pre_ms,query_ms,false_negatives,false_positives,reference");
  for (double factor : {0.25, 0.5, 1.0, 2.0, 4.0, 8.0}) {
    contact::CylindricalTableOptions table_options;
    table_options.resolution_r_mm = table_options.resolution_z_mm = factor * edge;
    contact::CylindricalTable table;
    const TimingStats pre = time_pre([&] { table = contact::CylindricalTable::build(s.fixed, s.centre, s.axis, table_options, &s.mobile); });
    contact::CylindricalQueryOptions q;
    q.num_threads = 1;
    contact::PenetrationResult result;
    const TimingStats query = time_query([&] { result = contact::cylindrical_segmenting(table, s.posed_mobile(), q); });
    const Exactness e = compare(reference, result);
    measured_.sweep_cylindrical_csv.push_back(s.name + "," + fmt(factor) + "," + fmt(factor * edge, 6) + "," +
                             std::to_string(table.num_r_cells() * table.num_z_cells()) + "," + fmt(pre.median_ms, 6) +
                             "," + fmt(query.median_ms, 6) + "," + std::to_string(e.false_negatives) + "," +
                             std::to_string(e.false_positives) + "," + reference.kind);
    measured_.cylindrical_sweep["query"].emplace_back(factor * edge, query.median_ms);
    measured_.cylindrical_sweep["pre-processing"].emplace_back(factor * edge, pre.median_ms);
  }
}

void Bench::stepping(const Scenario& s, bool full_sweep) {
  log("range of motion (one pass vs stepping) on " + s.name);
  contact::RangeOfMotionOptions rom_options;
  rom_options.query.num_threads = 1;
  contact::RangeOfMotion exact;
  const TimingStats finder = time_repeated([&] { exact = contact::range_of_motion(s.fixed, s.mobile, s.centre, s.axis, rom_options); },
                                           1, budget_.max_repeats, budget_.query_budget_ms);
  const double kMaxDeg = 180.0;
  const double exact_ccw = std::min(exact.anticlockwise_deg, kMaxDeg), exact_cw = std::min(exact.clockwise_deg, kMaxDeg);
  std::string finder_exact = "vertex passes not checked (too large for the oracle)";
  if (static_cast<double>(s.mobile.num_vertices()) * static_cast<double>(s.fixed.num_triangles()) <= budget_.oracle_pairs) {
    // The oracle enumerates vertex contacts: it checks the finder's vertex passes.
    contact::RangeOfMotionOptions vertex_options = rom_options;
    vertex_options.include_edge_edge = false;
    const auto vertices = contact::range_of_motion(s.fixed, s.mobile, s.centre, s.axis, vertex_options);
    const auto oracle = contact::oracle_range_of_motion(s.fixed, s.mobile, s.centre, s.axis);
    const double diff = std::max(std::abs(oracle.anticlockwise_deg - vertices.anticlockwise_deg),
                                 std::abs(oracle.clockwise_deg - vertices.clockwise_deg));
    finder_exact = "vertex passes vs oracle " + fmt(diff) + " deg";
  }
  const bool edge_limited = exact.anticlockwise_limit.kind == contact::ContactKind::kEdgeOnEdge ||
                            exact.clockwise_limit.kind == contact::ContactKind::kEdgeOnEdge;
  finder_exact += edge_limited ? ", limited by an edge-edge contact" : ", limited by vertex contacts";
  // Detectors. FCL: boolean collide (num_max_contacts 1, no contact data: the cheapest FCL call).
  auto run_fcl = [&](double step, SteppingRom& rom) {
    FclModel fixed_model(s.fixed, FclBoundingVolume::kObbRss), mobile_model(s.mobile, FclBoundingVolume::kObbRss);
    FclCollideOptions boolean;
    boolean.all_contacts = false;
    boolean.enable_contact = false;
    SteppingRomOptions so;
    so.step_deg = step;
    so.max_deg = kMaxDeg;
    rom = stepping_range_of_motion([&](double angle_deg) {
      return fixed_model.collide(mobile_model, rotation_about(s.centre, s.axis, angle_deg * std::numbers::pi / 180.0), boolean).collides;
    }, so);
  };
  auto run_hash = [&](double step, SteppingRom& rom) {
    SurfaceSpatialHash hash(s.fixed);
    SteppingRomOptions so;
    so.step_deg = step;
    so.max_deg = kMaxDeg;
    rom = stepping_range_of_motion([&](double angle_deg) {
      return hash.first_collision(transformed(s.mobile, rotation_about(s.centre, s.axis, angle_deg * std::numbers::pi / 180.0)));
    }, so);
  };
  auto error_of = [&](const SteppingRom& rom) {
    return std::max(std::abs(rom.anticlockwise_deg - exact_ccw), std::abs(rom.clockwise_deg - exact_cw));
  };
  SteppingRom fcl_rom, hash_rom;
  const TimingStats fcl_time = time_repeated([&] { run_fcl(1.0, fcl_rom); }, 1, 3, budget_.pre_budget_ms);
  const TimingStats hash_time = time_repeated([&] { run_hash(1.0, hash_rom); }, 1, 3, budget_.pre_budget_ms);
  // Independent check of the whole finder (vertex and edge-edge contacts): stepping with the
  // exact triangle-triangle test of spatial hashing must stop within one step before it.
  auto within_step = [](double exact_deg, double stepped_deg) {
    return stepped_deg <= exact_deg + 1e-9 && exact_deg < stepped_deg + 1.0 + 1e-9;
  };
  finder_exact += (within_step(exact_ccw, hash_rom.anticlockwise_deg) && within_step(exact_cw, hash_rom.clockwise_deg))
                      ? "; within the 1 deg step of triangle-triangle stepping"
                      : "; NOT within the 1 deg step of triangle-triangle stepping";
  measured_.rom_table.push_back({s.name, s.total_vertices(), finder.median_ms, fcl_time.median_ms, hash_time.median_ms, exact_ccw,
                     exact_cw, fcl_rom.anticlockwise_deg, fcl_rom.clockwise_deg, hash_rom.anticlockwise_deg,
                     hash_rom.clockwise_deg, finder_exact});
  if (!full_sweep) return;
  measured_.sweep_stepping_csv.push_back("scenario,detector,step_deg,time_ms,detections,anticlockwise_deg,clockwise_deg,exact_anticlockwise_deg,exact_clockwise_deg,max_error_deg");
  measured_.sweep_stepping_csv.push_back(s.name + ",range_finder,0," + fmt(finder.median_ms, 6) + ",1," + fmt(exact_ccw, 10) + "," +
                            fmt(exact_cw, 10) + "," + fmt(exact_ccw, 10) + "," + fmt(exact_cw, 10) + ",0");
  for (double step : {10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1}) {
    for (int detector = 0; detector < 2; ++detector) {
      SteppingRom rom;
      const TimingStats t = time_repeated([&] { detector == 0 ? run_fcl(step, rom) : run_hash(step, rom); }, 1, 3, budget_.pre_budget_ms);
      const std::string name = detector == 0 ? "fcl_OBBRSS" : "spatial_hash_surface";
      measured_.sweep_stepping_csv.push_back(s.name + "," + name + "," + fmt(step) + "," + fmt(t.median_ms, 6) + "," +
                                std::to_string(rom.detections) + "," + fmt(rom.anticlockwise_deg, 10) + "," +
                                fmt(rom.clockwise_deg, 10) + "," + fmt(exact_ccw, 10) + "," + fmt(exact_cw, 10) + "," +
                                fmt(error_of(rom), 6));
      measured_.stepping_sweep[name].emplace_back(t.median_ms, std::max(error_of(rom), 1e-6));
    }
  }
  measured_.stepping_sweep["range_finder (one pass)"].emplace_back(finder.median_ms, 1e-6);
}

// ------------------------------------------------------------------ ratios, outputs

void Bench::fill_ratios() {
  for (auto& row : measured_.rows) {
    // Ours: the pose cache where the scenario is cylindrical (striking, lever and stone, torus).
    const bool cylindrical = std::any_of(measured_.rows.begin(), measured_.rows.end(), [&](const BenchRow& other) {
      return other.scenario == row.scenario && other.method == "cylindrical_pose_cache";
    });
    const std::string ours = cylindrical ? "cylindrical_pose_cache" : "radial_cube";
    const int threads = row.threads > 2 ? 2 : row.threads;
    for (const auto& other : measured_.rows) {
      if (other.scenario != row.scenario || other.method != ours || other.threads != threads) continue;
      if (other.query.median_ms > 0.0) row.ratio_query = row.query.median_ms / other.query.median_ms;
      if (other.total_ms() > 0.0) row.ratio_total = row.total_ms() / other.total_ms();
    }
  }
}

CollisionBenchReport Bench::run() {
  const auto start = std::chrono::steady_clock::now();
  std::error_code ec;
  std::filesystem::create_directories(options_.out_dir, ec);
  if (ec) throw_error("--out ", options_.out_dir.string(), ": cannot create the directory (", ec.message(), ")");
  log("generating the parametric hip (gmsh)");
  const geometry::HipModel hip = make_coarse_hip();
  const auto striking = make_striking_hip(hip, budget_.hip_max_level);
  for (const auto& s : striking) bench_striking(s);
  std::optional<Scenario> real;
  if (!options_.quick && !options_.lhdl_dir.empty()) {
    try {
      real = make_striking_real_ct(options_.lhdl_dir);
      bench_striking(*real);
    } catch (const Error& error) {
      measured_.notes.push_back(std::string("real CT scenario skipped: ") + error.what());
      log(measured_.notes.back());  // on the console too: a run from another folder misses the default
    }
  }
  // The non-medical examples of thesis §3.7.2: a lever turning about its fulcrum against a stone
  // (depths at a pose past the first contact, and the range of motion), and a torus rolling on a
  // rough surface (cylindrical segmenting about its axis).
  const Scenario lever = make_lever_stone();
  bench_striking(lever);
  bench_striking(make_torus_rough());
  for (int level = 2; level <= budget_.sphere_max_level; ++level) bench_radial(make_sphere_cube(level));
  for (const auto& s : make_cartilage(hip, budget_.hip_max_level)) bench_radial(s);
  sweep_radial_table(make_sphere_cube(options_.quick ? 4 : 5));
  sweep_cylindrical_resolution(striking[static_cast<std::size_t>(options_.quick ? 1 : 2)]);
  for (std::size_t i = 0; i < striking.size(); ++i) stepping(striking[i], i == (options_.quick ? 0u : 1u));
  if (real) stepping(*real, false);
  stepping(lever, false);
  fill_ratios();
  measured_.quick = options_.quick;
  CollisionBenchReport report;
  report.targets = evaluate_targets(measured_);
  log("writing the tables, figures and report");
  report.report_path = write_collision_bench_report(measured_, report.targets, options_.out_dir);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace

CollisionBenchReport run_collision_bench(const CollisionBenchOptions& options) {
  if (options.thread_counts.empty()) throw_error("bench: at least one thread count is needed");
  Bench bench(options);
  return bench.run();
}

const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& scenario, const std::string& method,
                         int threads) {
  for (const auto& row : rows) {
    if (row.scenario == scenario && row.method == method && row.threads == threads) return &row;
  }
  return nullptr;
}

}  // namespace hipfai::bench
