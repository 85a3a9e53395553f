// hipfai study assess-truth / soft-tissue-truth: the patient-specific assessment and the soft tissue
// synthesised on bones against known truth — the 25 generated hips from their bones, moved and
// mirrored (studies/assessment_truth.h), and stripped and re-dressed (studies/soft_tissue_truth.h).
// Registered as "study.assess", which sorts after "study": the parent sub-command exists by then.
#include "app/command_registry.h"
#include "studies/assessment_truth.h"
#include "studies/assessment_truth_report.h"
#include "studies/pipeline/mpi_launch.h"
#include "studies/soft_tissue_truth.h"
#include "studies/soft_tissue_truth_report.h"

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

namespace hipfai::app {
namespace {

const CommandRegistrar study_assess_registrar("study.assess", [](CLI::App& parent) {
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

  auto* tissue = study->add_subcommand(
      "soft-tissue-truth", "Synthesised cartilage and labrum against known truth: the 25 generated hips stripped to "
                           "their bones, tissues synthesised, penetration depths over standing-to-sitting compared "
                           "(soft_tissue_truth.md, .csv)");
  auto tissue_options = std::make_shared<studies::SoftTissueTruthOptions>();
  tissue->add_option("--out", tissue_options->out_dir, "Output folder")->capture_default_str();
  tissue->add_option("--edge-mm", tissue_options->edge_mm, "Surface edge length of the generated hips")
      ->capture_default_str()->check(CLI::Range(0.5, 10.0));
  tissue->add_option("--sub-motions", tissue_options->sub_motions, "Standing-to-sitting steps")
      ->capture_default_str()->check(CLI::Range(1, 200));
  tissue->add_option("--threads", tissue_options->threads, "Threads of the penetration queries")->capture_default_str();
  tissue->add_flag("--quick", tissue_options->quick, "Test-sized: two hips at 3 mm, 10 sub-motions, FE coarse");
#ifdef HIPFAI_WITH_FEM
  auto fe_level = std::make_shared<std::string>(to_string(FeLevel::kDefault));
#else
  auto fe_level = std::make_shared<std::string>("none");
#endif
  std::vector<std::string> fe_level_choices = fe_level_names();
  fe_level_choices.insert(fe_level_choices.begin(), "none");
  CLI::Option* fe_level_option = tissue->add_option("--fe-level", *fe_level,
                     "FE of both tissue sets at this level (docs/fem-levels.md), or none")
      ->capture_default_str()->check(CLI::IsMember(fe_level_choices));
  tissue->add_option("--cache", tissue_options->cache_dir, "Cache folder of the FE runs (shared with study validate)")
      ->capture_default_str();
  tissue->add_option("--jobs", tissue_options->jobs, "FE runs at once (one per process)")
      ->capture_default_str()->check(CLI::Range(1, 64));
  tissue->callback([tissue_options, fe_level, fe_level_option] {
    studies::SoftTissueTruthOptions run = *tissue_options;
    run.fe_level = fe_level_from_name(*fe_level);  // none: no FE
    if (run.quick && fe_level_option->count() == 0 && run.fe_level) run.fe_level = FeLevel::kCoarse;
    run.program = std::filesystem::read_symlink("/proc/self/exe");
    // Under mpirun / srun the hips are spread over the ranks, and rank 0 alone reports.
    run.spread = studies::unit_spread_of_this_process();
    const auto result = studies::run_soft_tissue_truth(run);
    if (!result.holds_results) return;
    // A hip that failed is named in one line; the others' tables and report are kept.
    if (result.rows.empty()) studies::throw_if_units_failed("soft-tissue-truth", result.failed, 0, "hips", run.out_dir);
    const auto report = studies::write_soft_tissue_truth(result);
    std::cout << "report: " << report.string() << " (" << std::fixed << std::setprecision(1) << result.seconds
              << " s)\n";
    studies::throw_if_units_failed("soft-tissue-truth", result.failed, result.rows.size(), "hips", run.out_dir);
  });
});

}  // namespace
}  // namespace hipfai::app
