// The scene runner end to end on a generated hip: demand-driven stages and the cache.
#include "studies/scene_runner.h"

#include "studies/results_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace hipfai::studies {
namespace {

std::filesystem::path scratch(const std::string& name) {
  const auto path = std::filesystem::temp_directory_path() / ("hipfai_runner_" + name);
  std::filesystem::remove_all(path);
  return path;
}

Scene radial_scene(int sub_motions) {
  Scene scene;
  scene.file = "test-scene";
  scene.name = "test";
  scene.parametric = ParametricHip{40.0, 80.0, 3.0};
  scene.outputs = {Output::kRadialDepth};
  scene.tissues = tissues_for(Output::kRadialDepth);
  scene.motion.sub_motions = sub_motions;
  return scene;
}

// A radial-only scene runs no cylindrical stage; re-running with only the motion changed reuses
// the generated hip and both radial tables from the cache.
TEST(SceneRunner, RadialOnlyRunsOnlyItsStagesAndReusesTheCache) {
  const auto cache = scratch("cache");
  SceneRunOptions options;
  options.out_dir = scratch("out1");
  options.cache_dir = cache;
  const Scene first = radial_scene(10);
  const auto a = run_scene(first, motion_of(first), options);
  EXPECT_EQ(a.log.executed_count(StageKind::kGenerateHip), 1);
  EXPECT_EQ(a.log.executed_count(StageKind::kRadialTable), 2);
  EXPECT_EQ(a.log.executed_count(StageKind::kCylindricalTable), 0);
  EXPECT_EQ(a.log.executed_count(StageKind::kCylindricalQuery), 0);
  EXPECT_EQ(a.log.executed_count(StageKind::kRadialQuery), 20);  // 10 steps, both roles
  // The pelvis is not needed for radial depth and is not loaded.
  EXPECT_EQ(a.hip.tissues.count("acetabular_bone"), 0u);
  EXPECT_EQ(a.log.executed_count(StageKind::kLoadTissue), 4);

  const Scene second = radial_scene(6);
  options.out_dir = scratch("out2");
  const auto b = run_scene(second, motion_of(second), options);
  EXPECT_EQ(b.log.executed_count(StageKind::kGenerateHip), 0);
  EXPECT_EQ(b.log.reused_count(StageKind::kGenerateHip), 1);
  EXPECT_EQ(b.log.executed_count(StageKind::kRadialTable), 0);
  EXPECT_EQ(b.log.reused_count(StageKind::kRadialTable), 2);
  // Same hip, same end pose: the deepest radial penetration is reached at the last step in both.
  EXPECT_NEAR(a.run.steps.back().radial_max_mm(), b.run.steps.back().radial_max_mm(), 1e-12);

  std::size_t rows = 0;
  const auto depth = read_dataset(options.out_dir / "results.h5", "/radial/max_depth_mm", &rows);
  EXPECT_EQ(rows, 6u);
  for (double d : depth) EXPECT_TRUE(std::isfinite(d));
  EXPECT_TRUE(std::filesystem::exists(options.out_dir / "steps.csv"));
  EXPECT_FALSE(std::filesystem::exists(options.out_dir / "results.h5.partial"));
}

// Curvilinear depth: the pose caches (table + crossings per axis) come from the cache on a re-run
// whose motion has the same axis (standing to sitting with fewer sub-motions).
TEST(SceneRunner, CurvilinearPoseCachesAreReused) {
  const auto cache = scratch("cache_curvilinear");
  SceneRunOptions options;
  options.out_dir = scratch("out3");
  options.cache_dir = cache;
  Scene scene = radial_scene(10);
  scene.outputs = {Output::kCurvilinearDepth};
  scene.tissues = tissues_for(Output::kCurvilinearDepth);
  const auto a = run_scene(scene, motion_of(scene), options);
  EXPECT_EQ(a.log.executed_count(StageKind::kCylindricalTable), 2);
  EXPECT_EQ(a.log.executed_count(StageKind::kRadialTable), 0);
  scene.motion.sub_motions = 5;
  const auto b = run_scene(scene, motion_of(scene), options);
  EXPECT_EQ(b.log.executed_count(StageKind::kCylindricalTable), 0);
  EXPECT_EQ(b.log.reused_count(StageKind::kCylindricalTable), 2);
  EXPECT_NEAR(a.run.steps.back().curvilinear_max_mm(), b.run.steps.back().curvilinear_max_mm(), 1e-12);
}

}  // namespace
}  // namespace hipfai::studies
