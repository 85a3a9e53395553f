#include "studies/hjc_cohort.h"

#include "core/error.h"
#include "core/literature.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "geometry/hip_generator.h"
#include "geometry/hjc.h"
#include "geometry/hjc_regions.h"
#include "studies/hjc_cohort_report.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <random>

namespace hipfai::studies {
namespace {

using geometry::TriMesh;
using geometry::Vec3;

constexpr double kNoiseCorrelationMm = 3.0;

// Smooth random scalar field: standard normal values on a lattice of spacing `cell`,
// trilinearly interpolated (value noise), scaled to RMS `rms` over the mesh's vertices.
std::vector<double> smooth_field(const TriMesh& mesh, double cell, double rms, std::mt19937& rng) {
  const geometry::BoundingBox box = geometry::bounding_box(mesh);
  const Eigen::Vector3i dims = ((box.extent() / cell).array().ceil().cast<int>() + 2).matrix();
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> lattice(static_cast<std::size_t>(dims.x()) * dims.y() * dims.z());
  for (double& v : lattice) v = normal(rng);
  auto at = [&](int x, int y, int z) {
    return lattice[(static_cast<std::size_t>(z) * dims.y() + y) * dims.x() + x];
  };
  std::vector<double> field(mesh.num_vertices());
  double sum2 = 0.0;
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 local = (mesh.vertices[v] - box.min) / cell;
    const Eigen::Vector3i i0 = local.array().floor().cast<int>().matrix().cwiseMax(0).cwiseMin(dims - Eigen::Vector3i::Constant(2));
    const Vec3 f = local - i0.cast<double>();
    double value = 0.0;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const double w = (dx ? f.x() : 1 - f.x()) * (dy ? f.y() : 1 - f.y()) * (dz ? f.z() : 1 - f.z());
          value += w * at(i0.x() + dx, i0.y() + dy, i0.z() + dz);
        }
    field[v] = value;
    sum2 += value * value;
  }
  const double scale = sum2 > 0.0 ? rms / std::sqrt(sum2 / static_cast<double>(field.size())) : 0.0;
  for (double& v : field) v *= scale;
  return field;
}

void add_noise(TriMesh& mesh, double rms, std::mt19937& rng) {
  const std::vector<Vec3> normals = geometry::vertex_normals(mesh);
  const std::vector<double> field = smooth_field(mesh, kNoiseCorrelationMm, rms, rng);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) mesh.vertices[v] += field[v] * normals[v];
}

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Vec3 u;
  do { u = Vec3(normal(rng), normal(rng), normal(rng)); } while (u.norm() < 1e-6);
  return u.normalized();
}

// Head -> ellipsoid with semi-axes R + e, R, R - e about `centre`, random orientation.
void make_aspherical(TriMesh& mesh, const Vec3& centre, double radius, double e, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Matrix3d q =
      Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().toRotationMatrix();
  const Eigen::Matrix3d s = q * Eigen::Vector3d(1.0 + e / radius, 1.0, 1.0 - e / radius).asDiagonal() * q.transpose();
  for (Vec3& p : mesh.vertices) p = centre + s * (p - centre);
}

// Socket pushed out radially from `centre` by amplitude (1 + u.e) / 2.
void make_uneven_gap(TriMesh& mesh, const Vec3& centre, double amplitude, const Vec3& e) {
  for (Vec3& p : mesh.vertices) {
    const Vec3 d = p - centre;
    const double r = d.norm();
    if (!(r > 0.0)) continue;
    p += amplitude * 0.5 * (1.0 + d.dot(e) / r) * d / r;
  }
}

struct Perturbation {
  std::string name;
  std::string level = "base";   // which generated hip: base, cam, coarse, fine
  bool random = false;          // replicated
  std::function<void(TriMesh& femur, TriMesh& pelvis, const geometry::HipModel&, std::mt19937&)> apply;
};

std::vector<Perturbation> perturbations(bool include_fine) {
  std::vector<Perturbation> list;
  list.push_back({"clean", "base", false, [](TriMesh&, TriMesh&, const geometry::HipModel&, std::mt19937&) {}});
  // Up to the thesis' bone segmentation accuracy.
  for (const double s : {literature::kSegmentationAccuracyMm / 3.0, 2.0 * literature::kSegmentationAccuracyMm / 3.0,
                         literature::kSegmentationAccuracyMm}) {
    char name[64];
    std::snprintf(name, sizeof(name), "noise %.1f mm", s);
    list.push_back({name, "base", true, [s](TriMesh& f, TriMesh& p, const geometry::HipModel&, std::mt19937& rng) {
                      add_noise(f, s, rng);
                      add_noise(p, s, rng);
                    }});
  }
  for (const double e : {0.5, 1.0}) {
    char name[64];
    std::snprintf(name, sizeof(name), "asphericity %.1f mm", e);
    list.push_back({name, "base", true, [e](TriMesh& f, TriMesh&, const geometry::HipModel& m, std::mt19937& rng) {
                      make_aspherical(f, m.hjc_mm, m.parameters.articular_radius_mm, e, rng);
                    }});
  }
  for (const double a : {0.5, 1.0}) {
    char name[64];
    std::snprintf(name, sizeof(name), "uneven joint space %.1f mm", a);
    list.push_back({name, "base", true, [a](TriMesh&, TriMesh& p, const geometry::HipModel& m, std::mt19937& rng) {
                      make_uneven_gap(p, m.hjc_mm, a, random_unit(rng));
                    }});
  }
  list.push_back({"cam (alpha 80)", "cam", false, [](TriMesh&, TriMesh&, const geometry::HipModel&, std::mt19937&) {}});
  list.push_back({"partial lunate (half)", "base", true,
                  [](TriMesh&, TriMesh& p, const geometry::HipModel& m, std::mt19937& rng) {
                    // A plane through the centre containing the acetabular axis, random about it.
                    Vec3 n = random_unit(rng);
                    n -= n.dot(m.acetabular_axis) * m.acetabular_axis;
                    const Vec3 normal = n.normalized();
                    p = geometry::submesh_where(p, [&](const Vec3& x) { return (x - m.hjc_mm).dot(normal) <= 0.0; });
                  }});
  list.push_back({"coarse mesh", "coarse", false, [](TriMesh&, TriMesh&, const geometry::HipModel&, std::mt19937&) {}});
  if (include_fine) {
    list.push_back({"fine mesh", "fine", false, [](TriMesh&, TriMesh&, const geometry::HipModel&, std::mt19937&) {}});
  }
  return list;
}

// The two surface sets fitted: (femur tissue, pelvis tissue).
const std::vector<std::pair<std::string, std::pair<std::string, std::string>>>& surface_sets() {
  static const std::vector<std::pair<std::string, std::pair<std::string, std::string>>> surfaces{
      {"articular", {"femoral_cartilage", "acetabular_cartilage"}}, {"bone", {"femur_bone", "acetabular_bone"}}};
  return surfaces;
}

// Fine and coarse meshes only for the middle CE (generation is the slow part).
bool runs_on_hip(const HjcCohortOptions& options, const Perturbation& perturbation, std::size_t h) {
  return !((perturbation.level == "coarse" || perturbation.level == "fine") && h != options.ce_deg.size() / 2);
}

std::size_t cohort_jobs(const HjcCohortOptions& options, const std::vector<Perturbation>& list) {
  std::size_t jobs = 0;
  for (std::size_t h = 0; h < options.ce_deg.size(); ++h) {
    for (const auto& p : list) {
      if (!runs_on_hip(options, p, h)) continue;
      jobs += (p.random ? options.replicates : 1) * surface_sets().size();
    }
  }
  return jobs;
}

// One row per method of one estimate: its error against the true centre, in the hip frame.
void add_method_rows(const std::vector<geometry::HjcMethodResult>& methods, const geometry::HipModel& model,
                     HjcCohortRow base, std::vector<HjcCohortRow>& rows) {
  const Eigen::Matrix3d frame = (Eigen::Matrix3d() << model.axes.flexion_axis, model.axes.adduction_axis,
                                 model.axes.internal_rotation_axis).finished();
  base.error_mm = std::numeric_limits<double>::quiet_NaN();
  base.residual_motion_rms_mm = std::numeric_limits<double>::quiet_NaN();
  for (const auto& name : geometry::hjc_method_names()) {
    HjcCohortRow row = base;
    row.method = name;
    for (const auto& m : methods) {
      if (m.name != name || !m.ok) continue;
      row.ok = true;
      row.error_vector_mm = frame.transpose() * (m.center_mm - model.hjc_mm);
      row.error_mm = row.error_vector_mm.norm();
      row.rms_mm = m.rms_mm;
      row.max_mm = m.max_mm;
      row.residual_motion_rms_mm = m.residual_motion_rms_mm;
    }
    rows.push_back(row);
  }
}

// The five methods on one perturbed surface set; a method that throws fails every row.
std::vector<geometry::HjcMethodResult> estimate_perturbed(const geometry::HipModel& model, const std::string& hip_name,
                                                          const std::pair<std::string, std::string>& tissues,
                                                          const Perturbation& perturbation, std::mt19937& rng) {
  TriMesh femur = model.tissue(tissues.first);
  TriMesh pelvis = model.tissue(tissues.second);
  perturbation.apply(femur, pelvis, model, rng);
  geometry::HjcRequest request;
  request.femur = &femur;
  request.pelvis = &pelvis;
  request.femur_long_axis = model.superior;
  request.femur_name = hip_name + " " + tissues.first;
  request.pelvis_name = hip_name + " " + tissues.second;
  try {
    return geometry::estimate_hjc(request).methods;
  } catch (const Error&) {
    return {};
  }
}

// Every perturbation, surface set and replicate of the base hip of CE options.ce_deg[h].
void hip_rows(const HjcCohortOptions& options, std::size_t h, const std::vector<Perturbation>& list,
              ProgressBar& progress, std::vector<HjcCohortRow>& rows) {
  const double ce = options.ce_deg[h];
  std::map<std::string, geometry::HipModel> models;
  auto model_for = [&](const std::string& level) -> const geometry::HipModel& {
    auto it = models.find(level);
    if (it != models.end()) return it->second;
    geometry::HipParameters parameters;
    parameters.ce_deg = ce;
    parameters.alpha_deg = level == "cam" ? 80.0 : 40.0;
    parameters.edge_mm = level == "coarse" ? options.coarse_edge_mm : level == "fine" ? options.fine_edge_mm : options.edge_mm;
    return models.emplace(level, geometry::generate_hip(parameters).model).first->second;
  };
  char hip_name[32];
  std::snprintf(hip_name, sizeof(hip_name), "ce%.0f", ce);
  for (std::size_t pi = 0; pi < list.size(); ++pi) {
    const Perturbation& perturbation = list[pi];
    if (!runs_on_hip(options, perturbation, h)) continue;
    const geometry::HipModel& model = model_for(perturbation.level);
    const int replicates = perturbation.random ? options.replicates : 1;
    for (const auto& [surface, tissues] : surface_sets()) {
      for (int r = 0; r < replicates; ++r) {
        std::mt19937 rng(static_cast<unsigned>(1000003u * (h + 1) + 7919u * pi + 31u * static_cast<unsigned>(r)));
        const auto methods = estimate_perturbed(model, hip_name, tissues, perturbation, rng);
        HjcCohortRow base;
        base.hip = hip_name;
        base.surface = surface;
        base.perturbation = perturbation.name;
        base.replicate = r;
        add_method_rows(methods, model, base, rows);
        progress.advance();
      }
    }
  }
}

// Count, mean, SD (n - 1) and maximum of the errors; 0 where there are none.
void summarise_errors(const std::vector<double>& e, HjcCohortSummary& s) {
  s.count = static_cast<int>(e.size());
  double sum = 0.0, max = 0.0;
  for (const double x : e) { sum += x; max = std::max(max, x); }
  s.mean_mm = e.empty() ? 0.0 : sum / static_cast<double>(e.size());
  double var = 0.0;
  for (const double x : e) var += (x - s.mean_mm) * (x - s.mean_mm);
  s.sd_mm = e.size() > 1 ? std::sqrt(var / static_cast<double>(e.size() - 1)) : 0.0;
  s.max_mm = max;
}

// Per (surface, perturbation, method), in the order met.
std::vector<HjcCohortSummary> summarise(const std::vector<HjcCohortRow>& rows) {
  std::vector<std::string> order;
  std::map<std::string, HjcCohortSummary> summary;
  std::map<std::string, std::vector<double>> errors;
  for (const auto& row : rows) {
    const std::string key = row.surface + "|" + row.perturbation + "|" + row.method;
    if (!summary.count(key)) {
      order.push_back(key);
      summary[key] = {row.surface, row.perturbation, row.method};
    }
    if (row.ok) errors[key].push_back(row.error_mm); else ++summary[key].failed;
  }
  std::vector<HjcCohortSummary> out;
  for (const auto& key : order) {
    if (errors[key].empty()) continue;
    summarise_errors(errors[key], summary[key]);
    out.push_back(summary[key]);
  }
  return out;
}

std::vector<HjcCohortSummary> overall(const std::vector<HjcCohortRow>& rows) {
  std::vector<HjcCohortSummary> out;
  for (const auto& m : geometry::hjc_method_names()) {
    HjcCohortSummary s{"", "", m};
    std::vector<double> e;
    for (const auto& r : rows) {
      if (r.method != m) continue;
      if (r.ok) e.push_back(r.error_mm); else ++s.failed;
    }
    summarise_errors(e, s);
    out.push_back(s);
  }
  return out;
}

}  // namespace

void perturb_like_segmentation(TriMesh& head_surface, TriMesh& socket_surface, const geometry::HipModel& model,
                               double noise_mm, double asphericity_mm, double uneven_gap_mm, unsigned seed) {
  std::mt19937 rng(seed);
  if (asphericity_mm > 0.0) {
    make_aspherical(head_surface, model.hjc_mm, model.parameters.articular_radius_mm, asphericity_mm, rng);
  }
  if (uneven_gap_mm > 0.0) make_uneven_gap(socket_surface, model.hjc_mm, uneven_gap_mm, random_unit(rng));
  if (noise_mm > 0.0) {
    add_noise(head_surface, noise_mm, rng);
    add_noise(socket_surface, noise_mm, rng);
  }
}

HjcCohortResult compute_hjc_cohort(const HjcCohortOptions& options) {
  if (options.ce_deg.empty()) throw_error("hjc cohort: no base hips");
  if (options.replicates < 1) throw_error("hjc cohort: replicates must be at least 1");
  HjcCohortResult result;
  result.options = options;
  const std::vector<Perturbation> list = perturbations(options.include_fine);
  ProgressBar progress("hjc cohort", cohort_jobs(options, list), options.progress);
  for (std::size_t h = 0; h < options.ce_deg.size(); ++h) hip_rows(options, h, list, progress, result.rows);
  progress.finish();
  result.summary = summarise(result.rows);
  result.overall = overall(result.rows);
  return result;
}

HjcCohortResult run_hjc_cohort(const HjcCohortOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  HjcCohortResult result = compute_hjc_cohort(options);
  result.report_path = write_hjc_cohort_report(result, options.out_dir);
  result.seconds = seconds_since(start);
  return result;
}

HjcCohortOptions quick_hjc_cohort_options(HjcCohortOptions base) {
  base.ce_deg = {20.0};
  base.replicates = 2;
  base.include_fine = false;
  base.edge_mm = 3.0;
  return base;
}

}  // namespace hipfai::studies
