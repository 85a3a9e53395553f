// hipfai study hjc-cohort / study hjc: the HJC estimators against a known centre (generated hips)
// and the HJC sensitivity study of thesis §4.4 (rotations about each method's centre).
// Registered as "study.hjc", which sorts after "study": the parent sub-command exists by then.
#include "app/command_registry.h"
#include "core/error.h"
#include "studies/hjc_cohort.h"
#include "studies/hjc_study.h"

#include <iomanip>
#include <iostream>
#include <memory>

namespace hipfai::app {
namespace {

const CommandRegistrar registrar("study.hjc", [](CLI::App& parent) {
  CLI::App* study = parent.get_subcommand("study");

  auto* cohort = study->add_subcommand(
      "hjc-cohort", "HJC estimators against a known centre: generated hips perturbed like real segmentations "
                    "(noise, asphericity, uneven joint space, cam, partial lunate, coarse/fine meshes); error per "
                    "method and perturbation (cohort.md, cohort.csv, cohort_summary.csv, cohort.h5)");
  auto cohort_options = std::make_shared<studies::HjcCohortOptions>();
  auto cohort_out = std::make_shared<std::string>("out/hjc-cohort");
  auto cohort_quick = std::make_shared<bool>(false);
  cohort->add_option("--out", *cohort_out, "Output folder")->capture_default_str();
  cohort->add_option("--replicates", cohort_options->replicates, "Replicates of each random perturbation per hip")
      ->capture_default_str()->check(CLI::Range(1, 100));
  cohort->add_option("--edge-mm", cohort_options->edge_mm, "Surface edge length of the base hips")
      ->capture_default_str()->check(CLI::Range(0.5, 10.0));
  cohort->add_flag("--quick", *cohort_quick, "Test-sized: one hip (CE 20), 2 replicates, no fine mesh");
  cohort->callback([=] {
    studies::HjcCohortOptions run = *cohort_options;
    run.out_dir = *cohort_out;
    if (*cohort_quick) {
      run.ce_deg = {20.0};
      run.replicates = 2;
      run.include_fine = false;
      run.edge_mm = 3.0;
    }
    const auto result = studies::run_hjc_cohort(run);
    std::cout << "report: " << result.report_path.string() << " (" << std::fixed << std::setprecision(1)
              << result.seconds << " s)\n";
  });

  auto* hjc = study->add_subcommand(
      "hjc", "HJC sensitivity study (thesis §4.4): rotations about each method's centre through the six medical "
             "rotations, maximum curvilinear and radial depth per degree, differences to dref (Eq. 12-15) and to the "
             "true centre; bones only: range of motion per method and axis");
  auto options = std::make_shared<studies::HjcStudyOptions>();
  auto quick = std::make_shared<bool>(false);
  auto out = std::make_shared<std::string>("out/hjc");
  hjc->add_option("--out", *out, "Output folder")->capture_default_str();
  hjc->add_option("--femur", options->femur, "Bones-only mode: femur mesh (e.g. a CT femur)")->check(CLI::ExistingFile);
  hjc->add_option("--pelvis", options->pelvis, "Bones-only mode: pelvis mesh, same frame")->check(CLI::ExistingFile);
  hjc->add_option("--edge-mm", options->edge_mm, "Surface edge length of the generated subjects")
      ->capture_default_str()->check(CLI::Range(0.5, 10.0));
  hjc->add_option("--step-deg", options->step_deg, "Rotation step (thesis: 1 deg)")
      ->capture_default_str()->check(CLI::Range(0.1, 30.0));
  hjc->add_flag("--quick", *quick, "Test-sized: two generated subjects at 3 mm, 5 deg steps");
  hjc->callback([=] {
    studies::HjcStudyOptions run = *options;
    run.out_dir = *out;
    if (run.femur.empty() != run.pelvis.empty()) throw_error("study hjc: give both --femur and --pelvis, or neither");
    if (*quick) {
      run.subjects = {{20.0, 40.0}, {30.0, 70.0}};
      run.edge_mm = 3.0;
      run.step_deg = 5.0;
      run.centre_offsets_mm = {2.0};
    }
    const auto result = studies::run_hjc_study(run);
    std::cout << "report: " << result.report_path.string() << " (" << std::fixed << std::setprecision(1)
              << result.seconds << " s)\n";
  });
});

}  // namespace
}  // namespace hipfai::app
