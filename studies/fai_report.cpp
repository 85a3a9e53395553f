// hipfai — the files of `study fai` from its result (see fai_report.h).
#include "studies/fai_report.h"

#include "core/atomic_file.h"
#include "core/text_format.h"
#include "core/version.h"
#include "geometry/mesh_io.h"
#include "studies/fai_reference.h"
#include "studies/reports/svg_plot.h"
#include "studies/results/results_file.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

namespace hipfai::studies {

namespace {

void write_csv(const std::filesystem::path& path, const std::string& text) { write_file_atomically(path, text); }

// The figures the report links to.
struct FaiFigures {
  std::string fig60_ce40_alpha60, fig60_ce40_alpha40;  // empty when that hip is not in the grid
  std::string hip;       // SVG of the hip coloured by depth
  std::string shown_id;  // the hip it shows
};

// results.h5: summary, motion, per-model step maxima, query times and maximum depth fields.
void write_results_h5(const FaiStudyResult& result, const FaiStudyOptions& options) {
  {
    ResultsFile file(options.out_dir / "results.h5");
    file.set_attribute("/", "study", "fai penetration (thesis 4.3)");
    file.set_attribute("/", "code_version", std::string(kVersion) + " " + kGitSha);
    file.set_attribute("/", "units", "length mm, angle deg, time ms");
    file.set_attribute("/", "motion", result.motion.name + ", " + std::to_string(result.motion.steps.size()) + " sub-motions");
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
    for (const auto& step : result.motion.steps) angles.push_back(step.angle_deg);
    file.write("/motion/angle_deg", angles, 1, "deg");
    for (const auto& [id, model] : result.runs) {
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
}

// summary.csv, steps.csv and resolution.csv.
void write_tables(const FaiStudyResult& result, const FaiStudyOptions& options) {
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
      const auto& run = result.runs.at(parametric_hip_id(m.ce_deg, m.alpha_deg)).run;
      for (std::size_t k = 0; k < run.steps.size(); ++k) {
        steps << m.ce_deg << ',' << m.alpha_deg << ',' << (k + 1) << ',' << result.motion.steps[k].angle_deg << ','
              << run.steps[k].curvilinear_max_mm() << ',' << run.steps[k].radial_max_mm() << ','
              << run.steps[k].curvilinear_ms << ',' << run.steps[k].radial_ms << '\n';
      }
    }
    write_csv(options.out_dir / "summary.csv", summary.str());
    write_csv(options.out_dir / "steps.csv", steps.str());
  }
  {
    std::ostringstream csv;
    csv << "edge_mm,femur_vertices,penetration_ms_per_step";
    for (const auto& [name, angles] : fai_archetypes()) csv << ",curvilinear_mm[" << name << "],radial_mm[" << name << "]";
    csv << '\n';
    for (const auto& row : result.resolution) {
      csv << row.edge_mm << ',' << row.femur_vertices << ',' << row.penetration_ms_per_step;
      for (const auto& [name, angles] : fai_archetypes()) {
        const auto it = row.maxima.find(name);
        csv << ',' << (it == row.maxima.end() ? NAN : it->second.first) << ','
            << (it == row.maxima.end() ? NAN : it->second.second);
      }
      csv << '\n';
    }
    write_csv(options.out_dir / "resolution.csv", csv.str());
  }
}

// Figs. 60, 62, 63 and the hip coloured by depth (SVG, and its tissues as VTP).
// Fig. 60: the maximum depths per step of one hip; returns the file name, empty when the grid
// has no such hip.
std::string write_fig60(const FaiStudyResult& result, const FaiStudyOptions& options, double ce, double alpha,
                        const std::string& file) {
  const auto it = result.runs.find(parametric_hip_id(ce, alpha));
  if (it == result.runs.end()) return std::string();
  std::vector<double> step_angles;
  for (const auto& step : result.motion.steps) step_angles.push_back(step.angle_deg);
  LineChart chart;
  chart.title = "Max penetration during standing to sitting, CE " + fixed(ce, 0) + ", alpha " + fixed(alpha, 0);
  chart.x_label = "rotation from neutral (deg)";
  chart.y_label = "max depth (mm)";
  Series c{"curvilinear", step_angles, {}, false}, r{"radial", step_angles, {}, true};
  for (const auto& s : it->second.run.steps) c.y.push_back(s.curvilinear_max_mm()), r.y.push_back(s.radial_max_mm());
  chart.series = {c, r};
  write_svg(chart, options.out_dir / file);
  return file;
}

// Fig. 62: the maximum depth over the motion against alpha, one line per CE.
void write_fig62(const FaiStudyResult& result, const FaiStudyOptions& options) {
  for (const bool radial : {false, true}) {
    LineChart chart;
    chart.title = std::string("Max ") + (radial ? "radial" : "curvilinear") + " penetration vs alpha";
    chart.x_label = "alpha (deg)";
    chart.y_label = "max depth over the motion (mm)";
    for (double ce : options.ce_deg) {
      Series s{"CE " + fixed(ce, 0), options.alpha_deg, {}, false};
      for (double alpha : options.alpha_deg) {
        const auto* m = find_fai_model(result.models, ce, alpha);
        s.y.push_back(m ? (radial ? m->max_radial_mm : m->max_curvilinear_mm) : NAN);
      }
      chart.series.push_back(s);
    }
    write_svg(chart, options.out_dir / (radial ? "fig62_radial.svg" : "fig62_curvilinear.svg"));
  }
}

// A Fig. 63 heat map over the CE x alpha grid (CE rows from the largest), optionally with each
// cell's pathology as its text.
void write_fig63(const FaiStudyResult& result, const FaiStudyOptions& options, const std::string& title,
                 const std::string& unit, bool diverging_map, double FaiModelSummary::*value,
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
      const auto* m = find_fai_model(result.models, *it, alpha);
      row.push_back(m ? (*m).*value : NAN);
      text.push_back(text_is_pathology && m ? m->pathology : "");
    }
    map.values.push_back(row);
    map.cell_text.push_back(text);
  }
  for (double alpha : options.alpha_deg) map.column_names.push_back(fixed(alpha, 0));
  write_svg(map, options.out_dir / file);
}

// The hip shown coloured by depth: the combined cam-pincer hip, or the deepest model.
const FaiModelSummary& shown_hip(const FaiStudyResult& result) {
  const FaiModelSummary* deepest = &result.models.front();
  for (const auto& m : result.models) {
    if (m.max_curvilinear_mm + m.max_radial_mm > deepest->max_curvilinear_mm + deepest->max_radial_mm) deepest = &m;
  }
  return find_fai_model(result.models, 40, 80) ? *find_fai_model(result.models, 40, 80) : *deepest;
}

// The shown hip's acetabular soft tissues and femoral cartilage with their maximum depth fields
// (one VTP each) and an SVG of them; returns the SVG's file name.
std::string write_coloured_hip(const FaiStudyResult& result, const FaiStudyOptions& options,
                               const FaiModelSummary& shown) {
  const std::string id = parametric_hip_id(shown.ce_deg, shown.alpha_deg);
  const auto& model = result.runs.at(id);
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
    geometry::write_mesh(mesh, options.out_dir / (id + "_" + tissue + ".vtp"));
    coloured.push_back(std::move(mesh));
  }
  std::vector<const geometry::TriMesh*> parts;
  for (const auto& mesh : coloured) parts.push_back(&mesh);
  const double scale = std::max(1.0, shown.max_radial_mm);
  const std::string file = "hip_" + id + ".svg";
  // Seen from lateral (looking medially, -X), superior up: the socket's opening and the labrum.
  write_mesh_svg(parts, "depth_mm", scale, geometry::Vec3(-1, 0, 0), geometry::Vec3(0, 0, 1),
                 "Acetabular soft tissue coloured by max penetration depth, " + id + " (lateral view)",
                 options.out_dir / file);
  return file;
}

FaiFigures write_figures(const FaiStudyResult& result, const FaiStudyOptions& options) {
  FaiFigures figures;
  figures.fig60_ce40_alpha60 = write_fig60(result, options, 40, 60, "fig60_ce40_alpha60.svg");
  figures.fig60_ce40_alpha40 = write_fig60(result, options, 40, 40, "fig60_ce40_alpha40.svg");
  write_fig62(result, options);
  write_fig63(result, options, "Max curvilinear penetration", "mm", false, &FaiModelSummary::max_curvilinear_mm,
              "fig63_curvilinear.svg");
  write_fig63(result, options, "Max radial penetration", "mm", false, &FaiModelSummary::max_radial_mm,
              "fig63_radial.svg");
  write_fig63(result, options, "Normalised curvilinear - radial", "", true, &FaiModelSummary::normalised_difference,
              "fig63_difference.svg");
  write_fig63(result, options, "Pathology (colour: normalised difference)", "", true,
              &FaiModelSummary::normalised_difference, "fig63_pathology.svg", true);
  const FaiModelSummary& shown = shown_hip(result);
  figures.shown_id = parametric_hip_id(shown.ce_deg, shown.alpha_deg);
  figures.hip = write_coloured_hip(result, options, shown);
  return figures;
}

// The hip parameters of the run in words: the defaults, or the fields --hip-parameters changed
// (CE, alpha and the edge are the grid's, whatever the base holds).
std::string hip_parameters_sentence(const FaiStudyOptions& options) {
  std::string text;
  if (options.base_parameters) {
    for (const auto& [key, value] : geometry::hip_parameters_changed(*options.base_parameters)) {
      if (key == "ce_deg" || key == "alpha_deg" || key == "edge_mm") continue;
      text += (text.empty() ? "the defaults except " : ", ") + key + " = " + fixed(value, 2);
    }
  }
  return text.empty() ? "the generator's defaults (geometry/hip_parameters.h)" : text + " (`--hip-parameters`)";
}

void write_introduction(std::ostream& md, const FaiStudyResult& result, const FaiStudyOptions& options) {
  md << "# FAI penetration study\n\n"
     << "hipfai " << kVersion << " (" << kGitSha << "). " << result.models.size()
     << " parametric hips, standing to sitting in " << result.motion.steps.size()
     << " equal sub-motions to (flexion, adduction, internal rotation) = (59.6, 13.6, 10.9) deg "
     << "(thesis §4.3.2.3), "
     << (options.pose_sequence == geometry::PoseSequence::kFixedAxes
             ? "read as rotations about the fixed pelvic axes X, then Y, then Z (`--pose-sequence fixed-axes`)"
             : "read in the joint coordinate system (X-Y'-Z'', Wu et al. 2002)")
     << (options.femoral_neutral == geometry::FemoralNeutral::kMechanicalAxis
             ? ", from the ISB femoral neutral (mechanical axis along Z: each femur adducted by the "
               "anatomic-mechanical angle, 6 deg, first; `--femoral-neutral mechanical`)"
             : ", from the femur as built (shaft along Z)")
     << ". Hip parameters: "
     << hip_parameters_sentence(options)
     << ". Surface edge " << options.edge_mm << " mm; radial mapping " << contact::to_string(options.mapping)
     << ", " << options.table_size << " cells. Curvilinear: femur bone vs labrum, cylindrical segmenting; "
     << "radial: femur bone and cartilage vs acetabular cartilage + labrum, radial segmenting, crossing rule '"
     << contact::to_string(options.radial_rule)
     << (options.radial_rule == contact::RadialCrossingRule::kBeyond
             ? "' (the thesis' rule: femur vertices beyond the socket's surface along their ray from the HJC)"
             : "' (femur vertices inside the acetabular soft tissues)")
     << "; both with the role swap (§4.3.2.1). Total run time " << fixed(result.total_seconds, 1) << " s.\n\n";
}

// A CE x alpha table whose cells `cell` formats from a model ("-" where there is none).
void write_grid_table(std::ostream& md, const FaiStudyResult& result, const FaiStudyOptions& options,
                      const std::function<std::string(const FaiModelSummary&)>& cell) {
  md << "| CE \\ alpha |";
  for (double alpha : options.alpha_deg) md << ' ' << fixed(alpha, 0) << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < options.alpha_deg.size(); ++i) md << "---|";
  md << '\n';
  for (double ce : options.ce_deg) {
    md << "| " << fixed(ce, 0) << " |";
    for (double alpha : options.alpha_deg) {
      const auto* m = find_fai_model(result.models, ce, alpha);
      md << ' ' << (m ? cell(*m) : std::string("-")) << " |";
    }
    md << '\n';
  }
}

// The maximum depths and the first-contact angles over the grid, and thesis Table 10.
void write_depth_tables(std::ostream& md, const FaiStudyResult& result, const FaiStudyOptions& options) {
  md << "## Maximum penetration depth over the motion (mm)\n\n";
  write_grid_table(md, result, options,
                   [](const FaiModelSummary& m) { return fixed(m.max_curvilinear_mm, 2) + " / " + fixed(m.max_radial_mm, 2); });
  md << "\nEach cell: curvilinear / radial.\n\n";
  md << "## Where impingement begins\n\nAngle (deg) along the motion's single axis at which the femur bone first meets "
        "the labrum (exact range finder, parts beyond R + tolerance; the motion turns "
     << fixed(result.motion.steps.back().angle_deg, 1) << " deg; inf: never within a turn).\n\n";
  write_grid_table(md, result, options, [](const FaiModelSummary& m) {
    return std::isfinite(m.first_contact_deg) ? fixed(m.first_contact_deg, 1) : std::string("inf");
  });
  md << '\n';
  md << "![curvilinear](fig63_curvilinear.svg) ![radial](fig63_radial.svg)\n\n"
     << "![difference](fig63_difference.svg) ![pathology](fig63_pathology.svg)\n\n";
  md << "## Table 10 from the computed values\n\n"
     << "| morphology | CE | alpha | max curvilinear (CP) | max radial (RP) | normalised CP - RP |\n"
     << "|---|---|---|---|---|---|\n";
  for (const auto& [name, angles] : fai_archetypes()) {
    const auto* m = find_fai_model(result.models, angles.first, angles.second);
    if (!m) continue;
    md << "| " << name << " | " << fixed(angles.first, 0) << " | " << fixed(angles.second, 0) << " | "
       << fixed(m->max_curvilinear_mm, 2) << " mm (" << curvilinear_band(m->max_curvilinear_mm) << ") | "
       << fixed(m->max_radial_mm, 2) << " mm (" << radial_band(m->max_radial_mm) << ") | "
       << fixed(m->normalised_difference, 2) << " (" << difference_band(m->normalised_difference) << ") |\n";
  }
  md << "\nBands as thesis Table 10 (curvilinear 0-5-10-15-20-25 mm, radial 0-2-4-6-8-10 mm, "
        "difference -0.4..0.4 in steps of 0.2); \"none\" means no penetrating vertex.\n\n";
}

// Comparison with the thesis' qualitative pattern (§4.3.3.2), computed, not asserted.
void write_thesis_pattern(std::ostream& md, const FaiStudyResult& result) {
  md << "## Against the thesis' pattern (§4.3.3.2)\n\n";
  auto verdict = [](bool ok) { return ok ? "**agrees**" : "**differs**"; };
  const auto* normal = find_fai_model(result.models, 20, 40);
  const auto* dysplasia = find_fai_model(result.models, 0, 40);
  const auto* combined = find_fai_model(result.models, 40, 80);
  const auto* cam = find_fai_model(result.models, 20, 80);
  const FaiModelSummary* most_c = &result.models.front();
  const FaiModelSummary* most_r = &result.models.front();
  const FaiModelSummary* most_negative = &result.models.front();
  for (const auto& m : result.models) {
    if (m.max_curvilinear_mm > most_c->max_curvilinear_mm) most_c = &m;
    if (m.max_radial_mm > most_r->max_radial_mm) most_r = &m;
    if (m.normalised_difference < most_negative->normalised_difference) most_negative = &m;
  }
  if (normal) {
    md << "- No penetration for the normal hip (CE 20, alpha 40): curvilinear " << fixed(normal->max_curvilinear_mm, 2)
       << " mm, radial " << fixed(normal->max_radial_mm, 2) << " mm — "
       << verdict(normal->max_curvilinear_mm == 0 && normal->max_radial_mm == 0) << ".\n";
  }
  if (dysplasia) {
    md << "- No penetration for the dysplastic hip (CE 0, alpha 40): curvilinear "
       << fixed(dysplasia->max_curvilinear_mm, 2) << " mm, radial " << fixed(dysplasia->max_radial_mm, 2) << " mm — "
       << verdict(dysplasia->max_curvilinear_mm == 0 && dysplasia->max_radial_mm == 0) << ".\n";
  }
  if (combined) {
    md << "- Largest curvilinear depth for combined cam-pincer (CE 40, alpha 80): the largest is at CE "
       << fixed(most_c->ce_deg, 0) << ", alpha " << fixed(most_c->alpha_deg, 0) << " ("
       << fixed(most_c->max_curvilinear_mm, 2) << " mm) — "
       << verdict(most_c->ce_deg == 40 && most_c->alpha_deg == 80) << ".\n";
  }
  if (cam) {
    md << "- Largest radial depth for pure cam (CE 20, alpha 80): the largest is at CE " << fixed(most_r->ce_deg, 0)
       << ", alpha " << fixed(most_r->alpha_deg, 0) << " (" << fixed(most_r->max_radial_mm, 2) << " mm) — "
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
}

void write_figure_sections(std::ostream& md, const FaiFigures& figures) {
  md << "## Penetration curves (Fig. 60) and trends (Fig. 62)\n\n";
  if (!figures.fig60_ce40_alpha60.empty()) md << "![](" << figures.fig60_ce40_alpha60 << ") ";
  if (!figures.fig60_ce40_alpha40.empty()) md << "![](" << figures.fig60_ce40_alpha40 << ")";
  md << "\n\n![](fig62_curvilinear.svg) ![](fig62_radial.svg)\n\n";
  md << "## A hip coloured by depth\n\n![](" << figures.hip << ")\n\nThe same tissues with their depth fields: "
     << figures.shown_id << "_*.vtp (open in ParaView).\n\n";
}

void write_speed(std::ostream& md, const FaiStudyResult& result, const FaiStudyOptions& options) {
  md << "## Speed\n\n| model | generate or load (s) | penetration, 30 steps (ms) | per step (ms) |\n|---|---|---|---|\n";
  double total_ms = 0;
  for (const auto& m : result.models) {
    total_ms += m.penetration_ms;
    md << "| " << parametric_hip_id(m.ce_deg, m.alpha_deg) << " | " << fixed(m.generate_s, 2) << " | " << fixed(m.penetration_ms, 1)
       << " | " << fixed(m.penetration_ms / result.motion.steps.size(), 2) << " |\n";
  }
  md << "\nPenetration part of all " << result.models.size() << " models x " << result.motion.steps.size()
     << " steps: " << fixed(total_ms, 0) << " ms in total, " << fixed(total_ms / (result.models.size() * result.motion.steps.size()), 2)
     << " ms per step on average (tables and pose caches included), " << options.threads << " threads.\n\n";
}

void write_resolution_table(std::ostream& md, const FaiStudyResult& result) {
  md << "## Accuracy vs time (surface resolution)\n\n| edge (mm) | femur vertices | ms per step |";
  for (const auto& [name, angles] : fai_archetypes()) md << ' ' << name << " CP / RP (mm) |";
  md << "\n|---|---|---|";
  for (std::size_t i = 0; i < fai_archetypes().size(); ++i) md << "---|";
  md << '\n';
  const FaiResolutionRow* finest = result.resolution.empty() ? nullptr : &result.resolution.back();
  for (const auto& row : result.resolution) {
    md << "| " << row.edge_mm << " | " << row.femur_vertices << " | " << fixed(row.penetration_ms_per_step, 2) << " |";
    for (const auto& [name, angles] : fai_archetypes()) {
      const auto it = row.maxima.find(name);
      if (it == row.maxima.end()) {
        md << " - |";
        continue;
      }
      md << ' ' << fixed(it->second.first, 2) << " / " << fixed(it->second.second, 2);
      if (finest && &row != finest && finest->maxima.count(name)) {
        md << " (" << std::showpos << fixed(it->second.first - finest->maxima.at(name).first, 2) << " / "
           << fixed(it->second.second - finest->maxima.at(name).second, 2) << std::noshowpos << ")";
      }
      md << " |";
    }
    md << '\n';
  }
  md << "\nBracketed: change from the finest resolution. Data: resolution.csv.\n";
}

// report.md: the tables and figures of thesis §4.3.3, the comparison with its pattern, speed and
// accuracy vs resolution.
void write_report_md(const FaiStudyResult& result, const FaiStudyOptions& options, const FaiFigures& figures) {
  std::ostringstream md;
  write_introduction(md, result, options);
  write_depth_tables(md, result, options);
  write_thesis_pattern(md, result);
  write_figure_sections(md, figures);
  write_speed(md, result, options);
  write_resolution_table(md, result);
  write_csv(options.out_dir / "report.md", md.str());
}

}  // namespace

void write_fai_study_outputs(FaiStudyResult& result, const FaiStudyOptions& options) {
  std::filesystem::create_directories(options.out_dir);
  write_results_h5(result, options);
  write_tables(result, options);
  const FaiFigures figures = write_figures(result, options);
  write_report_md(result, options, figures);
  result.report_path = (options.out_dir / "report.md").string();
}

}  // namespace hipfai::studies
