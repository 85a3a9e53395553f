// hipfai soft-tissue: cartilage and labrum synthesised on a segmented femur and pelvis, written as a
// hip model folder every command reads (studies/pipeline/soft_tissue_model.h).
#include "app/bone_pair_args.h"
#include "app/command_registry.h"
#include "studies/pipeline/soft_tissue_model.h"

#include <cstdio>
#include <memory>
#include <string>

namespace hipfai::app {
namespace {

struct SoftTissueArgs {
  BonePairArgs bones;
  std::string out;
};

void run(const SoftTissueArgs& args) {
  geometry::TriMesh femur, pelvis;
  studies::SoftTissueModelRequest request;
  request.assessment = bone_pair_request(args.bones, femur, pelvis);
  const studies::SoftTissueModel result = studies::build_soft_tissue_model(request);
  studies::write_soft_tissue_model(result, args.bones.femur, args.bones.pelvis, args.out);
  const auto& t = result.report;
  std::printf("%s hip: femoral cartilage %.0f mm2, mean %.2f mm (%.2f-%.2f); acetabular cartilage %.0f mm2, mean %.2f mm "
              "(%.2f-%.2f); labrum %.0f mm3 in %d piece(s)\n",
              anatomy::side_name(result.side), t.femoral.covered_area_mm2, t.femoral.mean_thickness_mm,
              t.femoral.min_thickness_mm, t.femoral.max_thickness_mm, t.acetabular.covered_area_mm2,
              t.acetabular.mean_thickness_mm, t.acetabular.min_thickness_mm, t.acetabular.max_thickness_mm,
              t.labrum_volume_mm3, t.labrum_pieces);
  std::printf("%.2f s; written to %s (model.json, soft_tissue.md)\n", result.total_seconds, args.out.c_str());
}

const CommandRegistrar soft_tissue_registrar("soft-tissue", [](CLI::App& parent) {
  auto* command = parent.add_subcommand(
      "soft-tissue", "Cartilage and labrum synthesised on a segmented femur and pelvis, written as a hip model "
                     "folder (model.json and the five tissues, hip frame) for run, collide and the other commands");
  auto args = std::make_shared<SoftTissueArgs>();
  add_bone_pair_options(command, args->bones);
  command->add_option("--out", args->out, "Output folder (written whole or not at all; replaced if it exists)")
      ->required();
  command->callback([args] { run(*args); });
});

}  // namespace
}  // namespace hipfai::app
