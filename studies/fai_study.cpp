#include "studies/fai_study.h"

#include "contact/radial_mapping.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "geometry/mesh_io.h"
#include "studies/fai_report.h"
#include "studies/hip_sensitivity.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/penetration_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

namespace hipfai::studies {

namespace {

using Clock = SteadyClock;

std::string model_id(double ce, double alpha) { return parametric_hip_id(ce, alpha); }

// One model: generate (or reuse) the hip, run the penetration method over the motion.
FaiModelRun run_model(double ce, double alpha, double edge_mm, const Motion& motion,
                   const FaiStudyOptions& options, StageLog& log) {
  Scene scene;
  scene.name = model_id(ce, alpha);
  scene.parametric = ParametricHip{ce, alpha, edge_mm, options.base_parameters};
  scene.outputs = {Output::kCurvilinearDepth, Output::kRadialDepth};
  for (Output o : scene.outputs) {
    const auto t = tissues_for(o);
    scene.tissues.insert(t.begin(), t.end());
  }
  FaiModelRun model;
  const auto start = Clock::now();
  model.hip = acquire_hip(scene, scene.tissues, options.cache_dir, log);
  put_femur_at_neutral(model.hip, options.femoral_neutral);
  model.summary.generate_s = seconds_since(start);
  PenetrationOptions penetration;
  penetration.mapping = options.mapping;
  penetration.radial_rule = options.radial_rule;
  penetration.table_size = options.table_size;
  penetration.threads = options.threads;
  penetration.cache_dir = options.cache_dir;
  penetration.contact_tolerance_mm = options.contact_tolerance_mm;
  penetration.sample_striking_boundary = options.sample_striking_boundary;
  const auto compute_start = Clock::now();
  const std::string id = model_id(ce, alpha);
  const bool wants_vtp = edge_mm == options.edge_mm &&
                         std::find(options.vtp_models.begin(), options.vtp_models.end(), id) != options.vtp_models.end();
  auto write_step_vtp = [&](std::size_t step, const DepthFields& fields) {
    bool wanted = false;
    for (int s : options.vtp_steps) {
      wanted = wanted || (s == 0 ? step + 1 == motion.steps.size() : step + 1 == static_cast<std::size_t>(s));
    }
    if (!wanted) return;
    std::filesystem::create_directories(options.out_dir / "vtp");
    std::map<std::string, geometry::TriMesh> coloured;
    for (const auto& [key, values] : fields) {
      const std::string tissue = key.substr(0, key.find('/'));
      auto [it, inserted] = coloured.try_emplace(tissue, model.hip.tissues.at(tissue));
      it->second.vertex_fields[key.substr(key.find('/') + 1)] = values;
    }
    for (const auto& [tissue, mesh] : coloured) {
      std::ostringstream name;
      name << id << '_' << tissue << "_step" << std::setw(3) << std::setfill('0') << (step + 1) << ".vtp";
      geometry::write_mesh(mesh, options.out_dir / "vtp" / name.str());
    }
  };
  model.run = wants_vtp ? compute_penetration(model.hip, motion, penetration, log, write_step_vtp)
                        : compute_penetration(model.hip, motion, penetration, log);
  model.summary.penetration_ms = 1e3 * seconds_since(compute_start);
  model.summary.ce_deg = ce;
  model.summary.alpha_deg = alpha;
  model.summary.max_curvilinear_mm = model.run.max_curvilinear_mm();
  model.summary.max_radial_mm = model.run.max_radial_mm();
  model.summary.pathology = pathology_of(ce, alpha);
  // Where impingement begins along the motion's single axis (exact, hip_sensitivity.h).
  model.summary.first_contact_deg = first_striking_contact_deg(
      model.hip.tissues.at("femur_bone"), model.hip.tissues.at("labrum"), model.hip.hjc_mm,
      (model.hip.frame * motion.steps.front().axis).normalized(),
      model.hip.articular_radius_mm + model.run.contact_tolerance_mm, options.threads,
      options.sample_striking_boundary);
  return model;
}

void normalise(std::vector<FaiModelSummary>& models) {
  double max_c = 0, max_r = 0;
  for (const auto& m : models) max_c = std::max(max_c, m.max_curvilinear_mm), max_r = std::max(max_r, m.max_radial_mm);
  for (auto& m : models) {
    m.normalised_difference = (max_c > 0 ? m.max_curvilinear_mm / max_c : 0.0) -
                              (max_r > 0 ? m.max_radial_mm / max_r : 0.0);
  }
}



}  // namespace

const FaiModelSummary* find_fai_model(const std::vector<FaiModelSummary>& models, double ce_deg, double alpha_deg) {
  for (const auto& m : models) {
    if (m.ce_deg == ce_deg && m.alpha_deg == alpha_deg) return &m;
  }
  return nullptr;
}

const std::vector<std::pair<std::string, std::pair<double, double>>>& fai_archetypes() {
  static const std::vector<std::pair<std::string, std::pair<double, double>>> archetypes{
      {"normal", {20, 40}}, {"pincer", {40, 40}}, {"cam", {20, 80}}, {"combined cam-pincer", {40, 80}},
      {"dysplasia", {0, 40}}, {"combined dysplasia-impingement", {0, 80}}};
  return archetypes;
}

std::string pathology_of(double ce_deg, double alpha_deg) {
  const bool cam = alpha_deg > 50.0;
  if (ce_deg < 20.0) return cam ? "combined dysplasia-impingement" : "dysplasia";
  if (ce_deg >= 40.0) return cam ? "combined cam-pincer" : "pincer";
  return cam ? "cam" : "normal";
}

std::string curvilinear_band(double d) {
  if (d <= 0.0) return "none";
  if (d < 5) return "very low";
  if (d < 10) return "low";
  if (d < 15) return "intermediate";
  if (d < 20) return "high";
  return "very high";
}

std::string radial_band(double d) {
  if (d <= 0.0) return "none";
  if (d < 2) return "very low";
  if (d < 4) return "low";
  if (d < 6) return "intermediate";
  if (d < 8) return "high";
  return "very high";
}

std::string difference_band(double x) {
  if (x < -0.2) return "very low";
  if (x < 0.0) return "low";
  if (x < 0.2) return "intermediate";
  return "high";
}

FaiStudyResult compute_fai_study(const FaiStudyOptions& options) {
  const auto study_start = Clock::now();
  FaiStudyResult result;
  result.motion = standing_to_sitting(options.sub_motions, options.pose_sequence);
  const Motion& motion = result.motion;
  auto& runs = result.runs;
  StageLog log;
  {
    ProgressBar progress("fai study: " + std::to_string(options.ce_deg.size() * options.alpha_deg.size()) +
                             " hips",
                         options.ce_deg.size() * options.alpha_deg.size(), options.progress);
    for (double ce : options.ce_deg) {
      for (double alpha : options.alpha_deg) {
        FaiModelRun model = run_model(ce, alpha, options.edge_mm, motion, options, log);
        result.models.push_back(model.summary);
        runs.emplace(model_id(ce, alpha), std::move(model));
        progress.advance();
      }
    }
  }
  normalise(result.models);

  // --- accuracy vs resolution --------------------------------------------------------------------
  {
    std::vector<double> edges = options.resolution_edges_mm;
    if (std::find(edges.begin(), edges.end(), options.edge_mm) == edges.end()) edges.push_back(options.edge_mm);
    std::sort(edges.rbegin(), edges.rend());
    for (double edge : edges) {
      FaiResolutionRow row{edge, 0.0, 0.0, {}, 0};
      double penetration_ms = 0;
      int step_count = 0;
      const auto start = Clock::now();
      for (const auto& [name, angles] : fai_archetypes()) {
        if (!find_fai_model(result.models, angles.first, angles.second)) continue;
        StageLog resolution_log;
        const FaiModelRun model = edge == options.edge_mm ? FaiModelRun{}
                                                       : run_model(angles.first, angles.second, edge, motion,
                                                                   options, resolution_log);
        const FaiModelRun& used = edge == options.edge_mm ? runs.at(model_id(angles.first, angles.second)) : model;
        row.maxima[name] = {used.summary.max_curvilinear_mm, used.summary.max_radial_mm};
        penetration_ms += used.summary.penetration_ms;
        step_count += static_cast<int>(used.run.steps.size());
        row.femur_vertices = used.hip.tissues.at("femur_bone").num_vertices();
      }
      row.seconds = seconds_since(start);
      row.penetration_ms_per_step = step_count ? penetration_ms / step_count : 0.0;
      result.resolution.push_back(row);
    }
  }
  result.total_seconds = seconds_since(study_start);
  return result;
}

FaiStudyResult run_fai_study(const FaiStudyOptions& options) {
  std::filesystem::create_directories(options.out_dir);
  FaiStudyResult result = compute_fai_study(options);
  write_fai_study_outputs(result, options);
  return result;
}

}  // namespace hipfai::studies
