// hipfai study hjc-cohort / study hjc: the HJC estimators against a known centre (generated hips)
// and the HJC sensitivity study of thesis §4.4 (rotations about each method's centre).
// Registered as "study.hjc", which sorts after "study": the parent sub-command exists by then.
#include "app/command_registry.h"
#include "core/error.h"
#include "studies/hjc_cohort.h"
#include "studies/hjc_study.h"

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

namespace hipfai::app {
namespace {

// The options both studies share: output folder, edge length of the generated hips, --quick.
struct CommonOptions {
  std::string out;
  bool quick = false;
};

std::shared_ptr<CommonOptions> add_common_options(CLI::App* command, const std::string& default_out,
                                                  double& edge_mm, const std::string& edge_help,
                                                  const std::string& quick_help) {
  auto common = std::make_shared<CommonOptions>();
  common->out = default_out;
  command->add_option("--out", common->out, "Output folder")->capture_default_str();
  command->add_option("--edge-mm", edge_mm, edge_help)->capture_default_str()->check(CLI::Range(0.5, 10.0));
  command->add_flag("--quick", common->quick, quick_help);
  return common;
}

void print_report(const std::filesystem::path& report, double seconds) {
  std::cout << "report: " << report.string() << " (" << std::fixed << std::setprecision(1) << seconds << " s)\n";
}

const CommandRegistrar study_hjc_registrar("study.hjc", [](CLI::App& parent) {
  CLI::App* study = parent.get_subcommand("study");

  auto* cohort = study->add_subcommand(
      "hjc-cohort", "HJC estimators against a known centre: generated hips perturbed like real segmentations "
                    "(noise, asphericity, uneven joint space, cam, partial lunate, coarse/fine meshes); error per "
                    "method and perturbation (cohort.md, cohort.csv, cohort_summary.csv, cohort.h5)");
  auto cohort_options = std::make_shared<studies::HjcCohortOptions>();
  const auto cohort_common =
      add_common_options(cohort, "out/hjc-cohort", cohort_options->edge_mm, "Surface edge length of the base hips",
                         "Test-sized: one hip (CE 20) at 3 mm, 2 replicates, no fine mesh");
  cohort->add_option("--replicates", cohort_options->replicates, "Replicates of each random perturbation per hip")
      ->capture_default_str()->check(CLI::Range(1, 100));
  cohort->callback([=] {
    studies::HjcCohortOptions run = *cohort_options;
    run.out_dir = cohort_common->out;
    if (cohort_common->quick) run = studies::quick_hjc_cohort_options(run);
    const auto result = studies::run_hjc_cohort(run);
    print_report(result.report_path, result.seconds);
  });

  auto* hjc = study->add_subcommand(
      "hjc", "HJC sensitivity study (thesis §4.4): rotations about each method's centre through the six medical "
             "rotations, maximum curvilinear and radial depth per degree, differences to dref (Eq. 12-15) and to the "
             "true centre; bones only: range of motion per method and axis");
  auto options = std::make_shared<studies::HjcStudyOptions>();
  const auto common = add_common_options(hjc, "out/hjc", options->edge_mm, "Surface edge length of the generated subjects",
                                         "Test-sized: two generated subjects at 3 mm, 5 deg steps");
  hjc->add_option("--femur", options->femur, "Bones-only mode: femur mesh (e.g. a CT femur)")->check(CLI::ExistingFile);
  hjc->add_option("--pelvis", options->pelvis, "Bones-only mode: pelvis mesh, same frame")->check(CLI::ExistingFile);
  hjc->add_option("--step-deg", options->step_deg, "Rotation step (thesis: 1 deg)")
      ->capture_default_str()->check(CLI::Range(0.1, 30.0));
  hjc->callback([=] {
    studies::HjcStudyOptions run = *options;
    run.out_dir = common->out;
    if (run.femur.empty() != run.pelvis.empty()) throw_error("study hjc: give both --femur and --pelvis, or neither");
    if (common->quick) run = studies::quick_hjc_study_options(run);
    // Under mpirun / srun the subjects are spread over the ranks, and rank 0 alone reports.
    run.spread = studies::unit_spread_of_this_process();
    const auto result = studies::run_hjc_study(run);
    if (!result.holds_results) return;
    // A subject that failed is named in one line; the others' report is kept.
    if (result.subjects.empty()) studies::throw_if_units_failed("study hjc", result.failed, 0, "hips", run.out_dir);
    print_report(result.report_path, result.seconds);
    studies::throw_if_units_failed("study hjc", result.failed, result.subjects.size(), "hips", run.out_dir);
  });
});

}  // namespace
}  // namespace hipfai::app
