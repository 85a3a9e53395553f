#include "studies/fai_unit.h"

#include "core/stopwatch.h"
#include "geometry/mesh_io.h"
#include "studies/hip_sensitivity.h"
#include "studies/pipeline/penetration_run.h"

#include <algorithm>
#include <iomanip>
#include <map>
#include <sstream>

namespace hipfai::studies {

std::vector<FaiUnit> fai_study_units(const FaiStudyOptions& options) {
  std::vector<FaiUnit> units;
  for (const double ce : options.ce_deg) {
    for (const double alpha : options.alpha_deg) units.push_back({ce, alpha, options.edge_mm});
  }
  std::vector<double> edges = options.resolution_edges_mm;
  std::sort(edges.rbegin(), edges.rend());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  const auto on_grid = [&](double ce, double alpha) {
    return std::find(options.ce_deg.begin(), options.ce_deg.end(), ce) != options.ce_deg.end() &&
           std::find(options.alpha_deg.begin(), options.alpha_deg.end(), alpha) != options.alpha_deg.end();
  };
  for (const double edge : edges) {
    if (edge == options.edge_mm) continue;
    for (const auto& [name, angles] : fai_archetypes()) {
      if (on_grid(angles.first, angles.second)) units.push_back({angles.first, angles.second, edge});
    }
  }
  return units;
}

std::string fai_unit_name(const FaiUnit& unit, const FaiStudyOptions& options) {
  std::string name = parametric_hip_id(unit.ce_deg, unit.alpha_deg);
  if (unit.edge_mm != options.edge_mm) {
    std::ostringstream edge;
    edge << unit.edge_mm;
    name += " at " + edge.str() + " mm";
  }
  return name;
}

LoadedHip load_fai_unit_hip(const FaiUnit& unit, const FaiStudyOptions& options, StageLog& log) {
  Scene scene;
  scene.name = parametric_hip_id(unit.ce_deg, unit.alpha_deg);
  scene.parametric = ParametricHip{unit.ce_deg, unit.alpha_deg, unit.edge_mm, options.base_parameters};
  scene.outputs = {Output::kCurvilinearDepth, Output::kRadialDepth};
  for (Output o : scene.outputs) {
    const auto t = tissues_for(o);
    scene.tissues.insert(t.begin(), t.end());
  }
  LoadedHip hip = acquire_hip(scene, scene.tissues, options.cache_dir, log);
  put_femur_at_neutral(hip, options.femoral_neutral);
  return hip;
}

FaiModelRun run_fai_unit(const FaiUnit& unit, const Motion& motion, const FaiStudyOptions& options, StageLog& log) {
  const auto start = SteadyClock::now();
  FaiModelRun model;
  model.hip = load_fai_unit_hip(unit, options, log);
  model.summary.generate_s = seconds_since(start);
  PenetrationOptions penetration;
  penetration.mapping = options.mapping;
  penetration.radial_rule = options.radial_rule;
  penetration.table_size = options.table_size;
  penetration.threads = options.threads;
  penetration.cache_dir = options.cache_dir;
  penetration.contact_tolerance_mm = options.contact_tolerance_mm;
  penetration.sample_striking_boundary = options.sample_striking_boundary;
  const auto compute_start = SteadyClock::now();
  const std::string id = parametric_hip_id(unit.ce_deg, unit.alpha_deg);
  const bool wants_vtp = unit.edge_mm == options.edge_mm &&
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
  model.summary.ce_deg = unit.ce_deg;
  model.summary.alpha_deg = unit.alpha_deg;
  model.summary.max_curvilinear_mm = model.run.max_curvilinear_mm();
  model.summary.max_radial_mm = model.run.max_radial_mm();
  model.summary.pathology = pathology_of(unit.ce_deg, unit.alpha_deg);
  // Where impingement begins along the motion's single axis (exact, hip_sensitivity.h).
  model.summary.first_contact_deg = first_striking_contact_deg(
      model.hip.tissues.at("femur_bone"), model.hip.tissues.at("labrum"), model.hip.hjc_mm,
      (model.hip.frame * motion.steps.front().axis).normalized(),
      model.hip.articular_radius_mm + model.run.contact_tolerance_mm, options.threads,
      options.sample_striking_boundary);
  model.seconds = seconds_since(start);
  return model;
}

}  // namespace hipfai::studies
