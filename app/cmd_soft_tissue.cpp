// hipfai soft-tissue: cartilage and labrum synthesised on a segmented femur and pelvis, written as a
// hip model folder every command reads (studies/soft_tissue_model.h).
#include "app/command_registry.h"
#include "anatomy/frame_file.h"
#include "anatomy/side.h"
#include "geometry/mesh_io.h"
#include "studies/soft_tissue_model.h"

#include <cstdio>
#include <memory>
#include <string>

namespace hipfai::app {
namespace {

struct SoftTissueArgs {
  std::string femur, pelvis, side, frame, out;
};

void run(const SoftTissueArgs& args) {
  const geometry::TriMesh femur = geometry::read_mesh(args.femur);
  const geometry::TriMesh pelvis = geometry::read_mesh(args.pelvis);
  studies::SoftTissueModelRequest request;
  request.assessment.femur = &femur;
  request.assessment.pelvis = &pelvis;
  request.assessment.femur_name = args.femur;
  request.assessment.pelvis_name = args.pelvis;
  if (!args.side.empty()) request.assessment.side = anatomy::side_from_name(args.side);
  if (!args.frame.empty()) request.assessment.frame = anatomy::read_frame_file(args.frame);
  const studies::SoftTissueModel result = studies::build_soft_tissue_model(request);
  studies::write_soft_tissue_model(result, args.femur, args.pelvis, args.out);
  const auto& t = result.report;
  std::printf("%s hip: femoral cartilage %.0f mm2, mean %.2f mm (%.2f-%.2f); acetabular cartilage %.0f mm2, mean %.2f mm "
              "(%.2f-%.2f); labrum %.0f mm3 in %d piece(s)\n",
              anatomy::side_name(result.side), t.femoral.covered_area_mm2, t.femoral.mean_thickness_mm,
              t.femoral.min_thickness_mm, t.femoral.max_thickness_mm, t.acetabular.covered_area_mm2,
              t.acetabular.mean_thickness_mm, t.acetabular.min_thickness_mm, t.acetabular.max_thickness_mm,
              t.labrum_volume_mm3, t.labrum_pieces);
  std::printf("%.2f s; written to %s (model.json, soft_tissue.md)\n", result.total_seconds, args.out.c_str());
}

const CommandRegistrar registrar("soft-tissue", [](CLI::App& parent) {
  auto* command = parent.add_subcommand(
      "soft-tissue", "Cartilage and labrum synthesised on a segmented femur and pelvis, written as a hip model "
                     "folder (model.json and the five tissues, hip frame) for run, collide and the other commands");
  auto args = std::make_shared<SoftTissueArgs>();
  command->add_option("--femur", args->femur, "Femur bone surface (STL, PLY, OBJ, VTP), closed")
      ->required()->check(CLI::ExistingFile);
  command->add_option("--pelvis", args->pelvis, "Pelvis bone surface, same frame; whole (both hemipelves) unless --frame")
      ->required()->check(CLI::ExistingFile);
  command->add_option("--side", args->side, "right or left (default: found from the bones)")
      ->check(CLI::IsMember({"right", "left"}));
  command->add_option("--frame", args->frame, "JSON frames or landmarks, as for assess --frame")
      ->check(CLI::ExistingFile);
  command->add_option("--out", args->out, "Output folder (written whole or not at all; replaced if it exists)")
      ->required();
  command->callback([args] { run(*args); });
});

}  // namespace
}  // namespace hipfai::app
