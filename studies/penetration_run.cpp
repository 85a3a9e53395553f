#include "studies/penetration_run.h"

#include "contact/cylindrical_cache_io.h"
#include "contact/cylindrical_segmenting.h"
#include "contact/radial_segmenting.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/literature.h"
#include "geometry/sphere_split.h"
#include "studies/radial_table_cache.h"

#include <algorithm>
#include <chrono>
#include <optional>

namespace hipfai::studies {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Copy of `mesh` with vertices rotated by `rotation` about `centre` (triangles are not needed
// by the queries, which read mobile vertices only, but are kept for VTP output).
double longest_edge(const geometry::TriMesh& mesh) {
  double longest = 0.0;
  for (const auto& tri : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      longest = std::max(longest, (mesh.vertices[static_cast<std::size_t>(tri[e])] -
                                   mesh.vertices[static_cast<std::size_t>(tri[(e + 1) % 3])]).norm());
    }
  }
  return longest;
}

// Which pairs count (see "Touching is not penetrating" in the header).
struct PairFilter {
  const geometry::TriMesh* mobile = nullptr;  // for the striking test; null: radial depth test
  geometry::Vec3 centre = geometry::Vec3::Zero();
  double min_distance_mm = 0.0;                // striking: |v - c| > this
  double min_depth_mm = 0.0;                   // radial: depth > this
  // Radial, when set: the vertex (of `points`) plus its depth must stay within max_reach_mm of the
  // centre (where the ray leaves the mobile solid).
  const geometry::TriMesh* points = nullptr;
  double max_reach_mm = 0.0;
  bool keep(const contact::PenetrationPair& pair) const {
    if (mobile) {
      return (mobile->vertices[static_cast<std::size_t>(pair.mobile_vertex)] - centre).norm() > min_distance_mm;
    }
    if (points && (points->vertices[static_cast<std::size_t>(pair.mobile_vertex)] - centre).norm() + pair.depth_mm >
                      max_reach_mm) {
      return false;
    }
    return pair.depth_mm > min_depth_mm;
  }
};

// Pairs of mobile vertices at or past step_field.size() are samples added on the striking
// boundary (geometry::split_at_sphere): they count towards the step's maximum depth only.
void record(const contact::PenetrationResult& result, const PairFilter& filter, std::vector<double>& step_field,
            std::vector<double>& max_field, double& max_depth, int& count) {
  if (result.status == contact::QueryStatus::kInvalidInput) throw_error(result.message);
  for (const auto& pair : result.pairs) {
    if (!filter.keep(pair)) continue;
    const auto v = static_cast<std::size_t>(pair.mobile_vertex);
    if (v >= step_field.size()) {
      max_depth = std::max(max_depth, pair.depth_mm);
      continue;
    }
    step_field[v] = pair.depth_mm;
    max_field[v] = std::max(max_field[v], pair.depth_mm);
    max_depth = std::max(max_depth, pair.depth_mm);
    ++count;
  }
}

// The file `name` in the cache folder, the folder made when it does not exist yet (a run from an
// empty working directory); a folder that cannot be made is reported by the write that follows.
std::filesystem::path cache_file(const std::filesystem::path& cache_dir, const std::string& name) {
  std::error_code error;
  std::filesystem::create_directories(cache_dir, error);
  return cache_dir / name;
}

contact::RadialTable radial_table_for(const geometry::TriMesh& fixed, const std::string& fixed_hash,
                                      const geometry::Vec3& centre, const PenetrationOptions& options,
                                      StageLog& log) {
  contact::RadialTableOptions table_options;
  table_options.mapping = options.mapping;
  table_options.table_size = options.table_size;
  std::filesystem::path file;
  if (!options.cache_dir.empty()) {
    Hasher key;
    key.add(fixed_hash).add(centre.x()).add(centre.y()).add(centre.z());
    key.add(static_cast<std::int64_t>(options.mapping)).add(options.table_size);
    file = cache_file(options.cache_dir, "radial-table-" + key.hex() + ".bin");
    if (auto cached = load_radial_table(file);
        cached && cached->num_triangles == fixed.num_triangles()) {
      log.hit(StageKind::kRadialTable);
      contact::compute_radial_spans(*cached, fixed);  // not stored in the file: derived from `fixed`
      return std::move(*cached);
    }
  }
  contact::RadialTable table = contact::build_radial_table(fixed, centre, table_options);
  log.ran(StageKind::kRadialTable);
  if (!file.empty()) save_radial_table(table, file);
  return table;
}

// The pose cache of `mobile` against `fixed` about `axis` through `centre` (§3.2.3.2): loaded from
// the cache folder when an identical one was built before, else built (table + cache) and saved.
contact::CylindricalPoseCache pose_cache_for(const geometry::TriMesh& fixed, const std::string& fixed_hash,
                                             const geometry::TriMesh& mobile, const std::string& mobile_hash,
                                             const geometry::Vec3& centre, const Eigen::Vector3d& axis,
                                             const PenetrationOptions& options, StageLog& log) {
  std::filesystem::path file;
  if (!options.cache_dir.empty()) {
    Hasher key;
    key.add(fixed_hash).add(mobile_hash).add(centre.x()).add(centre.y()).add(centre.z());
    key.add(axis.x()).add(axis.y()).add(axis.z());
    file = cache_file(options.cache_dir, "cylindrical-pose-cache-" + key.hex() + ".bin");
    if (auto cached = contact::load_pose_cache(file)) {
      log.hit(StageKind::kCylindricalTable);
      return std::move(*cached);
    }
  }
  contact::CylindricalQueryOptions query;
  query.num_threads = options.threads;
  contact::CylindricalTableOptions table_options;
  table_options.angular_index = false;  // the pose cache reads every crossing
  const auto table = contact::CylindricalTable::build(fixed, centre, axis, table_options, &mobile);
  contact::CylindricalPoseCache cache(table, mobile, query);
  log.ran(StageKind::kCylindricalTable);
  if (!file.empty()) contact::save_pose_cache(cache, file);
  return cache;
}

}  // namespace

double PenetrationRun::max_curvilinear_mm() const {
  double deepest = 0.0;
  for (const auto& step : steps) deepest = std::max(deepest, step.curvilinear_max_mm());
  return deepest;
}

double PenetrationRun::max_radial_mm() const {
  double deepest = 0.0;
  for (const auto& step : steps) deepest = std::max(deepest, step.radial_max_mm());
  return deepest;
}

PenetrationRun compute_penetration(const LoadedHip& hip, const Motion& motion,
                                   const PenetrationOptions& options, StageLog& log,
                                   const StepObserver& observer) {
  PenetrationRun run;
  const std::size_t steps = motion.steps.size();
  run.steps.resize(steps);
  const geometry::Vec3& centre = hip.hjc_mm;
  // Hip-frame rotations expressed in model coordinates.
  std::vector<Eigen::Matrix3d> rotation(steps);
  std::vector<Eigen::Vector3d> axis(steps);
  for (std::size_t k = 0; k < steps; ++k) {
    rotation[k] = hip.frame * motion.steps[k].rotation * hip.frame.transpose();
    axis[k] = (hip.frame * motion.steps[k].axis).normalized();
  }
  std::vector<DepthFields> step_fields(steps);
  if (options.contact_tolerance_mm >= 0.0) {
    run.contact_tolerance_mm = options.contact_tolerance_mm;
  } else {
    double longest = 0.0;
    for (const auto& [name, mesh] : hip.tissues) longest = std::max(longest, longest_edge(mesh));
    run.contact_tolerance_mm =
        std::max(longest * longest / (2.0 * hip.articular_radius_mm), literature::kSphericityToleranceMm);
  }
  const double tolerance = run.contact_tolerance_mm;
  if (hip.tissues.count("femur_bone") && hip.tissues.count("labrum")) {
    contact::StartPoseOptions start;
    start.touching_mm = tolerance;
    start.centre = centre;
    start.num_threads = options.threads;
    run.neutral_overlap = contact::check_start_pose(hip.tissues.at("labrum"), hip.tissues.at("femur_bone"), start);
    if (run.neutral_overlap.status == contact::QueryStatus::kInvalidInput) {
      throw_error(hip.id, ": ", run.neutral_overlap.message);
    }
    if (run.neutral_overlap.overlaps()) {
      throw_error(hip.id, ": femur_bone (mobile) and labrum (fixed) already intersect in the neutral pose: ",
                  run.neutral_overlap.summary(), " (tolerance ", tolerance, " mm); every depth of the motion would include it");
    }
  }
  PairFilter radial_filter;
  radial_filter.min_depth_mm = tolerance;
  auto field = [&](DepthFields& fields, const std::string& key, std::size_t n) -> std::vector<double>& {
    auto& values = fields[key];
    if (values.empty()) values.assign(n, 0.0);
    return values;
  };

  if (options.curvilinear) {
    const auto& femur_mesh = hip.tissues.at("femur_bone");
    const auto& labrum_mesh = hip.tissues.at("labrum");
    // The striking region of each side begins at the sphere R + tolerance, where its curvilinear
    // depth is largest (the cam's flank runs along under the labrum's face): sampled there too.
    const double striking_mm = hip.articular_radius_mm + tolerance;
    std::optional<geometry::SphereSplit> femur_split, labrum_split;
    if (options.sample_striking_boundary) {
      femur_split = geometry::split_at_sphere(femur_mesh, centre, striking_mm);
      labrum_split = geometry::split_at_sphere(labrum_mesh, centre, striking_mm);
    }
    const geometry::TriMesh& femur = femur_split ? femur_split->mesh : femur_mesh;
    const geometry::TriMesh& labrum = labrum_split ? labrum_split->mesh : labrum_mesh;
    const std::string femur_hash = femur_split ? geometry::mesh_hash(femur) : hip.mesh_hash.at("femur_bone");
    const std::string labrum_hash = labrum_split ? geometry::mesh_hash(labrum) : hip.mesh_hash.at("labrum");
    // Boundary samples lie on the sphere up to rounding: kept from a hair inside it.
    const double striking_filter_mm = femur_split ? striking_mm * (1.0 - 1e-12) : striking_mm;
    contact::CylindricalQueryOptions query;
    query.num_threads = options.threads;
    for (const auto& shared_axis : distinct_axes(motion)) {
      const Eigen::Vector3d model_axis = (hip.frame * shared_axis).normalized();
      const auto start = Clock::now();
      const contact::CylindricalPoseCache femur_cache = pose_cache_for(
          labrum_mesh, hip.mesh_hash.at("labrum"), femur, femur_hash, centre, model_axis, options, log);
      contact::CylindricalPoseCache labrum_cache;
      if (options.swap_roles) {
        labrum_cache = pose_cache_for(femur_mesh, hip.mesh_hash.at("femur_bone"), labrum, labrum_hash, centre,
                                      model_axis, options, log);
      }
      run.curvilinear_preprocessing_ms += ms_since(start);
      for (std::size_t k = 0; k < steps; ++k) {
        if ((motion.steps[k].axis - shared_axis).norm() >= 1e-9) continue;
        const auto query_start = Clock::now();
        auto& s = run.steps[k];
        PairFilter striking_femur{&femur, centre, striking_filter_mm, 0.0};
        record(femur_cache.query(motion.steps[k].angle_deg), striking_femur,
               field(step_fields[k], "femur_bone/curvilinear_depth_mm", femur_mesh.num_vertices()),
               field(run.max_fields, "femur_bone/curvilinear_depth_mm", femur_mesh.num_vertices()),
               s.curvilinear_mm, s.curvilinear_vertices);
        log.ran(StageKind::kCylindricalQuery);
        if (options.swap_roles) {
          // The femur turning by +angle is the labrum turning by -angle relative to it.
          PairFilter striking_labrum{&labrum, centre, striking_filter_mm, 0.0};
          record(labrum_cache.query(-motion.steps[k].angle_deg), striking_labrum,
                 field(step_fields[k], "labrum/curvilinear_depth_mm", labrum_mesh.num_vertices()),
                 field(run.max_fields, "labrum/curvilinear_depth_mm", labrum_mesh.num_vertices()),
                 s.curvilinear_swap_mm, s.curvilinear_vertices);
          log.ran(StageKind::kCylindricalQuery);
        }
        s.curvilinear_ms += ms_since(query_start);
      }
    }
  }

  if (options.radial) {
    // Femur side: bone and cartilage together (the cam is bone; thesis §4.3.2.1 speaks of "femur
    // vertices"); socket side: acetabular cartilage and labrum. Each side is a union of touching
    // closed solids, so the kUnion crossing rule measures depth from the side's outer boundary.
    const auto& bone = hip.tissues.at("femur_bone");
    const auto& cartilage = hip.tissues.at("femoral_cartilage");
    const auto& acetabular = hip.tissues.at("acetabular_cartilage");
    const auto& labrum = hip.tissues.at("labrum");
    const geometry::TriMesh femur = geometry::merge_meshes({&bone, &cartilage});
    const geometry::TriMesh socket = geometry::merge_meshes({&acetabular, &labrum});
    const auto start = Clock::now();
    const contact::RadialTable socket_table = radial_table_for(
        socket, hip.mesh_hash.at("acetabular_cartilage") + hip.mesh_hash.at("labrum"), centre, options, log);
    contact::RadialTable femur_table;
    if (options.swap_roles) {
      femur_table = radial_table_for(femur, hip.mesh_hash.at("femur_bone") + hip.mesh_hash.at("femoral_cartilage"),
                                     centre, options, log);
    }
    contact::RadialQueryOptions inside;
    inside.configuration = contact::RadialConfiguration::kMobileInsideFixed;
    inside.rule = options.radial_rule;
    inside.num_threads = options.threads;
    contact::RadialQueryOptions outside = inside;
    outside.configuration = contact::RadialConfiguration::kFixedInsideMobile;
    // Each side prepared once for the motion (contact::RadialPoseQuery): its vertices in buckets,
    // those a step's spans rule out dropped whole; the same answers as the query on the posed mesh.
    const contact::RadialPoseQuery femur_in_socket(socket_table, socket, femur, inside);
    std::optional<contact::RadialPoseQuery> socket_in_femur;
    if (options.swap_roles) socket_in_femur.emplace(femur_table, femur, socket, outside);
    run.radial_preprocessing_ms = ms_since(start);
    // Records a merged side's per-vertex result under its two tissues' names.
    // The swap role: a socket vertex inside the femur counts where the femoral head holds it. The
    // socket's soft tissues reach no farther from the HJC than their outermost vertex; where the
    // ray from the HJC leaves the femur beyond that, it runs along the neck or the shaft (a whole
    // segmented femur at a large angle), and the distance to that exit is not a depth into the head.
    PairFilter swap_filter = radial_filter;
    swap_filter.points = &socket;
    swap_filter.centre = centre;
    for (const geometry::Vec3& v : socket.vertices) {
      swap_filter.max_reach_mm = std::max(swap_filter.max_reach_mm, (v - centre).norm());
    }
    auto record_split = [&](std::size_t k, const contact::PenetrationResult& result, const PairFilter& filter,
                            const std::string& first, std::size_t n_first, const std::string& second,
                            std::size_t n_second, double& max_depth, int& count) {
      std::vector<double> step_values(n_first + n_second, 0.0), max_values(n_first + n_second, 0.0);
      record(result, filter, step_values, max_values, max_depth, count);
      auto& step_a = field(step_fields[k], first + "/radial_depth_mm", n_first);
      auto& step_b = field(step_fields[k], second + "/radial_depth_mm", n_second);
      auto& max_a = field(run.max_fields, first + "/radial_depth_mm", n_first);
      auto& max_b = field(run.max_fields, second + "/radial_depth_mm", n_second);
      for (std::size_t v = 0; v < n_first + n_second; ++v) {
        if (v < n_first) {
          step_a[v] = step_values[v];
          max_a[v] = std::max(max_a[v], step_values[v]);
        } else {
          step_b[v - n_first] = step_values[v];
          max_b[v - n_first] = std::max(max_b[v - n_first], step_values[v]);
        }
      }
    };
    for (std::size_t k = 0; k < steps; ++k) {
      auto& s = run.steps[k];
      const auto query_start = Clock::now();
      record_split(k, femur_in_socket.query_rotation(rotation[k]), radial_filter, "femur_bone", bone.num_vertices(),
                   "femoral_cartilage", cartilage.num_vertices(), s.radial_mm, s.radial_vertices);
      log.ran(StageKind::kRadialQuery);
      if (options.swap_roles) {
        // The socket seen from the femur turns by the inverse rotation.
        record_split(k, socket_in_femur->query_rotation(rotation[k].transpose()), swap_filter,
                     "acetabular_cartilage", acetabular.num_vertices(), "labrum", labrum.num_vertices(),
                     s.radial_swap_mm, s.radial_vertices);
        log.ran(StageKind::kRadialQuery);
      }
      s.radial_ms += ms_since(query_start);
    }
  }

  if (options.rom) {
    const auto& femur = hip.tissues.at("femur_bone");
    const auto& pelvis = hip.tissues.at("acetabular_bone");
    for (const auto& shared_axis : distinct_axes(motion)) {
      const Eigen::Vector3d model_axis = (hip.frame * shared_axis).normalized();
      contact::RangeOfMotionOptions rom_options;
      rom_options.query.num_threads = options.threads;
      run.rom_axes.push_back(model_axis);
      run.rom.push_back(contact::range_of_motion(pelvis, femur, centre, model_axis, rom_options));
      log.ran(StageKind::kRangeOfMotion);
    }
  }

  if (observer) {
    for (std::size_t k = 0; k < steps; ++k) observer(k, step_fields[k]);
  }
  return run;
}

}  // namespace hipfai::studies
