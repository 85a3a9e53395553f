#include "studies/plan.h"

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

TEST(Plan, FeOnlyWhenAsked) {
  const Plan plan = plan_scene(scene_with({Output::kVonMises}), standing_to_sitting(5));
  EXPECT_EQ(plan.count(StageKind::kFiniteElement), 1);
  EXPECT_EQ(plan.count(StageKind::kLoadTissue), 5);
  EXPECT_EQ(plan.count(StageKind::kRadialTable) + plan.count(StageKind::kCylindricalTable), 0);
}

}  // namespace
}  // namespace hipfai::studies
