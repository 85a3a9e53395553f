#include "studies/pipeline/plan.h"

#include <sstream>

namespace hipfai::studies {

const char* stage_kind_name(StageKind kind) {
  switch (kind) {
    case StageKind::kGenerateHip: return "generate-hip";
    case StageKind::kDressBones: return "dress-bones";
    case StageKind::kLocateHip: return "locate-hip";
    case StageKind::kLoadTissue: return "load-tissue";
    case StageKind::kCylindricalTable: return "cylindrical-table";
    case StageKind::kCylindricalQuery: return "cylindrical-query";
    case StageKind::kRadialTable: return "radial-table";
    case StageKind::kRadialQuery: return "radial-query";
    case StageKind::kRangeOfMotion: return "range-of-motion";
    case StageKind::kFiniteElement: return "finite-element";
    case StageKind::kAssessment: return "assessment";
    case StageKind::kWriteResults: return "write-results";
  }
  return "?";
}

int Plan::count(StageKind kind) const {
  int n = 0;
  for (const Stage& stage : stages) n += stage.kind == kind ? 1 : 0;
  return n;
}

std::string Plan::describe() const {
  std::ostringstream out;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    out << (i + 1) << ". " << stage_kind_name(stages[i].kind) << ": " << stages[i].label;
    if (stages[i].repeat > 1) out << "  (x" << stages[i].repeat << " steps)";
    out << '\n';
  }
  return out.str();
}

std::vector<Eigen::Vector3d> distinct_axes(const Motion& motion) {
  std::vector<Eigen::Vector3d> axes;
  for (const MotionStep& step : motion.steps) {
    bool known = false;
    for (const auto& axis : axes) known = known || (axis - step.axis).norm() < 1e-9;
    if (!known) axes.push_back(step.axis);
  }
  return axes;
}

std::string fe_load_description(const Scene& scene, const Motion& motion) {
  std::size_t with_force = 0;
  for (const MotionStep& step : motion.steps) with_force += step.force_N ? 1 : 0;
  std::ostringstream load;
  if (scene.motion.kind == MotionSpec::Kind::kStandingToSitting) {
    load << "sitting-down load, body weight " << scene.fe.body_weight_n << " N";
  } else if (with_force == motion.steps.size() && with_force > 0) {
    load << "the motion's joint forces";
  } else {
    load << (with_force > 0 ? "the motion's joint forces, " : "") << "constant joint force, body weight "
         << scene.fe.body_weight_n << " N";
  }
  return load.str();
}

Plan plan_scene(const Scene& scene, const Motion& motion) {
  Plan plan;
  const int steps = static_cast<int>(motion.steps.size());
  auto add = [&](StageKind kind, std::string label, int repeat = 1) {
    plan.stages.push_back({kind, std::move(label), repeat});
  };
  if (scene.parametric) {
    std::ostringstream label;
    label << "CE " << scene.parametric->ce_deg << " deg, alpha " << scene.parametric->alpha_deg
          << " deg, edge " << scene.parametric->edge_mm << " mm";
    add(StageKind::kGenerateHip, label.str());
  } else if (scene.bones) {
    add(StageKind::kDressBones, "cartilage and labrum synthesised on " + scene.bones->femur.filename().string() +
                                    " and " + scene.bones->pelvis.filename().string());
  } else {
    add(StageKind::kLocateHip, scene.model_dir.string());
  }
  for (const auto& tissue : scene.tissues) add(StageKind::kLoadTissue, tissue);

  const auto axes = distinct_axes(motion);
  const bool swap = scene.options.swap_roles;
  if (scene.outputs.count(Output::kCurvilinearDepth)) {
    for (std::size_t a = 0; a < axes.size(); ++a) {
      std::ostringstream axis;
      axis << " about axis " << (a + 1) << "/" << axes.size();
      add(StageKind::kCylindricalTable, "fixed labrum" + axis.str());
      if (swap) add(StageKind::kCylindricalTable, "fixed femur_bone (role swap)" + axis.str());
    }
    add(StageKind::kCylindricalQuery, "femur_bone vertices vs labrum", steps);
    if (swap) add(StageKind::kCylindricalQuery, "labrum vertices vs femur_bone (role swap)", steps);
  }
  if (scene.outputs.count(Output::kRadialDepth)) {
    const std::string cells =
        " (" + std::string(contact::to_string(scene.options.mapping)) + ", " + std::to_string(scene.options.table_size) + " cells)";
    add(StageKind::kRadialTable, "fixed acetabular_cartilage+labrum" + cells);
    if (swap) add(StageKind::kRadialTable, "fixed femur_bone+femoral_cartilage (role swap)" + cells);
    add(StageKind::kRadialQuery, "femur_bone+femoral_cartilage vertices vs acetabular_cartilage+labrum", steps);
    if (swap) {
      add(StageKind::kRadialQuery, "acetabular_cartilage+labrum vertices vs femur_bone+femoral_cartilage (role swap)",
          steps);
    }
  }
  if (scene.outputs.count(Output::kRom)) {
    for (std::size_t a = 0; a < axes.size(); ++a) {
      add(StageKind::kRangeOfMotion, "femur_bone vs acetabular_bone, axis " + std::to_string(a + 1));
    }
  }
  if (scene.outputs.count(Output::kAssessment)) {
    add(StageKind::kAssessment, "femur_bone and acetabular_bone, frame from model.json: measures, clinical "
                                "motions, the motion's bone-to-bone depths (assessment/)");
  }
  if (needs_fe(scene)) {
    std::ostringstream label;
    label << "contact FE over the motion (level " << to_string(scene.fe.level) << "; " << fe_load_description(scene, motion)
          << ')';
    add(StageKind::kFiniteElement, label.str(), steps);
  }
  add(StageKind::kWriteResults, "results.h5, CSV");
  return plan;
}

}  // namespace hipfai::studies
