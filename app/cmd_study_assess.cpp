// hipfai study assess-truth: the patient-specific assessment against known truth — the 25
// generated hips assessed from their bones, moved and mirrored (studies/assessment_truth.h).
// Registered as "study.assess", which sorts after "study": the parent sub-command exists by then.
#include "app/command_registry.h"
#include "studies/assessment_truth.h"
#include "studies/assessment_truth_report.h"

#include <iomanip>
#include <iostream>
#include <memory>

namespace hipfai::app {
namespace {

const CommandRegistrar registrar("study.assess", [](CLI::App& parent) {
  CLI::App* study = parent.get_subcommand("study");
  auto* truth = study->add_subcommand(
      "assess-truth", "The assessment (hipfai assess) against known truth: the 25 generated hips from their bones "
                      "with their model.json as frame, moved and mirrored into left hips (known_truth.md, .csv)");
  auto options = std::make_shared<studies::AssessmentTruthOptions>();
  truth->add_option("--out", options->out_dir, "Output folder")->capture_default_str();
  truth->add_option("--edge-mm", options->edge_mm, "Surface edge length of the generated hips")
      ->capture_default_str()->check(CLI::Range(0.5, 10.0));
  truth->add_option("--seed", options->seed, "Seed of the random rigid transforms")->capture_default_str();
  truth->add_flag("--quick", options->quick, "Test-sized: two hips at 3 mm");
  truth->callback([options] {
    const auto result = studies::run_assessment_truth(*options);
    const auto report = studies::write_assessment_truth(result);
    std::cout << "report: " << report.string() << " (" << std::fixed << std::setprecision(1) << result.seconds
              << " s)\n";
  });
});

}  // namespace
}  // namespace hipfai::app
