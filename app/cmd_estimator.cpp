// hipfai estimator: the contact-pressure estimator of thesis §4.5 (train, predict, validate).
#include "app/command_registry.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/literature.h"
#include "studies/estimator_holdout.h"
#include "studies/estimator_holdout_report.h"
#include "studies/estimator_model_file.h"
#include "studies/estimator_refine.h"
#include "studies/estimator_refine_report.h"
#include "studies/estimator_sample.h"
#include "studies/estimator_sample_fe.h"
#include "studies/estimator_sample_run.h"
#include "studies/estimator_sample_report.h"
#include "studies/estimator_study.h"
#include "studies/pipeline/mpi_launch.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace hipfai::app {
namespace {

struct TrainArgs {
  std::vector<std::string> fe;
  std::string hips, base, measure = "pressure_max_mpa";
  int polar_steps = literature::kEstimatorGridPolarSteps, azimuth_steps = literature::kEstimatorGridAzimuthSteps;
  int components = literature::kEstimatorEffectiveFeatures, nearest = literature::kEstimatorNearestSets;
  double scale_floor_mm = literature::kSphericityToleranceMm;
  std::vector<std::string> tissues;
  std::vector<std::string> fe_hip;  // folder, table, folder, table, ...
};

void add_train_options(CLI::App* app, TrainArgs& args, bool fe_required) {
  auto* fe = app->add_option("--fe", args.fe,
                             "FE results: a `hipfai study validate` output folder (steps.csv), a steps.csv, or a "
                             "scripts/fem-sweep output folder; repeat for several sweeps of the same motion");
  if (fe_required) fe->required();
  app->add_option("--hips", args.hips, "Folder of hip model folders (model.json), matched to the FE rows by CE/alpha");
  app->add_option("--fe-hip", args.fe_hip,
                  "A hip of its own and its FE: DIR TABLE, a hip model folder (e.g. `hipfai soft-tissue` on a "
                  "segmented hip) and its `fem run --csv` table (the run's --out HDF5 beside it, same name, .h5); "
                  "repeat for more hips")
      ->expected(2)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app->add_option("--measure", args.measure, "FE quantity to estimate (a steps.csv column ending in _mpa)")
      ->capture_default_str();
  app->add_option("--polar-steps", args.polar_steps, "Feature grid: polar steps (thesis f = 1944 = 4 x 18 x 27)")
      ->capture_default_str()->check(CLI::Range(1, 360));
  app->add_option("--azimuth-steps", args.azimuth_steps, "Feature grid: azimuth steps")->capture_default_str()
      ->check(CLI::Range(1, 720));
  app->add_option("--tissues", args.tissues, "Tissues sampled (default femur_bone,femoral_cartilage,"
                                             "acetabular_cartilage,labrum)")->delimiter(',');
  app->add_option("--components", args.components, "PCA components kept, e (thesis: 10)")->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app->add_option("--nearest", args.nearest, "Eq. 22 DIST1 shortlist (thesis: 4)")->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app->add_option("--scale-floor-mm", args.scale_floor_mm,
                  "Normalisation: features vary less than this are divided by it, not by their deviation")
      ->capture_default_str()->check(CLI::Range(0.0, 100.0));
}

studies::EstimatorTrainOptions train_options(const CLI::App* app, const TrainArgs& args) {
  studies::EstimatorTrainOptions options;
  for (const auto& fe : args.fe) options.fe.emplace_back(fe);
  options.hips = args.hips;
  for (std::size_t k = 0; k + 1 < args.fe_hip.size(); k += 2) options.fe_hips.emplace_back(args.fe_hip[k], args.fe_hip[k + 1]);
  options.base_model = args.base;
  options.measure = args.measure;
  options.grid.polar_steps = args.polar_steps;
  options.grid.azimuth_steps = args.azimuth_steps;
  if (!args.tissues.empty()) options.grid.tissues = args.tissues;
  options.grid_given = app->count("--polar-steps") + app->count("--azimuth-steps") + app->count("--tissues") > 0;
  options.settings.pca.components = args.components;
  options.settings.pca.scale_floor = args.scale_floor_mm;
  options.settings.nearest = args.nearest;
  options.settings.knn_k = args.nearest;
  return options;
}

void print_training(const studies::EstimatorModel& model, const std::string& out,
                    std::chrono::steady_clock::time_point start) {
  double features_ms = 0;
  int extracted = 0;
  for (const auto& hip : model.hips) {
    if (hip.feature_ms > 0) {
      features_ms += hip.feature_ms;
      ++extracted;
    }
  }
  std::cout << std::fixed << std::setprecision(1) << "trained on " << model.hips.size() << " hips x "
            << model.angle_deg.size() << " steps (" << model.measure << "), " << model.grid.num_features()
            << " features (" << model.grid.describe() << "), e = " << model.estimator.pca.num_components()
            << " components (" << std::setprecision(1)
            << 100.0 * model.estimator.pca.variances.sum() / model.estimator.pca.total_variance
            << " % of the variance); features " << (extracted ? features_ms / extracted : 0.0)
            << " ms per hip; total "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s; model: "
            << out << '\n';
}

void add_train_command(CLI::App* estimator) {
  auto* train = estimator->add_subcommand("train", "Train a model file from FE results and their hips");
  auto train_args = std::make_shared<TrainArgs>();
  auto train_out = std::make_shared<std::string>();
  add_train_options(train, *train_args, false);
  train->add_option("--base", train_args->base,
                    "Retrain: start from this model's training hips (same grid, motion and measure) and add --fe")
      ->check(CLI::ExistingFile);
  train->add_option("--out", *train_out, "Model file (HDF5)")->required();
  train->callback([=] {
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::string> notes;
    const auto model = studies::train_estimator_model(train_options(train, *train_args), &notes);
    studies::write_estimator_model(model, *train_out);
    for (const auto& note : notes) std::cout << "note: " << note << '\n';
    print_training(model, *train_out, start);
  });
}

// What `estimator predict` reads from its command line.
struct PredictArgs {
  std::string model_path, hip_dir, csv, method = "pca_nn", e_prime;
};

// e' as asked: all the model keeps, a number, or chosen by leave-one-out ('auto', reported).
int components_used(const studies::EstimatorModel& model, stats::EstimatorMethod method, const std::string& e_prime) {
  if (e_prime == "auto") {
    const stats::EPrimeSelection selection = studies::choose_e_prime(model, method);
    std::cout << "e' = " << selection.e_prime << " chosen by leave-one-out among the " << selection.hips
              << " training hips";
    if (selection.hips == 0) std::cout << " (too few hips with complete values to choose: all components)";
    std::cout << '\n';
    return selection.e_prime;
  }
  return e_prime.empty() ? model.estimator.pca.num_components() : std::stoi(e_prime);
}

void write_prediction_csv(const stats::EstimateResult& result, const std::string& path) {
  std::ostringstream table;
  table << std::setprecision(10) << "step,estimate,low,high,bordering\n";
  for (std::size_t j = 0; j < result.steps.size(); ++j) {
    const auto& s = result.steps[j];
    table << j + 1 << ',' << s.estimate << ',' << s.low << ',' << s.high << ',' << (result.bordering ? 1 : 0) << '\n';
  }
  write_file_atomically(path, table.str());
}

// The first step at which the hip's penetration depths say it impinges, if any.
void print_impingement(const studies::HipPrediction& prediction) {
  int first = -1;
  for (Eigen::Index j = 0; j < prediction.depths.curvilinear_mm.cols() && first < 0; ++j) {
    if (prediction.depths.curvilinear_mm(0, j) > 0.0 || prediction.depths.radial_mm(0, j) > 0.0) {
      first = static_cast<int>(j);
    }
  }
  if (first < 0) {
    std::cout << "impinging: no (no penetration over the motion)\n";
  } else {
    std::cout << "impinging: yes, from step " << first + 1 << " (max curvilinear "
              << prediction.depths.curvilinear_mm.maxCoeff() << " mm, radial "
              << prediction.depths.radial_mm.maxCoeff() << " mm)\n";
  }
}

void print_prediction(const studies::EstimatorModel& model, const studies::HipPrediction& prediction,
                      const PredictArgs& args, int used) {
  const auto& result = prediction.result;
  std::cout << std::fixed << std::setprecision(3) << args.method << " e'=" << used << " estimate of " << model.measure
            << " for " << args.hip_dir << " (MPa):\n step  angle_deg  estimate     low    high\n";
  for (std::size_t j = 0; j < result.steps.size(); ++j) {
    const auto& s = result.steps[j];
    std::cout << std::setw(5) << j + 1 << std::setw(11) << model.angle_deg[j] << std::setw(10) << s.estimate
              << std::setw(8) << s.low << std::setw(8) << s.high << '\n';
  }
  std::cout << (result.bordering ? "BORDERING" : "interior") << ": Mahalanobis distance " << result.mahalanobis
            << " (training max " << model.estimator.max_training_mahalanobis << "), outside the training range on "
            << result.outside_components << " of " << model.estimator.significant_components
            << " significant components" << (result.bordering ? " - the estimate extrapolates" : "") << '\n'
            << (prediction.approximate_frame
                    ? "frame: approximate, from the bones of a segmented hip (no anatomical landmarks)\n"
                    : "")
            << "time: load " << prediction.load_ms << " ms, features " << prediction.feature_ms << " ms, ";
  if (prediction.depths.known()) std::cout << "penetration depths " << prediction.penetration_ms << " ms, ";
  std::cout << "prediction " << prediction.predict_ms << " ms\n";
  if (prediction.depths.known()) print_impingement(prediction);
}

void add_predict_command(CLI::App* estimator) {
  auto* predict = estimator->add_subcommand("predict", "Estimate the FE quantity of a hip at every step of the motion");
  auto args = std::make_shared<PredictArgs>();
  predict->add_option("--model", args->model_path, "Model file from `estimator train`")->required();
  predict->add_option("--hip", args->hip_dir, "Hip model folder (model.json)")->required();
  predict->add_option("--csv", args->csv, "Write step, estimate, low, high, bordering to this file");
  predict->add_option("--method", args->method,
                      "pca_nn (thesis), knn, ridge, depth_nn or depth_aligned (these two also compute the hip's "
                      "penetration depths over the model's standing-to-sitting motion)")
      ->capture_default_str()
      ->check(CLI::IsMember({"pca_nn", "knn", "ridge", "depth_nn", "depth_aligned"}));
  predict->add_option("--e-prime", args->e_prime,
                      "Components used, e' (default: all the model keeps), or 'auto': the e' with the smallest "
                      "leave-one-out error among the training hips")
      ->check(CLI::Range(1, 1000) | CLI::IsMember({"auto"}));
  predict->callback([args] {
    const auto model = studies::read_estimator_model(args->model_path);
    const stats::EstimatorMethod method = stats::parse_estimator_method(args->method);
    const int used = components_used(model, method, args->e_prime);
    const auto prediction = studies::predict_hip(model, args->hip_dir, method, used);
    if (!args->csv.empty()) write_prediction_csv(prediction.result, args->csv);
    print_prediction(model, prediction, *args, used);
  });
}

void print_validation(const studies::EstimatorValidateSummary& summary, int max_e_prime) {
  std::cout << std::fixed << std::setprecision(2);
  for (int c = 0; c < 2; ++c) {
    std::cout << "case " << c + 1 << " (" << summary.hips[c] << " hips, " << summary.bordering[c]
              << " flagged bordering, " << summary.impinging[c] << " impinging), e'=" << max_e_prime
              << " mean |error| %:";
    for (int m = 0; m < stats::kNumEstimatorMethods; ++m) {
      if (!std::isfinite(summary.mean_error[c][m])) continue;  // depth_nn without depths
      std::cout << ' ' << stats::to_string(stats::kEstimatorMethods[m]) << ' ' << summary.mean_error[c][m]
                << " (interior " << summary.interior_error[c][m] << ')';
    }
    std::cout << "; pca_nn_cv (e' chosen without the target) " << summary.chosen_e_prime_error[c] << " (interior "
              << summary.chosen_e_prime_interior_error[c] << ")\n";
  }
  std::cout << "thesis: case 1 5.14 (interior 1.62); report: " << summary.report.string() << '\n';
}

void add_estimator_validate_command(CLI::App* estimator) {
  auto* validate = estimator->add_subcommand(
      "validate", "Leave-one-out over all hips, e' = 1..10, cases 1-2 (thesis Tables 12-13, Figs. 72-74) with "
                  "baselines; writes loo.csv, estimates.csv, report.md, model.h5");
  auto validate_args = std::make_shared<TrainArgs>();
  auto validate_out = std::make_shared<std::string>("out/estimator");
  auto quick = std::make_shared<bool>(false);
  auto cache = std::make_shared<std::string>("cache");
  add_train_options(validate, *validate_args, false);
  validate->add_option("--out", *validate_out, "Output folder")->capture_default_str();
  validate->add_flag("--quick", *quick,
                     "From nothing: 5 hips at 3 mm edges, 6 steps, FE coarse (study validate), then validate");
  validate->add_option("--cache", *cache, "Cache of --quick's hips and FE runs")->capture_default_str();
  validate->callback([=] {
    studies::EstimatorValidateOptions options;
    options.train = train_options(validate, *validate_args);
    options.out_dir = *validate_out;
    if (*quick) {
      options.quick_cache = *cache;
      options.quick_program = std::filesystem::read_symlink("/proc/self/exe");
    } else if (options.train.fe.empty() || options.train.hips.empty()) {
      throw_error("estimator validate: --fe and --hips are required (or --quick)");
    }
    // Under mpirun / srun the --quick FE's hips and the folds are spread over the ranks; rank 0 reports.
    options.spread = studies::unit_spread_of_this_process();
    const auto summary = studies::validate_estimator(options);
    if (summary.wrote_report) print_validation(summary, options.max_e_prime);
  });
}

// What `estimator sample` reads from its command line (names parsed into enums in the callback).
struct SampleArgs {
  int n = 0, held_out = 0;
  std::uint64_t seed = 1;
  std::string design = "lhs", out;
  std::vector<std::string> vary{"ce", "alpha"};
  double edge_mm = 2.0;
  std::string fe_level, cache = "cache";
  int steps = 30, jobs = 2, threads = 2;
};

void add_sample_command(CLI::App* estimator) {
  auto* sample = estimator->add_subcommand(
      "sample", "Training and held-out hips spread over the parameter space by a space-filling design, generated "
                "one folder per hip, with design.csv; a re-run makes only the missing hips");
  auto args = std::make_shared<SampleArgs>();
  sample->add_option("--n", args->n, "Training hips")->required();
  sample->add_option("--out", args->out, "Output folder (design.csv and one folder per hip)")->required();
  sample->add_option("--seed", args->seed, "Seed of the design (same seed, same hips)")->capture_default_str();
  sample->add_option("--design", args->design,
                     "lhs (maximin Latin hypercube) or sobol (digitally shifted Sobol sequence)")
      ->capture_default_str();
  sample->add_option("--vary", args->vary,
                     "Parameters varied, comma-separated: ce (0-45 deg), alpha (40-80), neck_shaft_angle (110-146.2), "
                     "femoral_anteversion (-10-40); the others keep the generator's defaults")
      ->delimiter(',')
      ->capture_default_str();
  sample->add_option("--held-out", args->held_out,
                     "Held-out hips, drawn the same way from another stream of the seed (never a training hip)")
      ->capture_default_str();
  sample->add_option("--edge-mm", args->edge_mm, "Surface edge of the generated hips, mm")
      ->check(CLI::Range(0.2, 10.0))
      ->capture_default_str();
  sample->add_option("--fe-level", args->fe_level,
                     "Also the ground truth: each hip's penetration depths and FE at this level (coarse, default, fine), "
                     "into steps.csv (training hips), held_out_steps.csv and timings.csv")
      ->check(CLI::IsMember({"coarse", "default", "fine"}));
  sample->add_option("--cache", args->cache, "FE cache folder (with --fe-level)")->capture_default_str();
  sample->add_option("--steps", args->steps, "Sub-motions of standing to sitting (with --fe-level)")
      ->check(CLI::Range(3, 1000))
      ->capture_default_str();
  sample->add_option("--jobs", args->jobs, "FE runs at once, one hip per process (with --fe-level)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  sample->add_option("--threads", args->threads, "Threads of the penetration queries (with --fe-level)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  sample->callback([args] {
    studies::SampleOptions options;
    options.n = args->n;
    options.held_out = args->held_out;
    options.seed = args->seed;
    options.design = stats::parse_sampling_design(args->design);
    options.vary.clear();
    for (const auto& name : args->vary) options.vary.push_back(studies::parse_sampled_parameter(name));
    options.edge_mm = args->edge_mm;
    const studies::SamplePlan plan = studies::plan_sample(options);
    std::optional<studies::SampleFeOptions> fe;
    if (!args->fe_level.empty()) {
      fe.emplace();
      fe->sample_dir = args->out;
      fe->cache_dir = args->cache;
      fe->level = parse_fe_level(args->fe_level, "--fe-level");
      fe->steps = args->steps;
      fe->jobs = args->jobs;
      fe->threads = args->threads;
      fe->program = std::filesystem::read_symlink("/proc/self/exe");
    }
    // Under mpirun / srun the hips (generation, depths and FE) are spread over the ranks; rank 0 reports.
    const studies::EstimatorSampleRun run = studies::run_estimator_sample(
        plan, args->out, fe, studies::unit_spread_of_this_process(), [](const std::string& line, bool failed) {
          (failed ? std::cerr : std::cout) << line << std::endl;
        });
    if (!run.holds_results) return;
    const std::vector<studies::SampleHipOutcome>& outcomes = run.outcomes;
    std::cout << studies::sample_summary(plan, outcomes, args->out) << '\n';
    if (run.fe) {
      studies::write_sample_fe_tables(plan, *run.fe, fe->level, args->out);
      std::cout << studies::sample_fe_summary(plan, *run.fe, args->out) << '\n';
      for (const auto& hip : run.fe->hips) {
        if (!hip.error.empty()) std::cerr << "estimator sample: " << plan.hips[hip.plan_index].name << ": " << hip.error << '\n';
      }
    }
    const auto failed = std::count_if(outcomes.begin(), outcomes.end(), [](const auto& outcome) {
      return outcome.status == studies::SampleHipOutcome::Status::kFailed;
    });
    if (failed > 0) throw_error("estimator sample: ", failed, " of ", outcomes.size(), " hips failed (named above)");
  });
}

// What `estimator holdout` reads from its command line (names parsed into enums in the callback).
struct HoldoutArgs {
  studies::HoldoutOptions options;
  std::string out, refine_method = "depth_nn";
  std::vector<std::string> criteria{"width", "disagreement"};
};

void add_holdout_command(CLI::App* estimator) {
  auto* holdout = estimator->add_subcommand(
      "holdout", "Train on an `estimator sample`'s training hips and test on its held-out hips: error vs training-set "
                 "size, calibrated intervals, the flag, refinement vs random sampling (report.md and CSVs)");
  auto args = std::make_shared<HoldoutArgs>();
  studies::HoldoutOptions& o = args->options;
  holdout->add_option("--sample", o.sample_dir, "Folder of `estimator sample ... --fe-level L` (steps.csv, held_out_steps.csv)")
      ->required();
  holdout->add_option("--out", args->out, "Output folder")->required();
  holdout->add_option("--sizes", o.sizes, "Training-set sizes: the first k training hips of the design")
      ->delimiter(',')
      ->capture_default_str();
  holdout->add_option("--nominal", o.nominal, "Nominal coverage of the calibrated intervals")
      ->check(CLI::Range(0.5, 0.999))
      ->capture_default_str();
  holdout->add_option("--refine-start", o.refine_start, "Refinement: the first k training hips to start from")
      ->capture_default_str();
  holdout->add_option("--refine-budget", o.refine_budget, "Refinement: hips added per round")->capture_default_str();
  holdout->add_option("--refine-rounds", o.refine_rounds, "Refinement: rounds (0: none)")->capture_default_str();
  holdout->add_option("--criteria", args->criteria, "Refinement: uncertainty criteria (width, disagreement)")
      ->delimiter(',')
      ->capture_default_str();
  holdout->add_option("--refine-method", args->refine_method, "Refinement: the method whose interval `width` reads")
      ->capture_default_str();
  holdout->add_option("--random-repeats", o.random_repeats, "Refinement: random draws at the same budget")
      ->capture_default_str();
  holdout->add_option("--seed", o.seed, "Seed of the random draws")->capture_default_str();
  holdout->add_option("--measure", o.measure, "FE measure (a _mpa column of the tables)")->capture_default_str();
  holdout->callback([args] {
    studies::HoldoutOptions options = args->options;
    options.criteria.clear();
    for (const auto& name : args->criteria) options.criteria.push_back(stats::parse_uncertainty_criterion(name));
    options.refine_method = stats::parse_estimator_method(args->refine_method);
    const studies::HoldoutResult result = studies::run_estimator_holdout(options);
    studies::write_holdout_report(result, options, args->out);
    std::cout << studies::holdout_summary(result, args->out) << '\n';
  });
}

void add_refine_command(CLI::App* estimator) {
  auto* refine = estimator->add_subcommand(
      "refine", "Pick the candidate hips whose predictions are least certain (the next hips to run the FE on and "
                "train with `train --base`)");
  auto model_path = std::make_shared<std::string>();
  auto candidates = std::make_shared<std::string>();
  auto criterion = std::make_shared<std::string>("width");
  auto method = std::make_shared<std::string>("pca_nn");
  auto csv = std::make_shared<std::string>();
  auto budget = std::make_shared<int>(1);
  refine->add_option("--model", *model_path, "Model file from `estimator train`")->required();
  refine->add_option("--candidates", *candidates,
                     "Folder of candidate hip folders (model.json), e.g. an `estimator sample` output")
      ->required();
  refine->add_option("--budget", *budget, "Hips to pick")->capture_default_str();
  refine->add_option("--criterion", *criterion,
                     "width (mean interval width of --method) or disagreement (mean range of the methods' estimates)")
      ->capture_default_str();
  refine->add_option("--method", *method, "Method whose interval `width` reads: pca_nn, knn, ridge, depth_nn, depth_aligned")
      ->capture_default_str();
  refine->add_option("--csv", *csv, "Write hip, score, rank (0 = not picked) of every candidate to this file");
  struct LoopArgs {
    std::string fe_level, cache = "cache", held_out, out;
    int rounds = 1, jobs = 2;
  };
  auto loop = std::make_shared<LoopArgs>();
  refine->add_option("--fe-level", loop->fe_level,
                     "Run the loop: each round pick --budget hips, run their FE at this level, retrain (needs --out)")
      ->check(CLI::IsMember({"coarse", "default", "fine"}));
  refine->add_option("--rounds", loop->rounds, "Rounds of the loop")->check(CLI::Range(1, 1000))->capture_default_str();
  refine->add_option("--cache", loop->cache, "FE cache folder of the loop")->capture_default_str();
  refine->add_option("--jobs", loop->jobs, "FE runs at once in the loop")->check(CLI::Range(1, 64))->capture_default_str();
  refine->add_option("--held-out", loop->held_out,
                     "An `estimator sample --fe-level` folder: its held-out hips measure the model after each round "
                     "(and are never picked)");
  refine->add_option("--out", loop->out, "Loop output folder: model.h5 (the retrained model) and rounds.csv");
  refine->callback([=] {
    studies::RefineOptions options;
    options.candidates = *candidates;
    options.budget = *budget;
    options.criterion = stats::parse_uncertainty_criterion(*criterion);
    options.method = stats::parse_estimator_method(*method);
    if (options.budget < 1) throw_error("estimator refine: --budget ", options.budget, " must be at least 1");
    auto model = studies::read_estimator_model(*model_path);
    if (loop->fe_level.empty()) {
      const auto result = studies::pick_refine_candidates(model, options);
      if (!csv->empty()) write_file_atomically(*csv, studies::refine_csv(result));
      std::cout << studies::refine_summary(result, options);
      return;
    }
    if (loop->out.empty()) throw_error("estimator refine: --fe-level runs the loop and needs --out");
    studies::RefineLoopOptions run;
    run.pick = options;
    run.rounds = loop->rounds;
    run.fe.level = parse_fe_level(loop->fe_level, "--fe-level");
    run.fe.cache_dir = loop->cache;
    run.fe.jobs = loop->jobs;
    run.fe.program = std::filesystem::read_symlink("/proc/self/exe");
    run.held_out = loop->held_out;
    const studies::RefineLoopResult result = studies::refine_estimator(std::move(model), run);
    std::filesystem::create_directories(loop->out);
    studies::write_estimator_model(result.model, std::filesystem::path(loop->out) / "model.h5");
    write_file_atomically(std::filesystem::path(loop->out) / "rounds.csv", studies::refine_rounds_csv(result));
    std::cout << studies::refine_rounds_summary(result) << "model: " << (std::filesystem::path(loop->out) / "model.h5").string()
              << '\n';
  });
}

const CommandRegistrar estimator_registrar("estimator", [](CLI::App& parent) {
  auto* estimator = parent.add_subcommand(
      "estimator", "Contact-pressure estimator of thesis §4.5 (PCA nearest neighbour): train, predict, validate, sample, refine");
  estimator->require_subcommand(1);
  add_train_command(estimator);
  add_predict_command(estimator);
  add_estimator_validate_command(estimator);
  add_sample_command(estimator);
  add_refine_command(estimator);
  add_holdout_command(estimator);
});

}  // namespace
}  // namespace hipfai::app
