// hipfai fem verify [--case NAME] [--csv FILE]: runs the FE contact model's verification cases
// (closed-form references) and prints inputs, computed values, closed forms and relative errors.
// Runs under mpirun as well; rank 0 prints and writes the CSV.
// hipfai fem shells [--motion CSV] [--steps N] --out FILE.h5: the femur motion (rotation about
// the HJC, free translation under the joint force) on concentric cartilage shells, a spherical
// joint, with per-step HDF5 results: the motion machinery end to end until the hip volume
// meshes are ready.
#ifdef HIPFAI_WITH_FEM

#include "app/command_registry.h"
#include "core/error.h"
#include "core/progress.h"
#include "fem/fem_results.h"
#include "fem/motion_solver.h"
#include "fem/verification_cases.h"
#include "studies/motion.h"

#include <mpi.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
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

  std::unique_ptr<std::ofstream> csv;
  if (!options.csv_file.empty() && rank == 0) {
    csv = std::make_unique<std::ofstream>(options.csv_file);
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
                name.c_str(), fem::to_string(s.status), s.n_cells, s.n_dofs, options.degree,
                s.n_ranks, s.active_set_iterations, s.linear_solves, s.linear_iterations,
                s.max_penetration_mm, s.wall_time_s);
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
             << (q.passed() ? 1 : 0) << ',' << fem::to_string(s.status) << ',' << s.n_cells
             << ',' << s.n_dofs << ',' << s.n_ranks << ',' << s.active_set_iterations << ','
             << s.linear_solves << ',' << s.linear_iterations << ',' << s.max_penetration_mm
             << ',' << s.wall_time_s << '\n';
      }
    }
    std::fflush(stdout);
  }
  if (!failed.empty()) {
    std::string list;
    for (const auto& name : failed) list += (list.empty() ? "" : ", ") + name;
    throw_error("fem verify: case(s) outside tolerance: ", list);
  }
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
  std::vector<fem::MotionStep> steps;
  for (const studies::MotionStep& step : motion.steps) {
    fem::MotionStep out;
    for (unsigned i = 0; i < 3; ++i) {
      for (unsigned j = 0; j < 3; ++j) out.rotation[i][j] = step.rotation(i, j);
      if (step.force_N) out.force_n[i] = (*step.force_N)[i];
    }
    steps.push_back(out);
  }
  fem::ContactProblem problem(MPI_COMM_WORLD, [] {
    fem::ContactOptions solver;
    solver.mapping_degree = 4;  // r = 25 mm faceting would otherwise rival the 0.02 mm load
    return solver;
  }());
  std::unique_ptr<fem::FemResultsWriter> writer;
  if (rank == 0) writer = std::make_unique<fem::FemResultsWriter>(
      options.out_file, std::vector<std::string>{"femoral cartilage", "acetabular cartilage"}, 0);
  fem::build_concentric_shells(problem, options.expansion_mm);
  ProgressBar progress("fem shells", steps.size(), rank == 0);
  fem::MotionOptions motion_options;
  motion_options.moving_body = 0;
  const auto results = fem::run_motion(problem, steps, motion_options,
                                       [&](std::size_t k, const fem::ContactResult& result) {
                                         if (writer) writer->append(steps[k], result);
                                         progress.advance();
                                       });
  progress.finish();
  std::size_t failed = 0;
  for (const auto& result : results) failed += result.status != fem::ContactStatus::kConverged;
  if (rank == 0) {
    std::printf("fem shells: %zu steps, %zu not converged, results in %s\n", results.size(), failed,
                options.out_file.c_str());
  }
  if (failed > 0) throw_error("fem shells: ", failed, " step(s) did not converge (see ", options.out_file, ")");
}

const CommandRegistrar registrar{"fem", [](CLI::App& parent) {
  auto* fem_command = parent.add_subcommand("fem", "Finite-element contact model (deal.II/PETSc)");
  fem_command->require_subcommand(1);
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
}};

}  // namespace
}  // namespace hipfai::app

#endif  // HIPFAI_WITH_FEM
