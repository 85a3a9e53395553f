// hipfai generate: the parametric CAD-like hip of thesis §4.3.2.2 — one model, or the 25-model
// FAI study grid (CE 0..40 x alpha 40..80, 10 deg steps) — with CE and alpha measured back.
#include "app/command_registry.h"
#include "core/error.h"
#include "core/literature.h"
#include "core/progress.h"
#include "geometry/hip_figures.h"
#include "geometry/hip_generator.h"
#include "geometry/hip_measure.h"
#include "geometry/hip_model.h"
#include "geometry/hip_volume_mesh.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <iostream>
#include <string>
#include <vector>

namespace hipfai::app {
namespace {

struct GenerateOptions {
  double ce_deg = 30.0;
  double alpha_deg = 40.0;
  double edge_mm = 2.0;
  std::string out;
  std::string format = "ply";
  bool grid = false;
  bool volume = false;
  double volume_edge_mm = 0.0;  // 0: the surface edge
  int volume_layers = 2;
  bool figures = false;
  std::string hip_parameters;  // JSON file of base parameters (--hip-parameters); empty: defaults
  geometry::HipParameters base;
};

struct GeneratedRow {
  double ce_deg = 0.0;
  double alpha_deg = 0.0;
  double measured_ce_deg = 0.0;
  double measured_alpha_deg = 0.0;
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  double seconds = 0.0;
  std::size_t hexahedra = 0;          // volume.msh, when written
  double min_scaled_jacobian = 0.0;
  double volume_seconds = 0.0;
  std::string dir;
};

GeneratedRow generate_one(const GenerateOptions& options, double ce_deg, double alpha_deg,
                          const std::filesystem::path& dir) {
  geometry::HipParameters parameters = options.base;
  parameters.ce_deg = ce_deg;
  parameters.alpha_deg = alpha_deg;
  parameters.edge_mm = options.edge_mm;
  geometry::validate_hip_parameters(parameters, "generate");
  const auto generated = geometry::generate_hip(parameters);
  if (!generated.model.mesher_failures.empty()) {
    std::ostringstream note;
    note << "note: hip ce " << ce_deg << " alpha " << alpha_deg << ": surfaces meshed by gmsh algorithm "
         << generated.model.surface_algorithm << " after " << generated.model.mesher_failures << '\n';
    std::cerr << note.str();
  }
  const geometry::HipModel& model = generated.model;
  // The volume mesh is built before anything is written: a hip it cannot mesh leaves no files.
  GeneratedRow row;
  std::optional<geometry::HipVolumeMesh> volume;
  if (options.volume) {
    const auto start = std::chrono::steady_clock::now();
    geometry::HipVolumeOptions volume_options;
    volume_options.edge_mm = options.volume_edge_mm > 0.0 ? options.volume_edge_mm : options.edge_mm;
    volume_options.layers = options.volume_layers;
    volume = geometry::build_hip_volume_mesh(model, volume_options);
    row.hexahedra = volume->mesh.hexes.size();
    row.min_scaled_jacobian = volume->min_scaled_jacobian;
    row.volume_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  geometry::write_hip_model(model, dir, options.format, volume ? &*volume : nullptr);
  if (options.figures) {
    // The drawings need the constructions (rim point, departure point), not only the angles the
    // generator recorded.
    const auto ce = geometry::measure_ce_angle(
        {&model.tissue("acetabular_bone"), &model.tissue("acetabular_cartilage")}, model.hjc_mm,
        model.lateral, model.superior);
    const auto alpha = geometry::measure_alpha_angle(
        {&model.tissue("femur_bone"), &model.tissue("femoral_cartilage")}, model.hjc_mm,
        model.neck_axis, model.superior, model.superior.cross(model.lateral));
    geometry::write_hip_figures(model, ce, alpha, dir);
  }

  row.ce_deg = ce_deg;
  row.alpha_deg = alpha_deg;
  // Measured by the generator on the meshes (NaN where the measurement found no section).
  row.measured_ce_deg = model.measured_ce_deg;
  row.measured_alpha_deg = model.measured_alpha_notzli_deg;
  for (const auto& [name, mesh] : model.tissues) {
    row.vertices += mesh.num_vertices();
    row.triangles += mesh.num_triangles();
  }
  row.seconds = generated.seconds;
  row.dir = dir.string();
  return row;
}

void print_table(const std::vector<GeneratedRow>& rows, bool volume) {
  std::printf("%6s %9s %10s %13s %9s %10s %8s", "CE", "alpha", "CE meas.", "alpha meas.",
              "vertices", "triangles", "time s");
  if (volume) std::printf(" %10s %8s %8s", "hexahedra", "min SJ", "vol. s");
  std::printf("  %s\n", "directory");
  for (const auto& row : rows) {
    std::printf("%6.1f %9.1f %10.2f %13.2f %9zu %10zu %8.2f", row.ce_deg, row.alpha_deg,
                row.measured_ce_deg, row.measured_alpha_deg, row.vertices, row.triangles,
                row.seconds);
    if (volume) std::printf(" %10zu %8.3f %8.2f", row.hexahedra, row.min_scaled_jacobian, row.volume_seconds);
    std::printf("  %s\n", row.dir.c_str());
  }
}

void run(const GenerateOptions& options) {
  const std::filesystem::path out(options.out);
  std::vector<GeneratedRow> rows;
  if (!options.grid) {
    rows.push_back(generate_one(options, options.ce_deg, options.alpha_deg, out));
  } else {
    std::vector<std::pair<double, double>> grid;
    for (double ce = literature::kStudyCeMinDeg; ce <= literature::kStudyCeMaxDeg + 1e-9;
         ce += literature::kStudyStepDeg) {
      for (double alpha = literature::kStudyAlphaMinDeg; alpha <= literature::kStudyAlphaMaxDeg + 1e-9;
           alpha += literature::kStudyStepDeg) {
        grid.emplace_back(ce, alpha);
      }
    }
    ProgressBar progress("generate", grid.size());
    for (const auto& [ce, alpha] : grid) {
      const auto dir = out / ("ce" + std::to_string(static_cast<int>(std::lround(ce))) + "_alpha" +
                              std::to_string(static_cast<int>(std::lround(alpha))));
      rows.push_back(generate_one(options, ce, alpha, dir));
      progress.advance();
    }
    progress.finish();
    if (options.figures) {
      // The six characteristic morphologies of thesis Table 10 side by side.
      const std::vector<std::pair<std::string, std::pair<int, int>>> six{
          {"normal", {20, 40}}, {"pincer", {40, 40}}, {"cam", {20, 80}},
          {"combined cam-pincer", {40, 80}}, {"dysplasia", {0, 40}}, {"dysplasia + cam", {0, 80}}};
      std::vector<geometry::HipModel> models;
      for (const auto& [label, angles] : six) {
        models.push_back(geometry::load_hip_model(out / ("ce" + std::to_string(angles.first) + "_alpha" +
                                                         std::to_string(angles.second))));
      }
      std::vector<geometry::MorphologyPanel> panels;
      for (std::size_t i = 0; i < six.size(); ++i) panels.push_back({six[i].first, &models[i]});
      geometry::write_morphology_sheet(panels, out / "morphologies.svg");
    }
  }
  print_table(rows, options.volume);
}

const CommandRegistrar generate_registrar("generate", [](CLI::App& parent) {
  auto options = std::make_shared<GenerateOptions>();
  CLI::App* command = parent.add_subcommand(
      "generate",
      "Generate a parametric hip (femur, femoral cartilage, acetabulum, horseshoe cartilage, "
      "labrum) with a given CE and alpha angle; measure both back");
  command->add_option("--ce-deg", options->ce_deg, "Lateral centre-edge angle of Wiberg, deg")
      ->check(CLI::Range(0.0, 45.0))
      ->capture_default_str();
  command->add_option("--alpha-deg", options->alpha_deg, "Alpha angle of Noetzli, deg")
      ->check(CLI::Range(35.0, 90.0))
      ->capture_default_str();
  command->add_option("--edge-mm", options->edge_mm,
                      "Target surface edge length, mm (7: ~2 k vertices per model, 3.5: ~8 k, 1.7: ~32 k, 0.83: ~130 k)")
      ->check(CLI::Range(0.2, 10.0))
      ->capture_default_str();
  command->add_option("--out", options->out, "Output directory")->required();
  command->add_option("--format", options->format, "Surface mesh format")
      ->check(CLI::IsMember({"ply", "stl", "vtp", "obj"}))
      ->capture_default_str();
  command->add_flag("--grid", options->grid,
                    "Generate the 25 study hips (CE 0..40 x alpha 40..80, step 10) into "
                    "OUT/ce<CE>_alpha<A>/ and print requested vs measured angles");
  CLI::Option* volume = command->add_flag(
      "--volume", options->volume,
      "Also write volume.msh (gmsh MSH 2.2): hexahedral meshes of femoral cartilage, acetabular "
      "cartilage and labrum for the FE, cells tagged by tissue, boundary quadrangles by surface "
      "(articular, bonded, free); recorded under \"volume\" in model.json");
  command->add_option("--volume-edge-mm", options->volume_edge_mm,
                      "Target hexahedron edge on the articular faces, mm (default: --edge-mm)")
      ->check(CLI::Range(0.5, 10.0))
      ->needs(volume);
  command->add_option("--volume-layers", options->volume_layers, "Hexahedra through the tissue thickness")
      ->check(CLI::Range(1, 8))
      ->capture_default_str()
      ->needs(volume);
  command->add_flag("--figures", options->figures,
                    "Also write frontal.svg and axial.svg with the CE and alpha constructions");
  command->add_option("--hip-parameters", options->hip_parameters,
                      "JSON file of generator parameters (keys of model.json's 'parameters'); --ce-deg, "
                      "--alpha-deg and --edge-mm (or the grid) replace its ce_deg, alpha_deg and edge_mm");
  command->callback([options] {
    if (!options->hip_parameters.empty()) options->base = geometry::load_hip_parameters(options->hip_parameters);
    run(*options);
  });
});

}  // namespace
}  // namespace hipfai::app
