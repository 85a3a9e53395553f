#include "studies/fai_study.h"

#include "contact/radial_mapping.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/version.h"
#include "geometry/mesh_io.h"
#include "studies/fai_reference.h"
#include "studies/hip_sensitivity.h"
#include "studies/penetration_run.h"
#include "studies/results_file.h"
#include "studies/svg_plot.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <sstream>

namespace hipfai::studies {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string model_id(double ce, double alpha) {
  std::ostringstream id;
  id << "ce" << ce << "_alpha" << alpha;
  return id.str();
}

std::string fixed(double value, int digits = 2) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

struct ModelRun {
  FaiModelSummary summary;
  PenetrationRun run;
  LoadedHip hip;
};

// One model: generate (or reuse) the hip, run the penetration method over the motion.
ModelRun run_model(double ce, double alpha, double edge_mm, const Motion& motion,
                   const FaiStudyOptions& options, StageLog& log) {
  Scene scene;
  scene.name = model_id(ce, alpha);
  scene.parametric = ParametricHip{ce, alpha, edge_mm};
  scene.outputs = {Output::kCurvilinearDepth, Output::kRadialDepth};
  for (Output o : scene.outputs) {
    const auto t = tissues_for(o);
    scene.tissues.insert(t.begin(), t.end());
  }
  ModelRun model;
  const auto start = Clock::now();
  model.hip = acquire_hip(scene, scene.tissues, options.cache_dir, log);
  model.summary.generate_s = seconds_since(start);
  PenetrationOptions penetration;
  penetration.mapping = options.mapping;
  penetration.table_size = options.table_size;
  penetration.threads = options.threads;
  penetration.cache_dir = options.cache_dir;
  penetration.contact_tolerance_mm = options.contact_tolerance_mm;
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
      model.hip.articular_radius_mm + model.run.contact_tolerance_mm, options.threads);
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

void write_csv(const std::filesystem::path& path, const std::string& text) { write_file_atomically(path, text); }

const FaiModelSummary* find(const std::vector<FaiModelSummary>& models, double ce, double alpha) {
  for (const auto& m : models) {
    if (m.ce_deg == ce && m.alpha_deg == alpha) return &m;
  }
  return nullptr;
}

}  // namespace

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

FaiStudyResult run_fai_study(const FaiStudyOptions& options) {
  const auto study_start = Clock::now();
  std::filesystem::create_directories(options.out_dir);
  const Motion motion = standing_to_sitting(options.sub_motions);
  FaiStudyResult result;
  std::map<std::string, ModelRun> runs;
  StageLog log;
  {
    ProgressBar progress("fai study: " + std::to_string(options.ce_deg.size() * options.alpha_deg.size()) +
                             " hips",
                         options.ce_deg.size() * options.alpha_deg.size(), options.progress);
    for (double ce : options.ce_deg) {
      for (double alpha : options.alpha_deg) {
        ModelRun model = run_model(ce, alpha, options.edge_mm, motion, options, log);
        result.models.push_back(model.summary);
        runs.emplace(model_id(ce, alpha), std::move(model));
        progress.advance();
      }
    }
  }
  normalise(result.models);

  // --- results.h5 ---------------------------------------------------------------------------
  {
    ResultsFile file(options.out_dir / "results.h5");
    file.set_attribute("/", "study", "fai penetration (thesis 4.3)");
    file.set_attribute("/", "code_version", std::string(kVersion) + " " + kGitSha);
    file.set_attribute("/", "units", "length mm, angle deg, time ms");
    file.set_attribute("/", "motion", motion.name + ", " + std::to_string(motion.steps.size()) + " sub-motions");
    file.set_attribute("/", "edge_mm", options.edge_mm);
    file.set_attribute("/", "radial_mapping", contact::to_string(options.mapping));
    file.set_attribute("/", "radial_table_size", static_cast<double>(options.table_size));
    std::vector<double> ce, alpha, max_c, max_r, diff;
    for (const auto& m : result.models) {
      ce.push_back(m.ce_deg), alpha.push_back(m.alpha_deg), max_c.push_back(m.max_curvilinear_mm);
      max_r.push_back(m.max_radial_mm), diff.push_back(m.normalised_difference);
    }
    file.write("/summary/ce_deg", ce, 1, "deg");
    file.write("/summary/alpha_deg", alpha, 1, "deg");
    file.write("/summary/max_curvilinear_mm", max_c, 1, "mm");
    file.write("/summary/max_radial_mm", max_r, 1, "mm");
    file.write("/summary/normalised_difference", diff, 1, "1");
    std::vector<double> angles;
    for (const auto& step : motion.steps) angles.push_back(step.angle_deg);
    file.write("/motion/angle_deg", angles, 1, "deg");
    for (const auto& [id, model] : runs) {
      const std::string group = "/models/" + id;
      std::vector<double> c, r, c_ms, r_ms;
      for (const auto& s : model.run.steps) {
        c.push_back(s.curvilinear_max_mm()), r.push_back(s.radial_max_mm());
        c_ms.push_back(s.curvilinear_ms), r_ms.push_back(s.radial_ms);
      }
      file.write(group + "/curvilinear_max_mm", c, 1, "mm");
      file.write(group + "/radial_max_mm", r, 1, "mm");
      file.write(group + "/curvilinear_query_ms", c_ms, 1, "ms");
      file.write(group + "/radial_query_ms", r_ms, 1, "ms");
      for (const auto& [key, values] : model.run.max_fields) {
        file.write(group + "/fields/" + key, values, 1, "mm (maximum over the motion)");
      }
      for (const auto& [tissue, hash] : model.hip.mesh_hash) {
        file.set_attribute(group, "mesh_hash_" + tissue, hash);
      }
      file.set_attribute(group, "pathology", pathology_of(model.summary.ce_deg, model.summary.alpha_deg));
    }
    file.commit();
  }

  // --- CSV ------------------------------------------------------------------------------------
  {
    std::ostringstream summary, steps;
    summary << "ce_deg,alpha_deg,pathology,max_curvilinear_mm,max_radial_mm,normalised_difference,"
               "curvilinear_band,radial_band,difference_band,penetration_ms,first_contact_deg\n";
    steps << "ce_deg,alpha_deg,step,angle_deg,max_curvilinear_mm,max_radial_mm,curvilinear_ms,radial_ms\n";
    for (const auto& m : result.models) {
      summary << m.ce_deg << ',' << m.alpha_deg << ',' << m.pathology << ',' << m.max_curvilinear_mm << ','
              << m.max_radial_mm << ',' << m.normalised_difference << ',' << curvilinear_band(m.max_curvilinear_mm)
              << ',' << radial_band(m.max_radial_mm) << ',' << difference_band(m.normalised_difference) << ','
              << m.penetration_ms << ',' << m.first_contact_deg << '\n';
      const auto& run = runs.at(model_id(m.ce_deg, m.alpha_deg)).run;
      for (std::size_t k = 0; k < run.steps.size(); ++k) {
        steps << m.ce_deg << ',' << m.alpha_deg << ',' << (k + 1) << ',' << motion.steps[k].angle_deg << ','
              << run.steps[k].curvilinear_max_mm() << ',' << run.steps[k].radial_max_mm() << ','
              << run.steps[k].curvilinear_ms << ',' << run.steps[k].radial_ms << '\n';
      }
    }
    write_csv(options.out_dir / "summary.csv", summary.str());
    write_csv(options.out_dir / "steps.csv", steps.str());
  }

  // --- figures ----------------------------------------------------------------------------------
  std::vector<double> step_angles;
  for (const auto& step : motion.steps) step_angles.push_back(step.angle_deg);
  auto curve_chart = [&](double ce, double alpha, const std::string& file) {
    const auto it = runs.find(model_id(ce, alpha));
    if (it == runs.end()) return std::string();
    LineChart chart;
    chart.title = "Max penetration during standing to sitting, CE " + fixed(ce, 0) + ", alpha " + fixed(alpha, 0);
    chart.x_label = "rotation from neutral (deg)";
    chart.y_label = "max depth (mm)";
    Series c{"curvilinear", step_angles, {}, false}, r{"radial", step_angles, {}, true};
    for (const auto& s : it->second.run.steps) c.y.push_back(s.curvilinear_max_mm()), r.y.push_back(s.radial_max_mm());
    chart.series = {c, r};
    write_svg(chart, options.out_dir / file);
    return file;
  };
  const std::string fig60a = curve_chart(40, 60, "fig60_ce40_alpha60.svg");
  const std::string fig60b = curve_chart(40, 40, "fig60_ce40_alpha40.svg");
  for (const bool radial : {false, true}) {
    LineChart chart;
    chart.title = std::string("Max ") + (radial ? "radial" : "curvilinear") + " penetration vs alpha";
    chart.x_label = "alpha (deg)";
    chart.y_label = "max depth over the motion (mm)";
    for (double ce : options.ce_deg) {
      Series s{"CE " + fixed(ce, 0), options.alpha_deg, {}, false};
      for (double alpha : options.alpha_deg) {
        const auto* m = find(result.models, ce, alpha);
        s.y.push_back(m ? (radial ? m->max_radial_mm : m->max_curvilinear_mm) : NAN);
      }
      chart.series.push_back(s);
    }
    write_svg(chart, options.out_dir / (radial ? "fig62_radial.svg" : "fig62_curvilinear.svg"));
  }
  auto heat = [&](const std::string& title, const std::string& unit, bool diverging_map, auto value_of,
                  const std::string& file, bool text_is_pathology = false) {
    HeatMap map;
    map.title = title;
    map.unit = unit;
    map.row_label = "CE (deg)";
    map.column_label = "alpha (deg)";
    map.diverging = diverging_map;
    for (auto it = options.ce_deg.rbegin(); it != options.ce_deg.rend(); ++it) {
      map.row_names.push_back(fixed(*it, 0));
      std::vector<double> row;
      std::vector<std::string> text;
      for (double alpha : options.alpha_deg) {
        const auto* m = find(result.models, *it, alpha);
        row.push_back(m ? value_of(*m) : NAN);
        text.push_back(text_is_pathology && m ? m->pathology : "");
      }
      map.values.push_back(row);
      map.cell_text.push_back(text);
    }
    for (double alpha : options.alpha_deg) map.column_names.push_back(fixed(alpha, 0));
    write_svg(map, options.out_dir / file);
  };
  heat("Max curvilinear penetration", "mm", false,
       [](const FaiModelSummary& m) { return m.max_curvilinear_mm; }, "fig63_curvilinear.svg");
  heat("Max radial penetration", "mm", false, [](const FaiModelSummary& m) { return m.max_radial_mm; },
       "fig63_radial.svg");
  heat("Normalised curvilinear - radial", "", true,
       [](const FaiModelSummary& m) { return m.normalised_difference; }, "fig63_difference.svg");
  heat("Pathology (colour: normalised difference)", "", true,
       [](const FaiModelSummary& m) { return m.normalised_difference; }, "fig63_pathology.svg", true);

  // A hip coloured by depth: the combined cam-pincer hip (or the deepest model), femur and labrum.
  const FaiModelSummary* deepest = &result.models.front();
  for (const auto& m : result.models) {
    if (m.max_curvilinear_mm + m.max_radial_mm > deepest->max_curvilinear_mm + deepest->max_radial_mm) deepest = &m;
  }
  const FaiModelSummary* shown = find(result.models, 40, 80) ? find(result.models, 40, 80) : deepest;
  std::string hip_figure;
  {
    const auto& model = runs.at(model_id(shown->ce_deg, shown->alpha_deg));
    std::vector<geometry::TriMesh> coloured;
    for (const std::string tissue : {"labrum", "femoral_cartilage", "acetabular_cartilage"}) {
      geometry::TriMesh mesh = model.hip.tissues.at(tissue);
      std::vector<double> depth(mesh.num_vertices(), 0.0);
      for (const std::string quantity : {"curvilinear_depth_mm", "radial_depth_mm"}) {
        const auto it = model.run.max_fields.find(tissue + "/" + quantity);
        if (it == model.run.max_fields.end()) continue;
        for (std::size_t v = 0; v < depth.size(); ++v) depth[v] = std::max(depth[v], it->second[v]);
        mesh.vertex_fields[quantity] = it->second;
      }
      mesh.vertex_fields["depth_mm"] = depth;
      geometry::write_mesh(mesh, options.out_dir / (model_id(shown->ce_deg, shown->alpha_deg) + "_" + tissue + ".vtp"));
      coloured.push_back(std::move(mesh));
    }
    std::vector<const geometry::TriMesh*> parts;
    for (const auto& mesh : coloured) parts.push_back(&mesh);
    const double scale = std::max(1.0, shown->max_radial_mm);
    hip_figure = "hip_" + model_id(shown->ce_deg, shown->alpha_deg) + ".svg";
    // Seen from lateral (looking medially, -X), superior up: the socket's opening and the labrum.
    write_mesh_svg(parts, "depth_mm", scale, geometry::Vec3(-1, 0, 0), geometry::Vec3(0, 0, 1),
                   "Acetabular soft tissue coloured by max penetration depth, " +
                       model_id(shown->ce_deg, shown->alpha_deg) + " (lateral view)",
                   options.out_dir / hip_figure);
  }

  // --- accuracy vs resolution --------------------------------------------------------------------
  struct ResolutionRow {
    double edge_mm;
    double seconds;
    double penetration_ms_per_step;
    std::map<std::string, std::pair<double, double>> maxima;  // archetype -> (curvilinear, radial)
    std::size_t femur_vertices = 0;
  };
  const std::vector<std::pair<std::string, std::pair<double, double>>> archetypes{
      {"normal", {20, 40}}, {"pincer", {40, 40}}, {"cam", {20, 80}}, {"combined cam-pincer", {40, 80}},
      {"dysplasia", {0, 40}}, {"combined dysplasia-impingement", {0, 80}}};
  std::vector<ResolutionRow> resolution_rows;
  {
    std::vector<double> edges = options.resolution_edges_mm;
    if (std::find(edges.begin(), edges.end(), options.edge_mm) == edges.end()) edges.push_back(options.edge_mm);
    std::sort(edges.rbegin(), edges.rend());
    for (double edge : edges) {
      ResolutionRow row{edge, 0.0, 0.0, {}, 0};
      double penetration_ms = 0;
      int step_count = 0;
      const auto start = Clock::now();
      for (const auto& [name, angles] : archetypes) {
        if (!find(result.models, angles.first, angles.second)) continue;
        StageLog resolution_log;
        const ModelRun model = edge == options.edge_mm ? ModelRun{}
                                                       : run_model(angles.first, angles.second, edge, motion,
                                                                   options, resolution_log);
        const ModelRun& used = edge == options.edge_mm ? runs.at(model_id(angles.first, angles.second)) : model;
        row.maxima[name] = {used.summary.max_curvilinear_mm, used.summary.max_radial_mm};
        penetration_ms += used.summary.penetration_ms;
        step_count += static_cast<int>(used.run.steps.size());
        row.femur_vertices = used.hip.tissues.at("femur_bone").num_vertices();
      }
      row.seconds = seconds_since(start);
      row.penetration_ms_per_step = step_count ? penetration_ms / step_count : 0.0;
      resolution_rows.push_back(row);
    }
    std::ostringstream csv;
    csv << "edge_mm,femur_vertices,penetration_ms_per_step";
    for (const auto& [name, angles] : archetypes) csv << ",curvilinear_mm[" << name << "],radial_mm[" << name << "]";
    csv << '\n';
    for (const auto& row : resolution_rows) {
      csv << row.edge_mm << ',' << row.femur_vertices << ',' << row.penetration_ms_per_step;
      for (const auto& [name, angles] : archetypes) {
        const auto it = row.maxima.find(name);
        csv << ',' << (it == row.maxima.end() ? NAN : it->second.first) << ','
            << (it == row.maxima.end() ? NAN : it->second.second);
      }
      csv << '\n';
    }
    write_csv(options.out_dir / "resolution.csv", csv.str());
  }

  // --- report ----------------------------------------------------------------------------------
  result.total_seconds = seconds_since(study_start);
  std::ostringstream md;
  md << "# FAI penetration study\n\n"
     << "hipfai " << kVersion << " (" << kGitSha << "). " << result.models.size()
     << " parametric hips, standing to sitting in " << motion.steps.size()
     << " equal sub-motions to (flexion, adduction, internal rotation) = (59.6, 13.6, 10.9) deg "
     << "(thesis §4.3.2.3). Surface edge " << options.edge_mm << " mm; radial mapping " << contact::to_string(options.mapping)
     << ", " << options.table_size << " cells. Curvilinear: femur bone vs labrum, cylindrical segmenting; "
     << "radial: femoral cartilage vs acetabular cartilage + labrum, radial segmenting; both with the role "
     << "swap (§4.3.2.1). Total run time " << fixed(result.total_seconds, 1) << " s.\n\n";
  // A CE x alpha table whose cells `cell` formats from a model ("-" where there is none).
  auto grid_table = [&](const std::function<std::string(const FaiModelSummary&)>& cell) {
    md << "| CE \\ alpha |";
    for (double alpha : options.alpha_deg) md << ' ' << fixed(alpha, 0) << " |";
    md << "\n|---|";
    for (std::size_t i = 0; i < options.alpha_deg.size(); ++i) md << "---|";
    md << '\n';
    for (double ce : options.ce_deg) {
      md << "| " << fixed(ce, 0) << " |";
      for (double alpha : options.alpha_deg) {
        const auto* m = find(result.models, ce, alpha);
        md << ' ' << (m ? cell(*m) : std::string("-")) << " |";
      }
      md << '\n';
    }
  };
  md << "## Maximum penetration depth over the motion (mm)\n\n";
  grid_table([](const FaiModelSummary& m) { return fixed(m.max_curvilinear_mm) + " / " + fixed(m.max_radial_mm); });
  md << "\nEach cell: curvilinear / radial.\n\n";
  md << "## Where impingement begins\n\nAngle (deg) along the motion's single axis at which the femur bone first meets "
        "the labrum (exact range finder, parts beyond R + tolerance; the motion turns "
     << fixed(motion.steps.back().angle_deg, 1) << " deg; inf: never within a turn).\n\n";
  grid_table([](const FaiModelSummary& m) {
    return std::isfinite(m.first_contact_deg) ? fixed(m.first_contact_deg, 1) : std::string("inf");
  });
  md << '\n';
  md << "![curvilinear](fig63_curvilinear.svg) ![radial](fig63_radial.svg)\n\n"
     << "![difference](fig63_difference.svg) ![pathology](fig63_pathology.svg)\n\n";
  md << "## Table 10 from the computed values\n\n"
     << "| morphology | CE | alpha | max curvilinear (CP) | max radial (RP) | normalised CP - RP |\n"
     << "|---|---|---|---|---|---|\n";
  for (const auto& [name, angles] : archetypes) {
    const auto* m = find(result.models, angles.first, angles.second);
    if (!m) continue;
    md << "| " << name << " | " << fixed(angles.first, 0) << " | " << fixed(angles.second, 0) << " | "
       << fixed(m->max_curvilinear_mm) << " mm (" << curvilinear_band(m->max_curvilinear_mm) << ") | "
       << fixed(m->max_radial_mm) << " mm (" << radial_band(m->max_radial_mm) << ") | "
       << fixed(m->normalised_difference) << " (" << difference_band(m->normalised_difference) << ") |\n";
  }
  md << "\nBands as thesis Table 10 (curvilinear 0-5-10-15-20-25 mm, radial 0-2-4-6-8-10 mm, "
        "difference -0.4..0.4 in steps of 0.2); \"none\" means no penetrating vertex.\n\n";

  // Comparison with the thesis' qualitative pattern (§4.3.3.2), computed, not asserted.
  md << "## Against the thesis' pattern (§4.3.3.2)\n\n";
  auto verdict = [](bool ok) { return ok ? "**agrees**" : "**differs**"; };
  const auto* normal = find(result.models, 20, 40);
  const auto* dysplasia = find(result.models, 0, 40);
  const auto* combined = find(result.models, 40, 80);
  const auto* cam = find(result.models, 20, 80);
  const FaiModelSummary* most_c = &result.models.front();
  const FaiModelSummary* most_r = &result.models.front();
  const FaiModelSummary* most_negative = &result.models.front();
  for (const auto& m : result.models) {
    if (m.max_curvilinear_mm > most_c->max_curvilinear_mm) most_c = &m;
    if (m.max_radial_mm > most_r->max_radial_mm) most_r = &m;
    if (m.normalised_difference < most_negative->normalised_difference) most_negative = &m;
  }
  if (normal) {
    md << "- No penetration for the normal hip (CE 20, alpha 40): curvilinear " << fixed(normal->max_curvilinear_mm)
       << " mm, radial " << fixed(normal->max_radial_mm) << " mm — "
       << verdict(normal->max_curvilinear_mm == 0 && normal->max_radial_mm == 0) << ".\n";
  }
  if (dysplasia) {
    md << "- No penetration for the dysplastic hip (CE 0, alpha 40): curvilinear "
       << fixed(dysplasia->max_curvilinear_mm) << " mm, radial " << fixed(dysplasia->max_radial_mm) << " mm — "
       << verdict(dysplasia->max_curvilinear_mm == 0 && dysplasia->max_radial_mm == 0) << ".\n";
  }
  if (combined) {
    md << "- Largest curvilinear depth for combined cam-pincer (CE 40, alpha 80): the largest is at CE "
       << fixed(most_c->ce_deg, 0) << ", alpha " << fixed(most_c->alpha_deg, 0) << " ("
       << fixed(most_c->max_curvilinear_mm) << " mm) — "
       << verdict(most_c->ce_deg == 40 && most_c->alpha_deg == 80) << ".\n";
  }
  if (cam) {
    md << "- Largest radial depth for pure cam (CE 20, alpha 80): the largest is at CE " << fixed(most_r->ce_deg, 0)
       << ", alpha " << fixed(most_r->alpha_deg, 0) << " (" << fixed(most_r->max_radial_mm) << " mm) — "
       << verdict(most_r->pathology == "cam") << ".\n";
    md << "- Most negative normalised difference (radial dominating) at pure cam: found at CE "
       << fixed(most_negative->ce_deg, 0) << ", alpha " << fixed(most_negative->alpha_deg, 0) << " — "
       << verdict(most_negative->pathology == "cam") << ".\n";
  }
  {
    std::vector<StudyCell> cells;
    for (const auto& m : result.models) {
      cells.push_back({m.ce_deg, m.alpha_deg, m.max_curvilinear_mm, m.max_radial_mm, m.normalised_difference});
    }
    md << '\n' << compare_with_thesis(cells).markdown;
  }
  md << "\nThe geometry is not tuned to these statements: the hips are built from the parameters of "
        "geometry/hip_parameters.h and the angles are measured back independently.\n\n";
  md << "## Penetration curves (Fig. 60) and trends (Fig. 62)\n\n";
  if (!fig60a.empty()) md << "![](" << fig60a << ") ";
  if (!fig60b.empty()) md << "![](" << fig60b << ")";
  md << "\n\n![](fig62_curvilinear.svg) ![](fig62_radial.svg)\n\n";
  md << "## A hip coloured by depth\n\n![](" << hip_figure << ")\n\nThe same tissues with their depth fields: "
     << model_id(shown->ce_deg, shown->alpha_deg) << "_*.vtp (open in ParaView).\n\n";
  md << "## Speed\n\n| model | generate or load (s) | penetration, 30 steps (ms) | per step (ms) |\n|---|---|---|---|\n";
  double total_ms = 0;
  for (const auto& m : result.models) {
    total_ms += m.penetration_ms;
    md << "| " << model_id(m.ce_deg, m.alpha_deg) << " | " << fixed(m.generate_s) << " | " << fixed(m.penetration_ms, 1)
       << " | " << fixed(m.penetration_ms / motion.steps.size(), 2) << " |\n";
  }
  md << "\nPenetration part of all " << result.models.size() << " models x " << motion.steps.size()
     << " steps: " << fixed(total_ms, 0) << " ms in total, " << fixed(total_ms / (result.models.size() * motion.steps.size()), 2)
     << " ms per step on average (tables and pose caches included), " << options.threads << " threads.\n\n";
  md << "## Accuracy vs time (surface resolution)\n\n| edge (mm) | femur vertices | ms per step |";
  for (const auto& [name, angles] : archetypes) md << ' ' << name << " CP / RP (mm) |";
  md << "\n|---|---|---|";
  for (std::size_t i = 0; i < archetypes.size(); ++i) md << "---|";
  md << '\n';
  const ResolutionRow* finest = resolution_rows.empty() ? nullptr : &resolution_rows.back();
  for (const auto& row : resolution_rows) {
    md << "| " << row.edge_mm << " | " << row.femur_vertices << " | " << fixed(row.penetration_ms_per_step, 2) << " |";
    for (const auto& [name, angles] : archetypes) {
      const auto it = row.maxima.find(name);
      if (it == row.maxima.end()) {
        md << " - |";
        continue;
      }
      md << ' ' << fixed(it->second.first) << " / " << fixed(it->second.second);
      if (finest && &row != finest && finest->maxima.count(name)) {
        md << " (" << std::showpos << fixed(it->second.first - finest->maxima.at(name).first) << " / "
           << fixed(it->second.second - finest->maxima.at(name).second) << std::noshowpos << ")";
      }
      md << " |";
    }
    md << '\n';
  }
  md << "\nBracketed: change from the finest resolution. Data: resolution.csv.\n";
  write_csv(options.out_dir / "report.md", md.str());
  result.report_path = (options.out_dir / "report.md").string();
  return result;
}

}  // namespace hipfai::studies
