// hipfai hjc: the hip joint centre by the five methods of thesis §4.4.2.2 (femoralheadsphere,
// acetabulumsphere, doublesphere, dconst, dref), on a femur and a pelvis in the same frame.
#include "app/cli_util.h"
#include "app/command_registry.h"
#include "core/error.h"
#include "geometry/hjc.h"
#include "geometry/mesh_io.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace hipfai::app {
namespace {

struct HjcArgs {
  std::string femur, pelvis, head_region, lunate_region, method = "all";
  std::vector<double> long_axis;
  bool json = false;
};

void run(const HjcArgs& args) {
  const geometry::TriMesh femur = geometry::read_mesh(args.femur);
  const geometry::TriMesh pelvis = geometry::read_mesh(args.pelvis);
  geometry::HjcRequest request;
  request.femur = &femur;
  request.pelvis = &pelvis;
  request.femur_name = args.femur;
  request.pelvis_name = args.pelvis;
  if (!args.head_region.empty()) request.head_region = geometry::read_region(femur, args.head_region);
  if (!args.lunate_region.empty()) request.lunate_region = geometry::read_region(pelvis, args.lunate_region);
  if (args.method != "all") request.methods = {args.method};
  if (!args.long_axis.empty()) {
    const Eigen::Vector3d axis = to_vec3(args.long_axis, "--femur-axis");
    if (!(axis.norm() > 0.0)) throw_error("--femur-axis: the axis has zero length");
    request.femur_long_axis = axis;
  }
  const geometry::HjcResult result = geometry::estimate_hjc(request);
  if (args.json) {
    std::cout << geometry::hjc_result_json(result) << '\n';
    return;
  }
  std::printf("hip joint centre of %s in %s (input coordinates, mm)\n", args.femur.c_str(), args.pelvis.c_str());
  std::printf("femoral head: %s, %zu vertices; lunate surface: %s, %zu vertices\n", result.head_source.c_str(),
              result.head_vertices, result.lunate_source.c_str(), result.lunate_vertices);
  std::printf("%-18s %30s %10s %9s %9s %24s\n", "method", "centre (mm)", "radius", "rms", "max", "motion rms/max");
  for (const auto& m : result.methods) {
    char radius[32] = "-";
    if (std::isfinite(m.radius_mm)) std::snprintf(radius, sizeof(radius), "%.3f", m.radius_mm);
    char motion[64] = "-";
    if (std::isfinite(m.residual_motion_rms_mm)) {
      std::snprintf(motion, sizeof(motion), "%.4f/%.4f (%d poses)", m.residual_motion_rms_mm, m.residual_motion_max_mm,
                    m.poses);
    }
    std::printf("%-18s (%9.3f, %9.3f, %9.3f) %10s %9.4f %9.4f %24s%s%s\n", m.name.c_str(), m.center_mm.x(),
                m.center_mm.y(), m.center_mm.z(), radius, m.rms_mm, m.max_mm, motion, m.ok ? "" : "  FAILED: ",
                m.ok ? "" : m.message.c_str());
  }
}

const CommandRegistrar hjc_registrar("hjc", [](CLI::App& parent) {
  auto* command = parent.add_subcommand(
      "hjc", "Hip joint centre by five methods (thesis §4.4.2.2): femoralheadsphere, acetabulumsphere, "
             "doublesphere, dconst, dref");
  auto args = std::make_shared<HjcArgs>();
  command->add_option("--femur", args->femur, "Femur surface (bone, or its articular surface)")
      ->required()->check(CLI::ExistingFile);
  command->add_option("--pelvis", args->pelvis, "Pelvis / acetabulum surface, same frame as the femur")
      ->required()->check(CLI::ExistingFile);
  command->add_option("--femoral-head-region", args->head_region,
                      "Femoral head: a mesh of the head alone, or a text file of femur vertex indices or "
                      "one 0/1 per vertex (default: found automatically)")
      ->check(CLI::ExistingFile);
  command->add_option("--acetabulum-region", args->lunate_region,
                      "Lunate surface: a mesh, or pelvis vertex indices / 0-1 mask (default: automatic)")
      ->check(CLI::ExistingFile);
  command->add_option("--method", args->method, "all or one method")
      ->capture_default_str()
      ->check(CLI::IsMember({"all", "femoralheadsphere", "acetabulumsphere", "doublesphere", "dconst", "dref"}));
  add_vec3_option(command, "--femur-axis", args->long_axis,
                  "Femur long axis for the simulated circumduction (default: the femur's principal axis)");
  command->add_flag("--json", args->json, "Print one JSON object {\"methods\": {...}, \"regions\": {...}}");
  command->callback([args] { run(*args); });
});

}  // namespace
}  // namespace hipfai::app
