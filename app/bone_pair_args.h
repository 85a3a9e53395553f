// hipfai — the inputs every command on a segmented femur and pelvis shares (assess, soft-tissue):
// the two bone files, --side and --frame, registered once and read into an AssessmentRequest.
#pragma once

#include "anatomy/frame_file.h"
#include "anatomy/side.h"
#include "app/command_registry.h"
#include "geometry/mesh_io.h"
#include "studies/pipeline/assessment.h"

#include <string>

namespace hipfai::app {

struct BonePairArgs {
  std::string femur, pelvis, side, frame;
};

inline void add_bone_pair_options(CLI::App* command, BonePairArgs& args) {
  command->add_option("--femur", args.femur, "Femur bone surface (STL, PLY, OBJ, VTP), closed")
      ->required()->check(CLI::ExistingFile);
  command->add_option("--pelvis", args.pelvis, "Pelvis bone surface, same frame; whole (both hemipelves) unless --frame")
      ->required()->check(CLI::ExistingFile);
  command->add_option("--side", args.side, "right or left (default: found from the bones)")
      ->check(CLI::IsMember({"right", "left"}));
  command->add_option("--frame", args.frame,
                      "JSON: frames (an assessment.json's \"frames\"), landmarks (ASIS, pubic tubercles, "
                      "epicondyles), or a hipfai hip model.json")
      ->check(CLI::ExistingFile);
}

// The bones read into `femur` and `pelvis` (which must outlive the request), side and frame parsed.
inline studies::AssessmentRequest bone_pair_request(const BonePairArgs& args, geometry::TriMesh& femur,
                                                    geometry::TriMesh& pelvis) {
  femur = geometry::read_mesh(args.femur);
  pelvis = geometry::read_mesh(args.pelvis);
  studies::AssessmentRequest request;
  request.femur = &femur;
  request.pelvis = &pelvis;
  request.femur_name = args.femur;
  request.pelvis_name = args.pelvis;
  if (!args.side.empty()) request.side = anatomy::side_from_name(args.side);
  if (!args.frame.empty()) request.frame = anatomy::read_frame_file(args.frame);
  return request;
}

}  // namespace hipfai::app
