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

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
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
  bool figures = false;
};

struct GeneratedRow {
  double ce_deg = 0.0;
  double alpha_deg = 0.0;
  double measured_ce_deg = 0.0;
  double measured_alpha_deg = 0.0;
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  double seconds = 0.0;
  std::string dir;
};

GeneratedRow generate_one(const GenerateOptions& options, double ce_deg, double alpha_deg,
                          const std::filesystem::path& dir) {
  geometry::HipParameters parameters;
  parameters.ce_deg = ce_deg;
  parameters.alpha_deg = alpha_deg;
  parameters.edge_mm = options.edge_mm;
  geometry::validate_hip_parameters(parameters, "generate");
  const auto generated = geometry::generate_hip(parameters);
  const geometry::HipModel& model = generated.model;
  const auto ce = geometry::measure_ce_angle(
      {&model.tissue("acetabular_bone"), &model.tissue("acetabular_cartilage")}, model.hjc_mm,
      model.lateral, model.superior);
  const auto alpha = geometry::measure_alpha_angle(
      {&model.tissue("femur_bone"), &model.tissue("femoral_cartilage")}, model.hjc_mm,
      model.neck_axis, model.superior, model.superior.cross(model.lateral));
  geometry::write_hip_model(model, dir, options.format);
  if (options.figures) geometry::write_hip_figures(model, ce, alpha, dir);
  if (options.volume) geometry::write_hip_volume_mesh(parameters, dir / "volume.msh");

  GeneratedRow row;
  row.ce_deg = ce_deg;
  row.alpha_deg = alpha_deg;
  row.measured_ce_deg = ce.status == geometry::MeasureStatus::ok ? ce.ce_deg : std::nan("");
  row.measured_alpha_deg = alpha.status == geometry::MeasureStatus::ok ? alpha.alpha_deg : std::nan("");
  for (const auto& [name, mesh] : model.tissues) {
    row.vertices += mesh.num_vertices();
    row.triangles += mesh.num_triangles();
  }
  row.seconds = generated.seconds;
  row.dir = dir.string();
  return row;
}

void print_table(const std::vector<GeneratedRow>& rows) {
  std::printf("%6s %9s %10s %13s %9s %10s %8s  %s\n", "CE", "alpha", "CE meas.", "alpha meas.",
              "vertices", "triangles", "time s", "directory");
  for (const auto& row : rows) {
    std::printf("%6.1f %9.1f %10.2f %13.2f %9zu %10zu %8.2f  %s\n", row.ce_deg, row.alpha_deg,
                row.measured_ce_deg, row.measured_alpha_deg, row.vertices, row.triangles,
                row.seconds, row.dir.c_str());
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
  }
  print_table(rows);
}

const CommandRegistrar registrar("generate", [](CLI::App& parent) {
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
                      "Target surface edge length, mm (~8: 2 k vertices per model, 0.7: ~130 k)")
      ->check(CLI::Range(0.2, 10.0))
      ->capture_default_str();
  command->add_option("--out", options->out, "Output directory")->required();
  command->add_option("--format", options->format, "Surface mesh format")
      ->check(CLI::IsMember({"ply", "stl", "vtp", "obj"}))
      ->capture_default_str();
  command->add_flag("--grid", options->grid,
                    "Generate the 25 study hips (CE 0..40 x alpha 40..80, step 10) into "
                    "OUT/ce<CE>_alpha<A>/ and print requested vs measured angles");
  command->add_flag("--volume", options->volume,
                    "Also write volume.msh: tetrahedra tagged by tissue (gmsh physical groups)");
  command->add_flag("--figures", options->figures,
                    "Also write frontal.svg and axial.svg with the CE and alpha constructions");
  command->callback([options] { run(*options); });
});

}  // namespace
}  // namespace hipfai::app
