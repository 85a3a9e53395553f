// The scene runner end to end on a generated hip: demand-driven stages and the cache.
#include "studies/pipeline/scene_runner.h"

#include "studies/results/results_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace hipfai::studies {
namespace {

std::filesystem::path runner_scratch(const std::string& name) {
  const auto path = std::filesystem::temp_directory_path() / ("hipfai_runner_" + name);
  std::filesystem::remove_all(path);
  return path;
}

// steps.csv read back as text: header and rows of cells.
struct StepsCsv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  bool has(const std::string& name) const {
    return std::find(header.begin(), header.end(), name) != header.end();
  }
  std::vector<std::string> column(const std::string& name) const {
    const auto at = std::find(header.begin(), header.end(), name);
    EXPECT_NE(at, header.end()) << "no column " << name;
    std::vector<std::string> cells;
    if (at == header.end()) return cells;
    for (const auto& row : rows) cells.push_back(row.at(static_cast<std::size_t>(at - header.begin())));
    return cells;
  }
  std::vector<double> numbers(const std::string& name) const {
    std::vector<double> values;
    for (const auto& cell : column(name)) values.push_back(std::stod(cell));
    return values;
  }
};

StepsCsv read_steps_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in.good()) << file;
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream stream(line);
    std::string cell;
    while (std::getline(stream, cell, ',')) cells.push_back(cell);
    return cells;
  };
  StepsCsv csv;
  std::string line;
  if (std::getline(in, line)) csv.header = split(line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    csv.rows.push_back(split(line));
    EXPECT_EQ(csv.rows.back().size(), csv.header.size()) << line;
  }
  return csv;
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
  const auto cache = runner_scratch("cache");
  SceneRunOptions options;
  options.out_dir = runner_scratch("out1");
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
  // Penetration outputs only: no FE, neither solved nor looked up in the cache.
  EXPECT_EQ(a.log.executed_count(StageKind::kFiniteElement), 0);
  EXPECT_EQ(a.log.reused_count(StageKind::kFiniteElement), 0);
  EXPECT_FALSE(a.fe.ran);
  EXPECT_FALSE(std::filesystem::exists(cache / "fe"));
  const StepsCsv steps = read_steps_csv(options.out_dir / "steps.csv");
  EXPECT_EQ(steps.rows.size(), 10u);
  EXPECT_TRUE(steps.has("max_radial_mm"));
  EXPECT_FALSE(steps.has("fe_status"));

  const Scene second = radial_scene(6);
  options.out_dir = runner_scratch("out2");
  const auto b = run_scene(second, motion_of(second), options);
  EXPECT_EQ(b.log.executed_count(StageKind::kGenerateHip), 0);
  EXPECT_EQ(b.log.reused_count(StageKind::kGenerateHip), 1);
  EXPECT_EQ(b.log.executed_count(StageKind::kRadialTable), 0);
  EXPECT_EQ(b.log.reused_count(StageKind::kRadialTable), 2);
  EXPECT_EQ(b.log.executed_count(StageKind::kFiniteElement), 0);
  EXPECT_EQ(b.log.reused_count(StageKind::kFiniteElement), 0);
  // Same hip, same end pose: the deepest radial penetration is reached at the last step in both.
  EXPECT_NEAR(a.run.steps.back().radial_max_mm(), b.run.steps.back().radial_max_mm(), 1e-12);

  std::size_t rows = 0;
  const auto depth = read_dataset(options.out_dir / "results.h5", "/radial/max_depth_mm", &rows);
  EXPECT_EQ(rows, 6u);
  for (double d : depth) EXPECT_TRUE(std::isfinite(d));
  EXPECT_TRUE(std::filesystem::exists(options.out_dir / "steps.csv"));
  for (const auto& entry : std::filesystem::directory_iterator(options.out_dir)) {
    EXPECT_NE(entry.path().extension(), ".partial") << entry.path();
  }
}

// Curvilinear depth: the pose caches (table + crossings per axis) come from the cache on a re-run
// whose motion has the same axis (standing to sitting with fewer sub-motions).
TEST(SceneRunner, CurvilinearPoseCachesAreReused) {
  const auto cache = runner_scratch("cache_curvilinear");
  SceneRunOptions options;
  options.out_dir = runner_scratch("out3");
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

// The FE's motion: standing-to-sitting carries the sitting-down load of the scene's body weight;
// a medical rotation keeps no force (the FE applies its constant joint force).
TEST(SceneRunner, FeMotionCarriesTheSittingDownLoad) {
  Scene scene = radial_scene(4);
  const Motion light = fe_motion_of(scene, motion_of(scene));
  ASSERT_EQ(light.steps.size(), 4u);
  for (const MotionStep& step : light.steps) ASSERT_TRUE(step.force_N.has_value());
  scene.fe.body_weight_n = 1400.0;
  const Motion heavy = fe_motion_of(scene, motion_of(scene));
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(heavy.steps[k].force_N->norm(), 2.0 * light.steps[k].force_N->norm(), 1e-9);
    EXPECT_GT(light.steps[k].force_N->z(), 0.0);  // the femur pushes the acetabulum superiorly
  }
  scene.motion.kind = MotionSpec::Kind::kMedical;
  scene.motion.medical = "flexion";
  scene.motion.max_deg = 60;
  scene.motion.steps = 4;
  for (const MotionStep& step : fe_motion_of(scene, motion_of(scene)).steps) EXPECT_FALSE(step.force_N);
}

#ifdef HIPFAI_WITH_FEM
Scene fe_scene(std::set<Output> outputs) {
  Scene scene;
  scene.file = "fe-test-scene";
  scene.name = "fe-test";
  scene.parametric = ParametricHip{40.0, 40.0, 3.0};
  scene.outputs = std::move(outputs);
  for (Output output : scene.outputs) {
    const auto tissues = tissues_for(output);
    scene.tissues.insert(tissues.begin(), tissues.end());
  }
  scene.motion.sub_motions = 2;  // standing to sitting in 2 steps: ~4 s at the coarse level
  scene.fe.level = FeLevel::kCoarse;
  return scene;
}

// An FE scene end to end: the FE runs once (no penetration stage for FE-only outputs), steps.csv
// and results.h5 carry its per-step values, and a second scene on the same hip, motion and level
// takes them from the cache, identical, whatever else it asks for.
TEST(SceneRunner, FeSceneRunsTheFeOnceAndReusesItFromTheCache) {
  const auto cache = runner_scratch("cache_fe");
  SceneRunOptions options;
  options.out_dir = runner_scratch("fe_out1");
  options.cache_dir = cache;
  options.progress = false;
  const Scene fe_only = fe_scene({Output::kVonMises, Output::kContactPressure});
  const auto a = run_scene(fe_only, motion_of(fe_only), options);
  EXPECT_EQ(a.log.executed_count(StageKind::kFiniteElement), 1);
  EXPECT_EQ(a.log.reused_count(StageKind::kFiniteElement), 0);
  for (StageKind kind : {StageKind::kRadialTable, StageKind::kRadialQuery, StageKind::kCylindricalTable,
                         StageKind::kCylindricalQuery, StageKind::kRangeOfMotion}) {
    EXPECT_EQ(a.log.executed_count(kind) + a.log.reused_count(kind), 0) << stage_kind_name(kind);
  }
  EXPECT_TRUE(a.run.steps.empty());
  ASSERT_TRUE(a.fe.ran);
  EXPECT_FALSE(a.fe.reused);
  EXPECT_EQ(a.fe.not_converged, 0u);
  EXPECT_TRUE(std::filesystem::exists(a.fe.entry / "fe.csv"));

  const StepsCsv steps = read_steps_csv(options.out_dir / "steps.csv");
  ASSERT_EQ(steps.rows.size(), 2u);
  EXPECT_FALSE(steps.has("max_radial_mm"));  // no penetration output, no penetration column
  for (const auto& status : steps.column("fe_status")) EXPECT_EQ(status, "converged");
  for (const std::string tissue : {"femoral_cartilage", "acetabular_cartilage", "labrum"}) {
    const auto max = steps.numbers("von_mises_max_" + tissue + "_mpa");
    const auto ball = steps.numbers("von_mises_ball_" + tissue + "_mpa");
    const auto p95 = steps.numbers("von_mises_p95_" + tissue + "_mpa");
    ASSERT_EQ(max.size(), 2u);
    for (std::size_t k = 0; k < max.size(); ++k) {
      EXPECT_TRUE(std::isfinite(max[k]) && max[k] > 0.0) << tissue << " step " << k + 1 << ": " << max[k];
      EXPECT_TRUE(std::isfinite(ball[k]) && ball[k] > 0.0) << tissue << " step " << k + 1 << ": " << ball[k];
      // A percentile of the same stresses cannot exceed their maximum (the columns are not mixed up).
      EXPECT_GT(p95[k], 0.0) << tissue;
      EXPECT_LE(p95[k], max[k]) << tissue;
    }
  }
  const auto pressure = steps.numbers("pressure_max_mpa");
  const auto mean_pressure = steps.numbers("pressure_mean_mpa");
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_GT(mean_pressure[k], 0.0);
    EXPECT_GE(pressure[k], mean_pressure[k]);
  }
  EXPECT_TRUE(steps.has("pressure_ball_mpa"));
  // results.h5 has the same values at full precision, with units.
  const auto file = options.out_dir / "results.h5";
  EXPECT_EQ(read_dataset(file, "/fe/von_mises_max_labrum_mpa"),
            a.fe.column(VonMisesMeasure{VonMisesStat::kMax, FeTissue::kLabrum}));
  EXPECT_EQ(read_dataset(file, "/fe/pressure_max_mpa"), a.fe.column(PressureStat::kMax));
  EXPECT_EQ(read_string_attribute(file, "/fe/pressure_max_mpa", "units"), "MPa");
  EXPECT_EQ(read_string_attribute(file, "/fe", "level"), "coarse");
  EXPECT_NE(a.text.find("FE level coarse"), std::string::npos) << a.text;
  EXPECT_NE(a.text.find("0 of 2 steps not converged"), std::string::npos) << a.text;

  // Same hip, motion and level, with a penetration output and von Mises only: the FE comes from the
  // cache, the radial stages run, the pressure columns are left out.
  options.out_dir = runner_scratch("fe_out2");
  const Scene mixed = fe_scene({Output::kRadialDepth, Output::kVonMises});
  const auto b = run_scene(mixed, motion_of(mixed), options);
  EXPECT_EQ(b.log.executed_count(StageKind::kFiniteElement), 0);
  EXPECT_EQ(b.log.reused_count(StageKind::kFiniteElement), 1);
  EXPECT_EQ(b.log.reused_count(StageKind::kGenerateHip), 1);
  EXPECT_EQ(b.log.executed_count(StageKind::kRadialTable), 2);
  EXPECT_TRUE(b.fe.reused);
  EXPECT_EQ(b.fe.entry, a.fe.entry);
  EXPECT_EQ(b.run.steps.size(), 2u);
  const StepsCsv again = read_steps_csv(options.out_dir / "steps.csv");
  EXPECT_TRUE(again.has("max_radial_mm"));
  EXPECT_FALSE(again.has("pressure_max_mpa"));
  for (const FeTissue tissue : kFeTissues) {
    for (const VonMisesStat stat : kVonMisesStats) {
      const VonMisesMeasure measure{stat, tissue};
      const std::string name = fe_measure_name(measure);
      EXPECT_EQ(b.fe.column(measure), a.fe.column(measure)) << name;
      EXPECT_EQ(again.column(name), steps.column(name)) << name;
    }
  }
}
#endif

}  // namespace
}  // namespace hipfai::studies
