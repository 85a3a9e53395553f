// hipfai run SCENE [--plan]: runs a scene, computing only the outputs it asks for.
#include "app/command_registry.h"
#include "studies/pipeline/plan.h"
#include "studies/pipeline/scene.h"
#include "studies/pipeline/scene_runner.h"

#include <iostream>

namespace hipfai::app {
namespace {

const CommandRegistrar run_registrar("run", [](CLI::App& parent) {
  auto* command = parent.add_subcommand(
      "run", "Run a scene file: only the stages its outputs need (see meshes/scenes/)");
  struct Args {
    std::string scene;
    std::string out = "out/run";
    std::string cache = "cache";
    bool plan_only = false;
    int threads = 2;
    std::vector<int> vtp_steps;
  };
  auto args = std::make_shared<Args>();
  command->add_option("scene", args->scene, "Scene file (YAML, schema_version 1)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_flag("--plan", args->plan_only, "Print the plan and exit without running it");
  command->add_option("--out", args->out, "Output folder")->capture_default_str();
  command->add_option("--cache", args->cache, "Cache folder for meshes and tables")->capture_default_str();
  command->add_option("--threads", args->threads, "Threads for the per-pose queries")->capture_default_str()
      ->check(CLI::Range(1, 256));
  command->add_option("--vtp-step", args->vtp_steps,
                      "Write VTP depth fields of these steps (1-based; 0 = last)");
  command->callback([args] {
    const studies::Scene scene = studies::read_scene(args->scene);
    const studies::Motion motion = studies::motion_of(scene);
    const studies::Plan plan = studies::plan_scene(scene, motion);
    if (args->plan_only) {
      std::cout << "plan for scene '" << scene.name << "' (" << motion.steps.size()
                << " motion steps):\n"
                << plan.describe();
      return;
    }
    studies::SceneRunOptions options;
    options.out_dir = args->out;
    options.cache_dir = args->cache;
    options.threads = args->threads;
    options.vtp_steps = args->vtp_steps;
    const auto summary = studies::run_scene(scene, motion, options);
    std::cout << summary.text;
  });
});

}  // namespace
}  // namespace hipfai::app
