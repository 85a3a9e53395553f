#include "studies/hjc_cohort.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/literature.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "core/version.h"
#include "geometry/hip_generator.h"
#include "geometry/hjc.h"
#include "geometry/hjc_regions.h"
#include "studies/results_file.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <sstream>

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

std::string csv_escape(const std::string& s) {
  return s.find(',') == std::string::npos ? s : "\"" + s + "\"";
}

std::string fmt(double value, int digits = 3) {
  if (!std::isfinite(value)) return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
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

HjcCohortResult run_hjc_cohort(const HjcCohortOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (options.ce_deg.empty()) throw_error("hjc cohort: no base hips");
  if (options.replicates < 1) throw_error("hjc cohort: replicates must be at least 1");
  HjcCohortResult result;
  const std::vector<Perturbation> list = perturbations(options.include_fine);
  const std::vector<std::pair<std::string, std::pair<std::string, std::string>>> surfaces{
      {"articular", {"femoral_cartilage", "acetabular_cartilage"}}, {"bone", {"femur_bone", "acetabular_bone"}}};

  // Generated hips per (ce, level); fine and coarse only for the middle CE (generation is the slow part).
  std::size_t jobs = 0;
  for (std::size_t h = 0; h < options.ce_deg.size(); ++h) {
    for (const auto& p : list) {
      if ((p.level == "coarse" || p.level == "fine") && h != options.ce_deg.size() / 2) continue;
      jobs += (p.random ? options.replicates : 1) * surfaces.size();
    }
  }
  ProgressBar progress("hjc cohort", jobs, options.progress);
  for (std::size_t h = 0; h < options.ce_deg.size(); ++h) {
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
      if ((perturbation.level == "coarse" || perturbation.level == "fine") && h != options.ce_deg.size() / 2) continue;
      const geometry::HipModel& model = model_for(perturbation.level);
      const Eigen::Matrix3d frame = (Eigen::Matrix3d() << model.axes.flexion_axis, model.axes.adduction_axis,
                                     model.axes.internal_rotation_axis).finished();
      const int replicates = perturbation.random ? options.replicates : 1;
      for (const auto& [surface, tissues] : surfaces) {
        for (int r = 0; r < replicates; ++r) {
          std::mt19937 rng(static_cast<unsigned>(1000003u * (h + 1) + 7919u * pi + 31u * static_cast<unsigned>(r)));
          TriMesh femur = model.tissue(tissues.first);
          TriMesh pelvis = model.tissue(tissues.second);
          perturbation.apply(femur, pelvis, model, rng);
          geometry::HjcRequest request;
          request.femur = &femur;
          request.pelvis = &pelvis;
          request.femur_long_axis = model.superior;
          request.femur_name = std::string(hip_name) + " " + tissues.first;
          request.pelvis_name = std::string(hip_name) + " " + tissues.second;
          std::vector<geometry::HjcMethodResult> methods;
          std::string failure;
          try {
            methods = geometry::estimate_hjc(request).methods;
          } catch (const Error& e) {
            failure = e.what();
          }
          for (const auto& name : geometry::hjc_method_names()) {
            HjcCohortRow row;
            row.hip = hip_name;
            row.surface = surface;
            row.perturbation = perturbation.name;
            row.method = name;
            row.replicate = r;
            row.error_mm = std::numeric_limits<double>::quiet_NaN();
            row.residual_motion_rms_mm = std::numeric_limits<double>::quiet_NaN();
            for (const auto& m : methods) {
              if (m.name != name || !m.ok) continue;
              row.ok = true;
              row.error_vector_mm = frame.transpose() * (m.center_mm - model.hjc_mm);
              row.error_mm = row.error_vector_mm.norm();
              row.rms_mm = m.rms_mm;
              row.max_mm = m.max_mm;
              row.residual_motion_rms_mm = m.residual_motion_rms_mm;
            }
            result.rows.push_back(row);
          }
          progress.advance();
        }
      }
    }
  }
  progress.finish();

  // Summary per (surface, perturbation, method), in the order met.
  std::vector<std::string> order;
  std::map<std::string, HjcCohortSummary> summary;
  std::map<std::string, std::vector<double>> errors;
  for (const auto& row : result.rows) {
    const std::string key = row.surface + "|" + row.perturbation + "|" + row.method;
    if (!summary.count(key)) {
      order.push_back(key);
      summary[key] = {row.surface, row.perturbation, row.method};
    }
    if (row.ok) errors[key].push_back(row.error_mm); else ++summary[key].failed;
  }
  for (const auto& key : order) {
    HjcCohortSummary& s = summary[key];
    const auto& e = errors[key];
    s.count = static_cast<int>(e.size());
    if (e.empty()) continue;
    double sum = 0.0, max = 0.0;
    for (const double x : e) { sum += x; max = std::max(max, x); }
    s.mean_mm = sum / static_cast<double>(e.size());
    double var = 0.0;
    for (const double x : e) var += (x - s.mean_mm) * (x - s.mean_mm);
    s.sd_mm = e.size() > 1 ? std::sqrt(var / static_cast<double>(e.size() - 1)) : 0.0;
    s.max_mm = max;
    result.summary.push_back(s);
  }

  // Files.
  std::filesystem::create_directories(options.out_dir);
  std::ostringstream rows_csv;
  rows_csv << "hip,surface,perturbation,replicate,method,ok,error_mm,error_x_mm,error_y_mm,error_z_mm,fit_rms_mm,"
              "fit_max_mm,residual_motion_rms_mm\n";
  rows_csv.precision(6);
  for (const auto& r : result.rows) {
    rows_csv << r.hip << ',' << r.surface << ',' << csv_escape(r.perturbation) << ',' << r.replicate << ',' << r.method
             << ',' << (r.ok ? 1 : 0) << ',' << r.error_mm << ',' << r.error_vector_mm.x() << ','
             << r.error_vector_mm.y() << ',' << r.error_vector_mm.z() << ',' << r.rms_mm << ',' << r.max_mm << ','
             << r.residual_motion_rms_mm << '\n';
  }
  write_file_atomically(options.out_dir / "cohort.csv", rows_csv.str());
  std::ostringstream summary_csv;
  summary_csv << "surface,perturbation,method,n,failed,mean_error_mm,sd_error_mm,max_error_mm\n";
  for (const auto& s : result.summary) {
    summary_csv << s.surface << ',' << csv_escape(s.perturbation) << ',' << s.method << ',' << s.count << ','
                << s.failed << ',' << fmt(s.mean_mm, 4) << ',' << fmt(s.sd_mm, 4) << ',' << fmt(s.max_mm, 4) << '\n';
  }
  write_file_atomically(options.out_dir / "cohort_summary.csv", summary_csv.str());

  // Markdown: one table per surface, perturbations as rows, methods as columns (mean +- SD (max)),
  // then the winner per row and its margin over the runner-up.
  std::ostringstream md;
  md << "# HJC estimators against a known centre\n\n"
     << "Generated hips CE " ;
  for (std::size_t i = 0; i < options.ce_deg.size(); ++i) md << (i ? ", " : "") << options.ce_deg[i];
  md << " deg (alpha 40; cam: alpha 80), " << options.edge_mm << " mm edges (coarse " << options.coarse_edge_mm
     << ", fine " << options.fine_edge_mm << " mm, CE " << options.ce_deg[options.ce_deg.size() / 2]
     << " only); random perturbations " << options.replicates
     << " replicates per hip. Error = |estimate - true centre| in mm: mean +- SD (max). Code " << kGitSha
     << ". Definitions: studies/hjc_cohort.h.\n\n";
  for (const std::string surface : {"articular", "bone"}) {
    md << "## " << (surface == "articular" ? "Articular surfaces (femoral and acetabular cartilage)"
                                           : "Bones (femur bone, acetabular bone)")
       << "\n\n| perturbation | n |";
    for (const auto& m : geometry::hjc_method_names()) md << ' ' << m << " |";
    md << " best | margin to 2nd |\n|---|---|";
    for (std::size_t i = 0; i < geometry::hjc_method_names().size() + 2; ++i) md << "---|";
    md << '\n';
    std::vector<std::string> seen;
    for (const auto& s : result.summary) {
      if (s.surface != surface || std::find(seen.begin(), seen.end(), s.perturbation) != seen.end()) continue;
      seen.push_back(s.perturbation);
      std::vector<std::pair<double, std::string>> ranking;
      int n = 0;
      md << "| " << s.perturbation << " |";
      std::ostringstream cells;
      for (const auto& m : geometry::hjc_method_names()) {
        const auto& t = summary[surface + "|" + s.perturbation + "|" + m];
        n = std::max(n, t.count + t.failed);
        if (t.count == 0) { cells << " failed |"; continue; }
        cells << ' ' << fmt(t.mean_mm, 2) << " +- " << fmt(t.sd_mm, 2) << " (" << fmt(t.max_mm, 2) << ")"
              << (t.failed ? " [" + std::to_string(t.failed) + " failed]" : "") << " |";
        ranking.push_back({t.mean_mm, m});
      }
      std::sort(ranking.begin(), ranking.end());
      md << ' ' << n << " |" << cells.str();
      if (ranking.size() >= 2) {
        md << ' ' << ranking[0].second << " | " << fmt(ranking[1].first - ranking[0].first, 2) << " mm vs "
           << ranking[1].second << " |\n";
      } else {
        md << " - | - |\n";
      }
    }
    md << '\n';
  }
  // Overall: mean error of each method over every perturbation and surface.
  md << "## Overall (every perturbation, both surfaces)\n\n| method | n | mean error (mm) | SD | max |\n|---|---|---|---|---|\n";
  for (const auto& m : geometry::hjc_method_names()) {
    std::vector<double> e;
    for (const auto& r : result.rows) if (r.method == m && r.ok) e.push_back(r.error_mm);
    double sum = 0.0, max = 0.0;
    for (const double x : e) { sum += x; max = std::max(max, x); }
    const double mean = e.empty() ? 0.0 : sum / static_cast<double>(e.size());
    double var = 0.0;
    for (const double x : e) var += (x - mean) * (x - mean);
    md << "| " << m << " | " << e.size() << " | " << fmt(mean, 3) << " | "
       << fmt(e.size() > 1 ? std::sqrt(var / static_cast<double>(e.size() - 1)) : 0.0, 3) << " | " << fmt(max, 3) << " |\n";
  }
  result.report_path = options.out_dir / "cohort.md";
  write_file_atomically(result.report_path, md.str());

  {
    ResultsFile h5(options.out_dir / "cohort.h5");
    h5.set_attribute("/", "units", "mm");
    h5.set_attribute("/", "git_sha", kGitSha);
    h5.set_attribute("/", "study", "hjc cohort: HJC estimators against a known centre");
    std::vector<std::string> hip, surface, perturbation, method;
    std::vector<double> values;
    for (const auto& r : result.rows) {
      hip.push_back(r.hip);
      surface.push_back(r.surface);
      perturbation.push_back(r.perturbation);
      method.push_back(r.method);
      values.insert(values.end(), {r.error_mm, r.error_vector_mm.x(), r.error_vector_mm.y(), r.error_vector_mm.z(),
                                   r.rms_mm, r.max_mm, r.residual_motion_rms_mm, static_cast<double>(r.replicate)});
    }
    h5.write_strings("/rows/hip", hip);
    h5.write_strings("/rows/surface", surface);
    h5.write_strings("/rows/perturbation", perturbation);
    h5.write_strings("/rows/method", method);
    h5.write("/rows/values", values, 8, "mm");
    h5.set_attribute("/rows/values", "columns",
                     "error_mm,error_x_mm,error_y_mm,error_z_mm,fit_rms_mm,fit_max_mm,residual_motion_rms_mm,replicate");
    h5.commit();
  }
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
