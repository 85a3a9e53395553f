#include "studies/pipeline/penetration_run.h"

#include "contact/penetrate.h"
#include "core/error.h"
#include "core/literature.h"
#include "geometry/sphere_split.h"

#include <algorithm>
#include <optional>

namespace hipfai::studies {

namespace {

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

// The per-step and per-motion fields of a run, made on first use.
struct FieldSink {
  PenetrationRun& run;
  std::vector<DepthFields>& step_fields;
  std::vector<double>& field(DepthFields& fields, const std::string& key, std::size_t n) const {
    auto& values = fields[key];
    if (values.empty()) values.assign(n, 0.0);
    return values;
  }
  std::vector<double>& step(std::size_t k, const std::string& key, std::size_t n) const {
    return field(step_fields[k], key, n);
  }
  std::vector<double>& max(const std::string& key, std::size_t n) const { return field(run.max_fields, key, n); }
};

// The contact tolerance the run applies (see "Touching is not penetrating" in the header).
double contact_tolerance(const LoadedHip& hip, const PenetrationOptions& options) {
  if (options.contact_tolerance_mm >= 0.0) return options.contact_tolerance_mm;
  double longest = 0.0;
  for (const auto& [name, mesh] : hip.tissues) longest = std::max(longest, longest_edge(mesh));
  return std::max(longest * longest / (2.0 * hip.articular_radius_mm), literature::kSphericityToleranceMm);
}

// Femur bone against labrum in the neutral pose (PenetrationRun::neutral_overlap).
void check_neutral_pose(const LoadedHip& hip, const PenetrationOptions& options, PenetrationRun& run) {
  if (!hip.tissues.count("femur_bone") || !hip.tissues.count("labrum")) return;
  const double tolerance = run.contact_tolerance_mm;
  contact::StartPoseOptions start;
  start.touching_mm = tolerance;
  start.centre = hip.hjc_mm;
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

// A request about the HJC for the motion's steps in model coordinates. The curvilinear axis of a
// step is that of the first distinct axis of the motion it matches, so the steps about one axis
// share one pre-processing.
contact::PenetrationRequest motion_request(const LoadedHip& hip, const Motion& motion, const PenetrationOptions& options) {
  contact::PenetrationRequest request;
  request.centre = hip.hjc_mm;
  request.num_threads = options.threads;
  request.cache_dir = options.cache_dir;
  const std::vector<Eigen::Vector3d> axes = distinct_axes(motion);
  for (const MotionStep& step : motion.steps) {
    contact::PenetrationStep posed;
    posed.rotation = hip.frame * step.rotation * hip.frame.transpose();
    for (const auto& shared_axis : axes) {
      if ((step.axis - shared_axis).norm() >= 1e-9) continue;
      posed.axis = (hip.frame * shared_axis).normalized();
      break;
    }
    posed.angle_deg = step.angle_deg;
    request.steps.push_back(posed);
  }
  return request;
}

// The same motion seen from the other body: every rotation inverted.
contact::PenetrationRequest swapped_request(contact::PenetrationRequest request) {
  std::swap(request.fixed, request.mobile);
  std::swap(request.fixed_key, request.mobile_key);
  for (contact::PenetrationStep& step : request.steps) {
    step.rotation.transposeInPlace();
    step.angle_deg = -step.angle_deg;
  }
  return request;
}

contact::PenetrationResponse penetrate_or_throw(const contact::PenetrationRequest& request) {
  contact::PenetrationResponse response = contact::penetrate(request);
  if (response.status == contact::QueryStatus::kInvalidInput) throw_error(response.message);
  return response;
}

void log_preprocessing(const contact::PreprocessingCount& count, StageKind kind, StageLog& log) {
  for (int i = 0; i < count.loaded; ++i) log.hit(kind);
  for (int i = 0; i < count.built; ++i) log.ran(kind);
}

// Records one side's curvilinear pairs of every step under `tissue` (with `vertices` vertices),
// its deepest per step in `max_depth`.
void record_curvilinear(const contact::PenetrationResponse& response, const PairFilter& filter,
                        const std::string& tissue, std::size_t vertices, double StepPenetration::*max_depth,
                        const FieldSink& sink, StageLog& log) {
  log_preprocessing(response.curvilinear_preprocessing, StageKind::kCylindricalTable, log);
  sink.run.curvilinear_preprocessing_ms += response.curvilinear_preprocessing_ms;
  const std::string key = tissue + "/curvilinear_depth_mm";
  for (std::size_t k = 0; k < response.steps.size(); ++k) {
    StepPenetration& s = sink.run.steps[k];
    record(response.steps[k].curvilinear, filter, sink.step(k, key, vertices), sink.max(key, vertices), s.*max_depth,
           s.curvilinear_vertices);
    s.curvilinear_ms += response.steps[k].curvilinear_ms;
    log.ran(StageKind::kCylindricalQuery);
  }
}

// Curvilinear depth, femur bone in the labrum and (swap) labrum in the femur bone.
void curvilinear_depths(const LoadedHip& hip, const Motion& motion, const PenetrationOptions& options,
                        const FieldSink& sink, StageLog& log) {
  const geometry::Vec3& centre = hip.hjc_mm;
  const auto& femur_mesh = hip.tissues.at("femur_bone");
  const auto& labrum_mesh = hip.tissues.at("labrum");
  // The striking region of each side begins at the sphere R + tolerance, where its curvilinear
  // depth is largest (the cam's flank runs along under the labrum's face): sampled there too.
  const double striking_mm = hip.articular_radius_mm + sink.run.contact_tolerance_mm;
  std::optional<geometry::SphereSplit> femur_split, labrum_split;
  if (options.sample_striking_boundary) {
    femur_split = geometry::split_at_sphere(femur_mesh, centre, striking_mm);
    labrum_split = geometry::split_at_sphere(labrum_mesh, centre, striking_mm);
  }
  const geometry::TriMesh& femur = femur_split ? femur_split->mesh : femur_mesh;
  const geometry::TriMesh& labrum = labrum_split ? labrum_split->mesh : labrum_mesh;
  // Boundary samples lie on the sphere up to rounding: kept from a hair inside it.
  const double striking_filter_mm = femur_split ? striking_mm * (1.0 - 1e-12) : striking_mm;
  contact::PenetrationRequest request = motion_request(hip, motion, options);
  request.curvilinear = true;
  request.fixed = &labrum_mesh;
  request.fixed_key = hip.mesh_hash.at("labrum");
  request.mobile = &femur;
  request.mobile_key = femur_split ? geometry::mesh_hash(femur) : hip.mesh_hash.at("femur_bone");
  record_curvilinear(penetrate_or_throw(request), PairFilter{&femur, centre, striking_filter_mm, 0.0},
                     "femur_bone", femur_mesh.num_vertices(), &StepPenetration::curvilinear_mm, sink, log);
  if (!options.swap_roles) return;
  // The femur turning by +angle is the labrum turning by -angle relative to it; the labrum's
  // boundary samples (when any) are its vertices, the femur bone as it is the fixed side.
  contact::PenetrationRequest swap = swapped_request(request);
  swap.fixed = &femur_mesh;
  swap.fixed_key = hip.mesh_hash.at("femur_bone");
  swap.mobile = &labrum;
  swap.mobile_key = labrum_split ? geometry::mesh_hash(labrum) : hip.mesh_hash.at("labrum");
  record_curvilinear(penetrate_or_throw(swap), PairFilter{&labrum, centre, striking_filter_mm, 0.0}, "labrum",
                     labrum_mesh.num_vertices(), &StepPenetration::curvilinear_swap_mm, sink, log);
}

// Records a merged side's per-vertex result of step k under its two tissues' names.
void record_split(const FieldSink& sink, std::size_t k, const contact::PenetrationResult& result,
                  const PairFilter& filter, const std::string& first, std::size_t n_first, const std::string& second,
                  std::size_t n_second, double& max_depth, int& count) {
  std::vector<double> step_values(n_first + n_second, 0.0), max_values(n_first + n_second, 0.0);
  record(result, filter, step_values, max_values, max_depth, count);
  auto& step_a = sink.step(k, first + "/radial_depth_mm", n_first);
  auto& step_b = sink.step(k, second + "/radial_depth_mm", n_second);
  auto& max_a = sink.max(first + "/radial_depth_mm", n_first);
  auto& max_b = sink.max(second + "/radial_depth_mm", n_second);
  for (std::size_t v = 0; v < n_first + n_second; ++v) {
    if (v < n_first) {
      step_a[v] = step_values[v];
      max_a[v] = std::max(max_a[v], step_values[v]);
    } else {
      step_b[v - n_first] = step_values[v];
      max_b[v - n_first] = std::max(max_b[v - n_first], step_values[v]);
    }
  }
}

// Radial depth, the femur (bone and cartilage) in the socket's soft tissues and (swap) the socket
// in the femur.
void radial_depths(const LoadedHip& hip, const Motion& motion, const PenetrationOptions& options,
                   const FieldSink& sink, StageLog& log) {
  PenetrationRun& run = sink.run;
  // Femur side: bone and cartilage together (the cam is bone; thesis §4.3.2.1 speaks of "femur
  // vertices"); socket side: acetabular cartilage and labrum. Each side is a union of touching
  // closed solids, so the kUnion crossing rule measures depth from the side's outer boundary.
  const auto& bone = hip.tissues.at("femur_bone");
  const auto& cartilage = hip.tissues.at("femoral_cartilage");
  const auto& acetabular = hip.tissues.at("acetabular_cartilage");
  const auto& labrum = hip.tissues.at("labrum");
  const geometry::TriMesh femur = geometry::merge_meshes({&bone, &cartilage});
  const geometry::TriMesh socket = geometry::merge_meshes({&acetabular, &labrum});
  contact::PenetrationRequest request = motion_request(hip, motion, options);
  request.radial = true;
  request.radial_rule = options.radial_rule;
  request.radial_table.mapping = options.mapping;
  request.radial_table.table_size = options.table_size;
  request.fixed = &socket;
  request.fixed_key = hip.mesh_hash.at("acetabular_cartilage") + hip.mesh_hash.at("labrum");
  request.mobile = &femur;
  const contact::PenetrationResponse femur_in_socket = penetrate_or_throw(request);
  log_preprocessing(femur_in_socket.radial_preprocessing, StageKind::kRadialTable, log);
  run.radial_preprocessing_ms = femur_in_socket.radial_preprocessing_ms;
  PairFilter radial_filter;
  radial_filter.min_depth_mm = run.contact_tolerance_mm;
  for (std::size_t k = 0; k < motion.steps.size(); ++k) {
    auto& s = run.steps[k];
    record_split(sink, k, femur_in_socket.steps[k].radial, radial_filter, "femur_bone", bone.num_vertices(),
                 "femoral_cartilage", cartilage.num_vertices(), s.radial_mm, s.radial_vertices);
    s.radial_ms += femur_in_socket.steps[k].radial_ms;
    log.ran(StageKind::kRadialQuery);
  }
  if (!options.swap_roles) return;
  // The socket seen from the femur turns by the inverse rotation.
  contact::PenetrationRequest swap = swapped_request(request);
  swap.radial_configuration = contact::RadialConfiguration::kFixedInsideMobile;
  swap.fixed_key = hip.mesh_hash.at("femur_bone") + hip.mesh_hash.at("femoral_cartilage");
  const contact::PenetrationResponse socket_in_femur = penetrate_or_throw(swap);
  log_preprocessing(socket_in_femur.radial_preprocessing, StageKind::kRadialTable, log);
  run.radial_preprocessing_ms += socket_in_femur.radial_preprocessing_ms;
  // The swap role: a socket vertex inside the femur counts where the femoral head holds it. The
  // socket's soft tissues reach no farther from the HJC than their outermost vertex; where the
  // ray from the HJC leaves the femur beyond that, it runs along the neck or the shaft (a whole
  // segmented femur at a large angle), and the distance to that exit is not a depth into the head.
  PairFilter swap_filter = radial_filter;
  swap_filter.points = &socket;
  swap_filter.centre = hip.hjc_mm;
  for (const geometry::Vec3& v : socket.vertices) {
    swap_filter.max_reach_mm = std::max(swap_filter.max_reach_mm, (v - hip.hjc_mm).norm());
  }
  for (std::size_t k = 0; k < motion.steps.size(); ++k) {
    auto& s = run.steps[k];
    record_split(sink, k, socket_in_femur.steps[k].radial, swap_filter, "acetabular_cartilage",
                 acetabular.num_vertices(), "labrum", labrum.num_vertices(), s.radial_swap_mm, s.radial_vertices);
    s.radial_ms += socket_in_femur.steps[k].radial_ms;
    log.ran(StageKind::kRadialQuery);
  }
}

// The exact range of motion about each distinct axis of the motion.
void ranges_of_motion(const LoadedHip& hip, const Motion& motion, const PenetrationOptions& options,
                      PenetrationRun& run, StageLog& log) {
  const auto& femur = hip.tissues.at("femur_bone");
  const auto& pelvis = hip.tissues.at("acetabular_bone");
  for (const auto& shared_axis : distinct_axes(motion)) {
    const Eigen::Vector3d model_axis = (hip.frame * shared_axis).normalized();
    contact::RangeOfMotionOptions rom_options;
    rom_options.query.num_threads = options.threads;
    run.rom_axes.push_back(model_axis);
    run.rom.push_back(contact::range_of_motion(pelvis, femur, hip.hjc_mm, model_axis, rom_options));
    log.ran(StageKind::kRangeOfMotion);
  }
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

std::vector<double> PenetrationRun::curvilinear_maxima_mm() const {
  std::vector<double> maxima;
  for (const auto& step : steps) maxima.push_back(step.curvilinear_max_mm());
  return maxima;
}

std::vector<double> PenetrationRun::radial_maxima_mm() const {
  std::vector<double> maxima;
  for (const auto& step : steps) maxima.push_back(step.radial_max_mm());
  return maxima;
}

PenetrationRun compute_penetration(const LoadedHip& hip, const Motion& motion,
                                   const PenetrationOptions& options, StageLog& log,
                                   const StepObserver& observer) {
  PenetrationRun run;
  const std::size_t steps = motion.steps.size();
  run.steps.resize(steps);
  std::vector<DepthFields> step_fields(steps);
  const FieldSink sink{run, step_fields};
  run.contact_tolerance_mm = contact_tolerance(hip, options);
  check_neutral_pose(hip, options, run);
  if (options.curvilinear) curvilinear_depths(hip, motion, options, sink, log);
  if (options.radial) radial_depths(hip, motion, options, sink, log);
  if (options.rom) ranges_of_motion(hip, motion, options, run, log);
  if (observer) {
    for (std::size_t k = 0; k < steps; ++k) observer(k, step_fields[k]);
  }
  return run;
}

}  // namespace hipfai::studies
