// hipfai assess: the patient-specific FAI assessment of a segmented femur and pelvis — frames found
// on the bones, radiographic measures in 3D, clinical motions to bony impingement, a user motion's
// bone-to-bone depths, virtual resections (studies/pipeline/assessment.h); writes DIR/assessment.json,
// DIR/report.md with its figures, and VTP files (studies/pipeline/assessment_report.h).
#include "app/bone_pair_args.h"
#include "app/cli_util.h"
#include "app/command_registry.h"
#include "anatomy/opensim_motion.h"
#include "core/error.h"
#include "geometry/hip_measure.h"
#include "geometry/mesh_io.h"
#include "studies/pipeline/assessment.h"
#include "studies/pipeline/soft_tissue_model.h"
#include "studies/pipeline/assessment_report.h"
#include "studies/pipeline/motion.h"

#include <cstdio>
#include <memory>
#include <string>

namespace hipfai::app {
namespace {

struct AssessArgs {
  BonePairArgs bones;
  std::string motion, out, soft_tissue;
  double resect_alpha_deg = -1.0, trim_rim_deg = -1.0;
  int threads = 1;
  bool quiet = false;
};

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// A motion CSV (studies/pipeline/motion.h) or an OpenSim .mot/.sto (anatomy/opensim_motion.h).
studies::Motion read_user_motion(const std::filesystem::path& path, std::optional<anatomy::Side> side) {
  const std::string ext = lower_extension(path);
  if (ext == ".csv") return studies::read_motion_csv(path);
  if (ext == ".mot" || ext == ".sto") {
    const anatomy::JointAngleSeries series = anatomy::read_opensim_motion(path, side);
    if (side && series.side != *side) {
      throw_error(path.string(), ": its hip columns are the ", anatomy::side_name(series.side), " hip's, the hip is ",
                  anatomy::side_name(*side));
    }
    studies::Motion motion;
    motion.name = series.name.empty() ? path.stem().string() : series.name;
    for (const auto& pose : series.poses) motion.steps.push_back(studies::make_step(pose));
    return motion;
  }
  throw_error(path.string(), ": a motion is a .csv (step,flexion_deg,adduction_deg,internal_rotation_deg) or an "
              "OpenSim .mot/.sto file");
}

void print_summary(const studies::AssessmentResult& r, const std::string& out) {
  const auto& m = r.before.measures;
  std::printf("%s hip (%s): %s\n", anatomy::side_name(r.side), r.side_source.c_str(),
              anatomy::morphology_name(m.morphology));
  std::printf("  lateral CE %.1f deg, acetabular inclination %.1f deg, version %.1f deg\n", m.lateral_ce.ce_deg,
              m.acetabular_inclination_deg, m.acetabular_version_deg);
  std::printf("  alpha %.1f deg (largest %.1f at %s), neck-shaft %.1f deg, femoral version %s\n", m.alpha.alpha_deg,
              m.alpha.max_alpha_deg, geometry::clock_label(m.alpha.max_plane_deg).c_str(), m.neck_shaft_deg,
              m.femoral_version_deg ? (std::to_string(*m.femoral_version_deg).substr(0, 5) + " deg").c_str() : "n/a");
  for (const auto* o : r.before.rom.motions()) {
    if (!o->limit) {
      std::printf("  %-34s   —      %s\n", "(not reached)", o->reason.c_str());
    } else if (o->limit->unlimited) {
      std::printf("  %-34s no bony contact\n", o->limit->name.c_str());
    } else {
      std::printf("  %-34s %6.1f deg  rim %-5s head-neck %s\n", o->limit->name.c_str(), o->limit->angle_deg,
                  o->limit->acetabular_clock.label.c_str(), o->limit->femoral_clock.label.c_str());
    }
  }
  std::printf("%.2f s; written to %s (assessment.json, report.md)\n", r.total_seconds, out.c_str());
}

void run(const AssessArgs& args) {
  geometry::TriMesh femur, pelvis;
  studies::AssessmentRequest request = bone_pair_request(args.bones, femur, pelvis);
  if (!args.motion.empty()) {
    std::optional<anatomy::Side> side = request.side;
    if (!side && request.frame) side = request.frame->side;
    request.motion = read_user_motion(args.motion, side);
  }
  if (args.resect_alpha_deg >= 0.0) request.resect_alpha_deg = args.resect_alpha_deg;
  if (args.trim_rim_deg >= 0.0) request.trim_rim_deg = args.trim_rim_deg;
  request.threads = args.threads;
  request.progress = !args.quiet;
  const studies::AssessmentResult result = studies::assess_hip(request);
  studies::write_assessment(result, {args.bones.femur, args.bones.pelvis, args.bones.frame, args.motion}, args.out);
  print_summary(result, args.out);
  if (!args.soft_tissue.empty()) {
    const studies::SoftTissueModel tissues = studies::soft_tissue_model_from(
        result, anatomy::SoftTissueOptions{}, request.femur_name, request.pelvis_name);
    studies::write_soft_tissue_model(tissues, args.bones.femur, args.bones.pelvis, args.soft_tissue);
    std::printf("soft tissue synthesised (%.2f s; articular sphere %.2f mm); hip model folder %s\n",
                tissues.total_seconds - tissues.assessment_seconds, tissues.report.articular_radius_mm,
                args.soft_tissue.c_str());
  }
}

const CommandRegistrar assess_registrar("assess", [](CLI::App& parent) {
  auto* command = parent.add_subcommand(
      "assess", "Patient-specific FAI assessment of a femur and pelvis: frames from the bones, CE, alpha and "
                "the other radiographic measures in 3D, clinical motions to bony impingement, virtual resection");
  auto args = std::make_shared<AssessArgs>();
  add_bone_pair_options(command, args->bones);
  command->add_option("--motion", args->motion,
                      "Motion: CSV (step,flexion_deg,adduction_deg,internal_rotation_deg) or OpenSim .mot/.sto "
                      "(hip_flexion_r, hip_adduction_r, hip_rotation_r or _l)")
      ->check(CLI::ExistingFile);
  command->add_option("--resect-alpha-deg", args->resect_alpha_deg,
                      "Virtual osteochondroplasty: remove the head-neck bone outside the head sphere beyond this alpha")
      ->check(CLI::Range(1.0, 179.0));
  command->add_option("--trim-rim-deg", args->trim_rim_deg,
                      "Virtual rim trimming: move the superior half of the acetabular rim this many degrees deeper")
      ->check(CLI::Range(0.1, 60.0));
  command->add_option("--threads", args->threads, "Threads for the range finder (0: all)")->capture_default_str();
  command->add_option("--out", args->out, "Output folder (replaced whole)")->required();
  command->add_option("--soft-tissue", args->soft_tissue,
                      "Also write a hip model folder with cartilage and labrum synthesised on the bones here "
                      "(as `hipfai soft-tissue`; replaced whole)");
  command->add_flag("--quiet", args->quiet, "No progress lines");
  command->callback([args] { run(*args); });
});

}  // namespace
}  // namespace hipfai::app
