// hipfai study fai: the 25-model FAI penetration study (thesis §4.3).
#include "app/cli_util.h"
#include "app/command_registry.h"
#include "core/error.h"
#include "geometry/hip_parameters.h"
#include "studies/fai_study.h"
#include "studies/hip_sensitivity.h"
#include "studies/hip_sensitivity_report.h"
#include "studies/pipeline/radial_mapping_name.h"
#include "studies/validation_report.h"
#include "studies/validation_study.h"

#include <filesystem>

#include <iomanip>
#include <iostream>

namespace hipfai::app {
namespace {

// What `study fai` reads from its command line besides the study's own options.
struct FaiArguments {
  studies::FaiStudyOptions options;
  bool quick = false;
  std::vector<double> resolutions{3.0, 2.5};
  std::string out = "out/fai";
  std::string cache = "cache";
  std::string mapping = contact::to_string(options.mapping);
  std::string radial_rule = contact::to_string(options.radial_rule);
  std::string samples = "vertices";
  std::string pose_sequence = "jcs";
  std::string femoral_neutral = "shaft";
  std::string hip_parameters;
};

void add_fai_options(CLI::App* fai, FaiArguments& arguments) {
  fai->add_flag("--quick", arguments.quick,
                "CI-sized run: 25 hips at 3 mm edges, 10 sub-motions, no resolution sweep");
  fai->add_option("--out", arguments.out, "Output folder")->capture_default_str();
  fai->add_option("--cache", arguments.cache, "Cache folder for generated hips and radial tables")
      ->capture_default_str();
  fai->add_option("--edge-mm", arguments.options.edge_mm, "Surface edge length of the main run")->capture_default_str()
      ->check(CLI::Range(0.3, 10.0));
  fai->add_option("--sub-motions", arguments.options.sub_motions, "Sub-motions of standing to sitting")->capture_default_str()
      ->check(CLI::Range(1, 1000));
  fai->add_option("--resolutions", arguments.resolutions,
                  "Extra edge lengths (mm) for the accuracy-vs-time table (archetype hips)")->capture_default_str()
      ->delimiter(',');
  fai->add_option("--mapping", arguments.mapping, "Radial mapping")->capture_default_str()
      ->check(CLI::IsMember({"spherical", "cartesian", "cube"}));
  fai->add_option("--radial-rule", arguments.radial_rule,
                  "Radial penetration: 'union' (femur inside the acetabular soft tissues) or 'beyond' (the "
                  "thesis' rule: femur beyond the socket's surface along the ray from the HJC)")
      ->capture_default_str()->check(CLI::IsMember({"union", "beyond"}));
  fai->add_option("--table-size", arguments.options.table_size, "Radial table cells")->capture_default_str()
      ->check(CLI::Range(6LL, 100000000LL));
  fai->add_option("--threads", arguments.options.threads, "Threads for the per-pose queries")->capture_default_str()
      ->check(CLI::Range(1, 256));
  fai->add_option("--contact-tolerance-mm", arguments.options.contact_tolerance_mm,
                  "Touching is not penetrating below this (mm); default: max(chord sagitta of the mesh, 0.1 mm "
                  "sphericity), the same tolerance at every resolution when given")
      ->check(CLI::Range(0.0, 5.0));
  fai->add_option("--curvilinear-samples", arguments.samples,
                  "Where the curvilinear depth is sampled: 'vertices' (the thesis' method) or 'boundary' (also "
                  "where the surfaces cross the sphere R + tolerance, the border of the striking region)")
      ->capture_default_str()->check(CLI::IsMember({"vertices", "boundary"}));
  fai->add_option("--pose-sequence", arguments.pose_sequence,
                  "How the end pose's (flexion, adduction, internal rotation) compose: 'jcs' (joint coordinate "
                  "system, X-Y'-Z'') or 'fixed-axes' (about the fixed pelvic X, then Y, then Z: the thesis' "
                  "wording read literally)")
      ->capture_default_str()->check(CLI::IsMember({"jcs", "fixed-axes"}));
  fai->add_option("--femoral-neutral", arguments.femoral_neutral,
                  "Where the femur's zero pose is: 'shaft' (the femur as built, shaft along the pelvic Z) or "
                  "'mechanical' (the ISB femoral frame: HJC-to-knee along Z, i.e. the femur adducted by the 6 deg "
                  "anatomic-mechanical angle first)")
      ->capture_default_str()->check(CLI::IsMember({"shaft", "mechanical"}));
  fai->add_option("--hip-parameters", arguments.hip_parameters,
                  "JSON file of generator parameters shared by every hip (keys of model.json's 'parameters'; "
                  "ce_deg, alpha_deg and edge_mm are the grid's)");
}

// The study's options from its command line (names checked by the parser).
studies::FaiStudyOptions fai_options(const FaiArguments& arguments) {
  studies::FaiStudyOptions run = arguments.options;
  run.pose_sequence = studies::pose_sequence_from_name(arguments.pose_sequence);  // a member: checked by IsMember
  run.femoral_neutral = arguments.femoral_neutral == "mechanical" ? geometry::FemoralNeutral::kMechanicalAxis
                                                                   : geometry::FemoralNeutral::kShaftAxis;
  if (!arguments.hip_parameters.empty()) run.base_parameters = geometry::load_hip_parameters(arguments.hip_parameters);
  run.out_dir = arguments.out;
  run.cache_dir = arguments.cache;
  run.resolution_edges_mm = arguments.resolutions;
  run.sample_striking_boundary = arguments.samples == "boundary";
  run.mapping = *studies::radial_mapping_from_name(arguments.mapping);  // a member: checked by IsMember
  run.radial_rule = arguments.radial_rule == "beyond" ? contact::RadialCrossingRule::kBeyond
                                                      : contact::RadialCrossingRule::kUnion;
  if (arguments.quick) {
    run.edge_mm = 3.0;
    run.sub_motions = 10;
    run.resolution_edges_mm.clear();
  }
  return run;
}

void print_fai_result(const studies::FaiStudyResult& result) {
  std::cout << std::fixed << std::setprecision(2) << " CE  alpha  max curvilinear  max radial  pathology\n";
  for (const auto& m : result.models) {
    std::cout << std::setw(3) << m.ce_deg << std::setw(7) << m.alpha_deg << std::setw(14)
              << m.max_curvilinear_mm << " mm" << std::setw(9) << m.max_radial_mm << " mm  " << m.pathology
              << '\n';
  }
  std::cout << "total " << result.total_seconds << " s; report: " << result.report_path << '\n';
}

void add_fai_command(CLI::App* study) {
  auto* fai = study->add_subcommand(
      "fai", "FAI penetration study: 25 hips (CE 0-40, alpha 40-80), standing to sitting; writes "
             "results.h5, CSV tables and report.md with figures");
  auto arguments = std::make_shared<FaiArguments>();
  add_fai_options(fai, *arguments);
  fai->callback([arguments] {
    studies::FaiStudyOptions run = fai_options(*arguments);
    // Under mpirun / srun the hips are spread over the ranks, and rank 0 alone reports.
    run.spread = studies::unit_spread_of_this_process();
    const auto result = studies::run_fai_study(run);
    if (!result.holds_results) return;
    // A hip that failed is named in one line; the others' tables and report are kept.
    if (result.models.empty()) studies::throw_if_units_failed("fai", result.failed, 0, "hips", run.out_dir);
    print_fai_result(result);
    studies::throw_if_units_failed("fai", result.failed, result.models.size(), "hips", run.out_dir);
  });
}

void add_study_validate_command(CLI::App* study) {
  auto* validate = study->add_subcommand(
      "validate", "FAI validation: penetration depths vs the FE ground truth on 25 hips over standing to sitting "
                  "(thesis Tables 8-9); writes steps.csv, timings.csv, correlation.csv and report.md");
  auto validate_options = std::make_shared<studies::ValidationOptions>();
  auto validate_quick = std::make_shared<bool>(false);
  auto validate_out = std::make_shared<std::string>("out/validate");
  auto validate_cache = std::make_shared<std::string>("cache");
  validate->add_flag("--quick", *validate_quick,
                     "Test-sized run: 2 hips (CE 20 / alpha 40, CE 40 / alpha 60) at 3 mm edges, 6 steps, FE coarse");
  add_enum_option(validate, "--fe-level", validate_options->fe_level, kFeLevels, "FE mesh level (docs/fem-levels.md)");
  validate->add_option("--out", *validate_out, "Output folder")->capture_default_str();
  validate->add_option("--cache", *validate_cache, "Cache folder: generated hips, radial tables, FE runs")
      ->capture_default_str();
  validate->add_option("--edge-mm", validate_options->edge_mm, "Surface edge length of the penetration method")
      ->capture_default_str()->check(CLI::Range(0.5, 10.0));
  validate->add_option("--steps", validate_options->sub_motions, "Sub-motions of standing to sitting")
      ->capture_default_str()->check(CLI::Range(3, 1000));
  validate->add_option("--jobs", validate_options->jobs, "FE runs at once (one hip per process)")
      ->capture_default_str()->check(CLI::Range(1, 64));
  validate->add_option("--threads", validate_options->threads, "Threads of the penetration queries")
      ->capture_default_str()->check(CLI::Range(1, 256));
  validate->callback([=] {
    studies::ValidationOptions run = *validate_options;
    run.out_dir = *validate_out;
    run.cache_dir = *validate_cache;
    run.program = std::filesystem::read_symlink("/proc/self/exe");
    if (*validate_quick) {
      // Two hips whose depths differ: the normal hip and the thesis' Fig. 60 hip.
      run.hips = {{20, 40}, {40, 60}};
      run.edge_mm = 3.0;
      run.sub_motions = 6;
      if (validate->count("--fe-level") == 0) run.fe_level = FeLevel::kCoarse;
    }
    // Under mpirun / srun the hips are spread over the ranks, and rank 0 alone reports.
    run.spread = studies::unit_spread_of_this_process();
    const auto result = studies::run_validation_study(run);
    if (!result.wrote_tables) return;
    // A hip that failed is named in one line; the others' tables and report are kept.
    if (result.hips.empty()) studies::throw_if_units_failed("validate", result.failed, 0, "hips", run.out_dir);
    const auto report = studies::write_correlation_report(run.out_dir);
    std::cout << std::fixed << std::setprecision(2) << "validate: " << result.hips.size() << " hips x " << result.steps
              << " steps, FE level " << to_string(result.fe_level) << ", " << std::setprecision(0) << result.seconds
              << " s; mean r (primary measure) " << std::setprecision(2) << report.mean_r_all << " all, "
              << report.mean_r_curvilinear << " curvilinear, " << report.mean_r_radial << " radial over "
              << report.ok_cells << " cells; report: " << report.report.string() << '\n';
    studies::throw_if_units_failed("validate", result.failed, result.hips.size(), "hips", run.out_dir);
  });
}

void add_sensitivity_command(CLI::App* study) {
  auto* sensitivity = study->add_subcommand(
      "sensitivity", "Which hip features decide first contact of cam and rim: each parameter over its published "
                     "range on the pure-cam and pure-pincer hips; writes sensitivity.csv and sensitivity.md");
  auto sensitivity_options = std::make_shared<studies::SensitivityOptions>();
  auto sensitivity_out = std::make_shared<std::string>("out/sensitivity");
  sensitivity->add_option("--out", *sensitivity_out, "Output folder")->capture_default_str();
  sensitivity->add_option("--edge-mm", sensitivity_options->edge_mm, "Surface edge length")->capture_default_str()
      ->check(CLI::Range(0.5, 10.0));
  sensitivity->add_option("--sub-motions", sensitivity_options->sub_motions, "Sub-motions of standing to sitting")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  sensitivity->add_option("--threads", sensitivity_options->threads, "Threads for the queries")->capture_default_str()
      ->check(CLI::Range(1, 256));
  sensitivity->add_option("--parameters", sensitivity_options->only_parameters,
                          "Only these parameters' variants (comma-separated HipParameters keys)")
      ->delimiter(',');
  sensitivity->callback([=] {
    const auto result = studies::run_hip_sensitivity(*sensitivity_options);
    studies::write_sensitivity_report(result, *sensitivity_out);
    std::cout << "hip sensitivity: " << result.rows.size() << " hips in " << std::fixed << std::setprecision(1)
              << result.seconds << " s; report: " << *sensitivity_out << "/sensitivity.md\n";
  });
}

const CommandRegistrar study_registrar("study", [](CLI::App& parent) {
  auto* study = parent.add_subcommand("study", "Run a study: fai (thesis §4.3), validate (penetration vs FE, Tables 8-9), sensitivity (hip geometry)");
  study->require_subcommand(1);
  add_fai_command(study);
  add_study_validate_command(study);
  add_sensitivity_command(study);
});

}  // namespace
}  // namespace hipfai::app
