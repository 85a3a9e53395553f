#include "studies/pipeline/plan.h"

#include <gtest/gtest.h>

namespace hipfai::studies {
namespace {

Scene scene_with(std::set<Output> outputs, bool swap = true) {
  Scene scene;
  scene.parametric = ParametricHip{};
  scene.outputs = std::move(outputs);
  for (Output o : scene.outputs) {
    const auto t = tissues_for(o);
    scene.tissues.insert(t.begin(), t.end());
  }
  scene.options.swap_roles = swap;
  return scene;
}

TEST(Plan, RadialOnlySceneBuildsNoCylindricalTableAndNoFe) {
  const Plan plan = plan_scene(scene_with({Output::kRadialDepth}), standing_to_sitting(30));
  EXPECT_EQ(plan.count(StageKind::kCylindricalTable), 0);
  EXPECT_EQ(plan.count(StageKind::kCylindricalQuery), 0);
  EXPECT_EQ(plan.count(StageKind::kFiniteElement), 0);
  EXPECT_EQ(plan.count(StageKind::kRadialTable), 2);  // both roles
  EXPECT_EQ(plan.count(StageKind::kLoadTissue), 4);   // no acetabular bone
}

TEST(Plan, CurvilinearOnlyLoadsBoneAndLabrum) {
  const Plan plan = plan_scene(scene_with({Output::kCurvilinearDepth}, false), standing_to_sitting(30));
  EXPECT_EQ(plan.count(StageKind::kLoadTissue), 2);
  // Standing to sitting turns about one axis: one table serves all 30 steps.
  EXPECT_EQ(plan.count(StageKind::kCylindricalTable), 1);
  EXPECT_EQ(plan.count(StageKind::kRadialTable), 0);
}

TEST(Plan, CsvMotionWithSeveralAxesGetsOneTablePerAxis) {
  Motion motion;
  motion.steps = {make_step({10, 0, 0}), make_step({20, 0, 0}), make_step({0, 10, 0})};
  const Plan plan = plan_scene(scene_with({Output::kCurvilinearDepth, Output::kRom}, false), motion);
  EXPECT_EQ(plan.count(StageKind::kCylindricalTable), 2);
  EXPECT_EQ(plan.count(StageKind::kRangeOfMotion), 2);
}

// The FE stage label of a plan ("" when it has none).
std::string fe_label(const Plan& plan) {
  for (const Stage& stage : plan.stages) {
    if (stage.kind == StageKind::kFiniteElement) return stage.label;
  }
  return "";
}

TEST(Plan, FeOnlyWhenAsked) {
  Scene scene = scene_with({Output::kVonMises});
  scene.fe.level = FeLevel::kCoarse;
  const Plan plan = plan_scene(scene, standing_to_sitting(5));
  EXPECT_EQ(plan.count(StageKind::kFiniteElement), 1);
  // The FE tissues: no acetabular bone.
  EXPECT_EQ(plan.count(StageKind::kLoadTissue), 4);
  EXPECT_EQ(plan.count(StageKind::kRadialTable) + plan.count(StageKind::kCylindricalTable), 0);
  EXPECT_EQ(plan.count(StageKind::kRadialQuery) + plan.count(StageKind::kCylindricalQuery), 0);
  EXPECT_EQ(plan.count(StageKind::kRangeOfMotion), 0);
  EXPECT_EQ(fe_label(plan), "contact FE over the motion (level coarse; sitting-down load, body weight 700 N)");
  EXPECT_EQ(plan.stages.back().kind, StageKind::kWriteResults);
  EXPECT_NE(plan.describe().find("finite-element: contact FE over the motion (level coarse"), std::string::npos);
}

TEST(Plan, FeAfterThePenetrationStagesWithItsLoad) {
  Scene scene = scene_with({Output::kRadialDepth, Output::kContactPressure});
  scene.motion.kind = MotionSpec::Kind::kMedical;
  scene.fe.body_weight_n = 800;
  const Plan plan = plan_scene(scene, medical_rotation("flexion", 60, 4));
  ASSERT_EQ(plan.count(StageKind::kFiniteElement), 1);
  EXPECT_EQ(plan.stages[plan.stages.size() - 2].kind, StageKind::kFiniteElement);
  EXPECT_EQ(plan.stages[plan.stages.size() - 2].repeat, 4);
  EXPECT_EQ(plan.count(StageKind::kRadialTable), 2);
  EXPECT_EQ(fe_label(plan), "contact FE over the motion (level default; constant joint force, body weight 800 N)");
}

TEST(Plan, PenetrationOnlyScenesHaveNoFeStage) {
  for (Output output : {Output::kCurvilinearDepth, Output::kRadialDepth, Output::kRom}) {
    const Plan plan = plan_scene(scene_with({output}), standing_to_sitting(5));
    EXPECT_EQ(plan.count(StageKind::kFiniteElement), 0) << output_name(output);
    EXPECT_EQ(fe_label(plan), "") << output_name(output);
  }
}

}  // namespace
}  // namespace hipfai::studies
