// hipfai fem verify [--case NAME] [--csv FILE]: runs the FE contact model's verification cases
// (closed-form references) and prints inputs, computed values, closed forms and relative errors.
// Runs under mpirun as well; rank 0 prints and writes the CSV.
// hipfai fem shells [--motion CSV] [--steps N] --out FILE.h5: the femur motion (rotation about
// the HJC, free translation under the joint force) on concentric cartilage shells, a spherical
// joint, with per-step HDF5 results: the motion machinery end to end until the hip volume
// meshes are ready.
// hipfai fem run --model DIR [--motion CSV] [--steps N] [--level coarse|default|fine]
// [--body-weight-n W] [--peak-radius-mm R] [--labrum-refinement N] --out FILE.h5 [--verbose]: the hip FE model (fem/hip_fe_model.h) of a model
// directory through a motion, per-step HDF5 (fem/fem_results.h). A sub-command `run` because
// `fem` itself has sub-commands.
#ifdef HIPFAI_WITH_FEM

#include "app/cli_util.h"
#include "app/command_registry.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "fem/fem_results.h"
#include "fem/hip_fe_model.h"
#include "fem/motion_solver.h"
#include "fem/verification_cases.h"
#include "geometry/hip_volume_mesh.h"
#include "studies/fem_levels_report.h"
#include "studies/fem_levels_study.h"
#include "studies/pipeline/hip_fe_run.h"
#include "studies/pipeline/motion.h"

#include <mpi.h>

#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hipfai::app {
namespace {

struct FemVerifyOptions {
  std::vector<std::string> cases;
  std::string csv_file;
  std::string vtu_prefix;
  int refinement = 0;
  unsigned int degree = 2;
  bool verbose = false;
};

void run_fem_verify(const FemVerifyOptions& options) {
  fem::ensure_mpi_initialized();
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const std::vector<std::string> cases =
      options.cases.empty() ? fem::verification_case_names() : options.cases;

  std::optional<AtomicFile> csv_file;  // committed once every case has run
  std::unique_ptr<std::ofstream> csv;
  if (!options.csv_file.empty() && rank == 0) {
    csv_file.emplace(options.csv_file);
    csv = std::make_unique<std::ofstream>(csv_file->partial_path());
    if (!*csv) throw_error(options.csv_file, ": cannot open for writing (--csv)");
    *csv << "case,quantity,unit,computed,closed_form,relative_error,tolerance,passed,status,"
            "cells,dofs,ranks,active_set_iterations,linear_solves,cg_iterations,"
            "max_penetration_mm,wall_time_s\n";
  }
  std::vector<std::string> failed;
  for (const std::string& name : cases) {
    fem::VerificationOptions case_options;
    case_options.refinement = options.refinement;
    case_options.fe_degree = options.degree;
    case_options.verbose = options.verbose;
    if (!options.vtu_prefix.empty()) case_options.vtu_file = options.vtu_prefix + name + ".vtu";
    const fem::VerificationResult result =
        fem::run_verification_case(name, case_options, MPI_COMM_WORLD);
    if (!result.passed()) failed.push_back(name);
    if (rank != 0) continue;
    const fem::ContactResult& s = result.solve;
    std::printf("== %s (%s): %u cells, %lu dofs, Q%u, %u rank(s), %u active-set iterations, "
                "%u linear solves, %u CG iterations, max penetration %.3g mm, %.2f s\n",
                name.c_str(), fem::to_string(s.status), s.statistics.n_cells, s.statistics.n_dofs, options.degree,
                s.statistics.n_ranks, s.statistics.active_set_iterations, s.statistics.linear_solves, s.statistics.linear_iterations,
                s.peaks.max_penetration_mm, s.statistics.wall_time_s);
    std::printf("   inputs:");
    for (const auto& [key, value] : result.inputs) std::printf(" %s=%.6g", key.c_str(), value);
    std::printf("\n");
    for (const fem::VerificationQuantity& q : result.quantities) {
      std::printf("   %-34s %-4s computed %-14.9g closed form %-14.9g rel. error %.2e (tol %.0e) %s\n",
                  q.name.c_str(), q.unit.c_str(), q.computed, q.closed_form, q.relative_error(),
                  q.tolerance, q.passed() ? "ok" : "FAIL");
      if (csv) {
        *csv << name << ',' << q.name << ',' << q.unit << ',' << q.computed << ','
             << q.closed_form << ',' << q.relative_error() << ',' << q.tolerance << ','
             << (q.passed() ? 1 : 0) << ',' << fem::to_string(s.status) << ',' << s.statistics.n_cells
             << ',' << s.statistics.n_dofs << ',' << s.statistics.n_ranks << ',' << s.statistics.active_set_iterations << ','
             << s.statistics.linear_solves << ',' << s.statistics.linear_iterations << ',' << s.peaks.max_penetration_mm
             << ',' << s.statistics.wall_time_s << '\n';
      }
    }
    std::fflush(stdout);
  }
  if (csv) {
    csv->close();
    if (!*csv) throw_error(options.csv_file, ": write failed (--csv)");
    csv_file->commit();  // before the verdict: the table of a failed case is what one looks at
  }
  if (!failed.empty()) {
    std::string list;
    for (const auto& name : failed) list += (list.empty() ? "" : ", ") + name;
    throw_error("fem verify: case(s) outside tolerance: ", list);
  }
}

// Rotation and joint force per step; steps without a force (standing-to-sitting, a CSV without
// force columns) get `default_force_n`.
std::vector<fem::MotionStep> to_fem_steps(const studies::Motion& motion,
                                          const Eigen::Vector3d& default_force_n) {
  std::vector<fem::MotionStep> steps;
  for (const studies::MotionStep& step : motion.steps) {
    steps.push_back(fem::make_hip_motion_step(step.rotation, step.force_N.value_or(default_force_n)));
  }
  return steps;
}

// The motion with a progress bar, each step appended to `writer` (rank 0 only; null elsewhere).
std::vector<fem::ContactResult> run_motion_with_progress(const std::string& label,
                                                         fem::ContactProblem& problem,
                                                         const std::vector<fem::MotionStep>& steps,
                                                         const fem::MotionOptions& motion_options,
                                                         fem::FemResultsWriter* writer, bool show) {
  ProgressBar progress(label, steps.size(), show);
  auto results = fem::run_motion(problem, steps, motion_options,
                                 [&](std::size_t k, const fem::ContactResult& result) {
                                   if (writer) writer->append(steps[k], result);
                                   progress.advance();
                                 });
  progress.finish();
  return results;
}

struct FemShellsOptions {
  std::string motion_file;
  int steps = 30;
  std::string out_file;
  double expansion_mm = 0.02;
};

void run_fem_shells(const FemShellsOptions& options) {
  fem::ensure_mpi_initialized();
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  // Motion: the CSV (step, flexion_deg, adduction_deg, internal_rotation_deg, Fx_N, Fy_N, Fz_N)
  // or the thesis's standing-to-sitting (no forces: the joint force is then zero).
  const studies::Motion motion = options.motion_file.empty()
                                     ? studies::standing_to_sitting(options.steps)
                                     : studies::read_motion_csv(options.motion_file);
  const std::vector<fem::MotionStep> steps = to_fem_steps(motion, Eigen::Vector3d::Zero());
  fem::ContactProblem problem(MPI_COMM_WORLD, [] {
    fem::ContactOptions solver;
    solver.mapping_degree = 4;  // r = 25 mm faceting would otherwise rival the 0.02 mm load
    return solver;
  }());
  std::unique_ptr<fem::FemResultsWriter> writer;
  if (rank == 0) writer = std::make_unique<fem::FemResultsWriter>(
      options.out_file, std::vector<std::string>{"femoral cartilage", "acetabular cartilage"}, 0);
  fem::build_concentric_shells(problem, options.expansion_mm);
  const auto results =
      run_motion_with_progress("fem shells", problem, steps, fem::MotionOptions{}, writer.get(), rank == 0);
  std::size_t failed = 0;
  for (const auto& result : results) failed += result.status != fem::ContactStatus::kConverged;
  if (rank == 0) {
    std::printf("fem shells: %zu steps, %zu not converged, results in %s\n", results.size(), failed,
                options.out_file.c_str());
  }
  if (failed > 0) throw_error("fem shells: ", failed, " step(s) did not converge (see ", options.out_file, ")");
}

using FemRunOptions = studies::HipFeRunOptions;
using FemRunSummary = studies::HipFeRunSummary;

FemRunSummary run_fem_hip(const FemRunOptions& options, bool throw_on_failure = true) {
  return studies::run_hip_fe(options, throw_on_failure);
}
// A length in mm that must be finite and > 0 (CLI::PositiveNumber lets "inf" through).
const CLI::Validator kFiniteLengthMm(
    [](std::string& input) -> std::string {
      char* end = nullptr;
      const double value = std::strtod(input.c_str(), &end);
      if (input.empty() || *end != '\0' || !std::isfinite(value) || value <= 0.0) {
        return "must be a finite length > 0 (mm), got '" + input + "'";
      }
      return {};
    },
    "MM > 0");

void add_verify_command(CLI::App* fem_command) {
  auto options = std::make_shared<FemVerifyOptions>();
  auto* verify = fem_command->add_subcommand(
      "verify", "Run verification cases against closed-form solutions");
  verify->add_option("--case", options->cases, "Case(s) to run (default: all)")
      ->check(CLI::IsMember(fem::verification_case_names()));
  verify->add_option("--csv", options->csv_file, "Write one row per compared quantity");
  verify->add_option("--vtu-prefix", options->vtu_prefix,
                     "Write the displacement field of each case to <prefix><case>.vtu");
  verify->add_option("--refine", options->refinement, "Extra mesh refinement levels")
      ->check(CLI::Range(0, 3));
  verify->add_option("--degree", options->degree, "Polynomial degree of the elements")
      ->check(CLI::Range(1, 3));
  verify->add_flag("--verbose", options->verbose, "Print active-set iterations");
  verify->callback([options] { run_fem_verify(*options); });
}

void add_shells_command(CLI::App* fem_command) {
  auto shells_options = std::make_shared<FemShellsOptions>();
  auto* shells = fem_command->add_subcommand(
      "shells", "Femur motion on concentric cartilage shells (spherical joint), HDF5 per step");
  shells->add_option("--motion", shells_options->motion_file,
                     "Motion CSV: step,flexion_deg,adduction_deg,internal_rotation_deg,Fx_N,Fy_N,Fz_N")
      ->check(CLI::ExistingFile);
  shells->add_option("--steps", shells_options->steps,
                     "Sub-motions of standing-to-sitting (without --motion)")
      ->check(CLI::Range(1, 1000));
  shells->add_option("--expansion-mm", shells_options->expansion_mm,
                     "Radial expansion of the femoral shell (preload)")
      ->check(CLI::Range(0.0, 0.5));
  shells->add_option("--out", shells_options->out_file, "HDF5 results file")->required();
  shells->callback([shells_options] { run_fem_shells(*shells_options); });
}

void add_run_command(CLI::App* fem_command) {
  auto run_options = std::make_shared<FemRunOptions>();
  auto* run = fem_command->add_subcommand(
      "run", "Hip FE model of a model directory through a motion (standing-to-sitting by default)");
  run->add_option("--model", run_options->model_dir, "Hip model directory (model.json)")
      ->required()
      ->check(CLI::ExistingDirectory);
  run->add_option("--motion", run_options->motion_file,
                  "Motion CSV: step,flexion_deg,adduction_deg,internal_rotation_deg[,Fx_N,Fy_N,Fz_N]")
      ->check(CLI::ExistingFile);
  run->add_option("--steps", run_options->steps, "Sub-motions of standing-to-sitting (without --motion)")
      ->check(CLI::Range(1, 1000));
  add_enum_option(run, "--level", run_options->level, kFeLevels, "Mesh level (coarse, default, fine)");
  run->add_option("--body-weight-n", run_options->body_weight_n,
                  "Body weight (N) scaling the joint force when the motion has none")
      ->check(CLI::Range(1.0, 5000.0));
  run->add_option("--labrum-refinement", run_options->labrum_refinement,
                  "Mesh the labrum N times finer than the level (edge / N, layers * N)")
      ->capture_default_str()
      ->check(CLI::Range(1, 4));
  run->add_option("--peak-radius-mm", run_options->peak_radius_mm,
                  "Ball radius (mm) of the ball-averaged peak von Mises and pressure")
      ->capture_default_str()
      ->check(kFiniteLengthMm);
  run->add_option("--out", run_options->out_file, "HDF5 results file")->required();
  run->add_option("--csv", run_options->csv_file, "Also write one summary row per step (CSV)");
  add_enum_option(run, "--solver", run_options->solver, kFeSolvers,
                  "Solver: substructured (each body factorised once, contact condensed; default), "
                  "direct (MUMPS on the whole system: the monolithic reference) or cg (CG + GAMG)");
  auto* vtu_prefix = run->add_option("--vtu-prefix", run_options->vtu_prefix,
                                     "Fields to <prefix>_<step>.vtu and <prefix>.pvd (ParaView)");
  run->add_option("--vtu-every", run_options->vtu_every, "Write VTU every N steps (and the last)")
      ->check(CLI::Range(0, 1000))
      ->needs(vtu_prefix);
  run->add_option("--threads", run_options->threads,
                  "Threads of the FE stages (0: every hardware thread; under mpirun rank 0 takes them, "
                  "the other ranks solve compliance columns on one each); the results do not depend on it")
      ->capture_default_str()
      ->check(CLI::Range(0, 256));
  add_enum_option(run, "--team-columns", run_options->team_columns, fem::kTeamColumns,
                  "Under mpirun: which ranks solve compliance columns: spare-cores (rank 0, and another "
                  "rank while it has a core no thread of rank 0 uses and its share ends sooner; default) "
                  "or every-rank (every set shared evenly); the results do not depend on it");
  run->add_flag_callback("--no-search-ahead", [run_options] { run_options->search_ahead = false; },
                "Search each step's contact when it starts, not while the steps before are solved "
                "(the same results, more wall time)");
  run->add_flag("--verbose", run_options->verbose, "Print active-set iterations");
  run->callback([run_options] { run_fem_hip(*run_options); });
}

void add_levels_command(CLI::App* fem_command) {
  auto levels_options = std::make_shared<studies::FemLevelsOptions>();
  auto* levels = fem_command->add_subcommand(
      "levels", "The hip FE model at each mesh level: accuracy vs the finest level and time (table + plots)");
  levels->add_option("--model", levels_options->run.model_dir, "Hip model directory (model.json)")
      ->required()
      ->check(CLI::ExistingDirectory);
  levels->add_option("--motion", levels_options->run.motion_file,
                     "Motion CSV: step,flexion_deg,adduction_deg,internal_rotation_deg[,Fx_N,Fy_N,Fz_N]")
      ->check(CLI::ExistingFile);
  levels->add_option("--steps", levels_options->run.steps, "Sub-motions of standing-to-sitting (without --motion)")
      ->check(CLI::Range(1, 1000));
  auto level_names = std::make_shared<std::vector<std::string>>(fe_level_names());
  levels->add_option("--levels", *level_names, "Levels to run (the finest is the reference)")
      ->delimiter(',')
      ->check(CLI::IsMember(fe_level_names()));
  levels->add_option("--body-weight-n", levels_options->run.body_weight_n,
                     "Body weight (N) scaling the joint force when the motion has none")
      ->check(CLI::Range(1.0, 5000.0));
  levels->add_option("--labrum-refinement", levels_options->run.labrum_refinement,
                     "Mesh the labrum N times finer than the level (edge / N, layers * N)")
      ->capture_default_str()
      ->check(CLI::Range(1, 4));
  levels->add_option("--peak-radius-mm", levels_options->run.peak_radius_mm,
                     "Ball radius (mm) of the ball-averaged peak von Mises and pressure")
      ->capture_default_str()
      ->check(kFiniteLengthMm);
  add_enum_option(levels, "--solver", levels_options->run.solver, kFeSolvers,
                  "Solver of every level: substructured (default), direct (the monolithic reference) or cg");
  levels->add_option("--out", levels_options->out_dir,
                     "Output directory: levels.md, levels.csv, levels_*.svg, <level>.h5/.csv")
      ->required();
  levels->callback([levels_options, level_names] {
    levels_options->levels.clear();
    for (const std::string& name : *level_names) levels_options->levels.push_back(parse_fe_level(name, "fem levels"));
    if (levels_options->levels.size() < 2) throw_error("fem levels: --levels needs at least two levels");
    const studies::FemLevelsResult result = studies::compute_fem_levels(*levels_options);
    studies::write_fem_levels_report(result, *levels_options);
  });
}

const CommandRegistrar fem_registrar{"fem", [](CLI::App& parent) {
  auto* fem_command = parent.add_subcommand("fem", "Finite-element contact model (deal.II/PETSc)");
  fem_command->require_subcommand(1);
  add_verify_command(fem_command);
  add_shells_command(fem_command);
  add_run_command(fem_command);
  add_levels_command(fem_command);
}};

}  // namespace
}  // namespace hipfai::app

#endif  // HIPFAI_WITH_FEM
