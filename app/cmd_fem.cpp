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

#include "app/command_registry.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "fem/fem_results.h"
#include "fem/hip_fe_model.h"
#include "fem/motion_solver.h"
#include "fem/verification_cases.h"
#include "geometry/hip_model.h"
#include "geometry/hip_volume_mesh.h"
#include "studies/hip_fe_run.h"
#include "studies/motion.h"
#include "studies/svg_plot.h"

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
#include <thread>
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
// hipfai fem levels: the same model and motion at each mesh level; what accuracy costs in time.
struct FemLevelsOptions {
  FemRunOptions run;  // model, motion, steps, body weight, solver
  std::vector<std::string> levels = {"coarse", "default", "fine"};
  std::string out_dir;
};

struct LevelRow {
  std::string level;
  FemRunSummary summary;
  double peak_pressure = 0.0, wall_per_step = 0.0;
  std::vector<double> peak_vm, peak_p95;  // per body, max over the steps
  // Ball-averaged peaks (fem/peak_measures.h), max over the steps; where the pressure peaks sit
  // (at the step of each maximum).
  double ball_peak_pressure = 0.0;
  std::vector<double> ball_peak_vm;  // per body
  dealii::Point<3> max_pressure_position, ball_peak_pressure_position;
  std::string max_pressure_surface = "none", ball_peak_pressure_surface = "none";
  // Integral quantities at the last step (the peak load of standing-to-sitting).
  double last_mean_pressure = 0.0, last_area = 0.0, last_translation = 0.0;
};

double relative_difference_percent(double value, double reference) {
  return reference != 0.0 ? 100.0 * (value - reference) / reference : 0.0;
}

void run_fem_levels(const FemLevelsOptions& options) {
  fem::ensure_mpi_initialized();
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  // Levels in the order of refinement; the finest one is the reference.
  std::vector<std::string> levels;
  for (const std::string& name : fem::hip_fe_level_names()) {
    if (std::find(options.levels.begin(), options.levels.end(), name) != options.levels.end()) levels.push_back(name);
  }
  // A model directory that cannot be read fails here, before the output directory exists.
  (void)geometry::load_hip_model(options.run.model_dir,
                                 {"femur_bone", "femoral_cartilage", "acetabular_cartilage", "labrum"});
  std::filesystem::create_directories(options.out_dir);
  std::vector<LevelRow> rows;
  for (const std::string& level : levels) {
    FemRunOptions run = options.run;
    run.level = level;
    run.out_file = (std::filesystem::path(options.out_dir) / (level + ".h5")).string();
    run.csv_file = (std::filesystem::path(options.out_dir) / (level + ".csv")).string();
    LevelRow row;
    row.level = level;
    row.summary = run_fem_hip(run, false);
    const auto& results = row.summary.results;
    const std::size_t bodies = row.summary.bodies.size();
    row.peak_vm.assign(bodies, 0.0);
    row.peak_p95.assign(bodies, 0.0);
    row.ball_peak_vm.assign(bodies, 0.0);
    double step_seconds = 0.0;
    const auto surface = [&row](int pair) {
      return pair >= 0 && pair < static_cast<int>(row.summary.pair_surfaces.size()) ? row.summary.pair_surfaces[pair]
                                                                                    : std::string("none");
    };
    for (const fem::ContactResult& r : results) {
      if (r.max_pressure_mpa > row.peak_pressure) {
        row.max_pressure_position = r.max_pressure_position_mm;
        row.max_pressure_surface = surface(r.max_pressure_pair);
      }
      if (r.ball_peak_pressure_mpa > row.ball_peak_pressure) {
        row.ball_peak_pressure = r.ball_peak_pressure_mpa;
        row.ball_peak_pressure_position = r.ball_peak_pressure_position_mm;
        row.ball_peak_pressure_surface = surface(r.ball_peak_pressure_pair);
      }
      for (std::size_t b = 0; b < bodies && b < r.ball_peak_von_mises_mpa.size(); ++b) {
        row.ball_peak_vm[b] = std::max(row.ball_peak_vm[b], r.ball_peak_von_mises_mpa[b]);
      }
      row.peak_pressure = std::max(row.peak_pressure, r.max_pressure_mpa);
      for (std::size_t b = 0; b < bodies && b < r.max_von_mises_mpa.size(); ++b) {
        row.peak_vm[b] = std::max(row.peak_vm[b], r.max_von_mises_mpa[b]);
        row.peak_p95[b] = std::max(row.peak_p95[b], r.p95_von_mises_mpa[b]);
      }
      step_seconds += r.wall_time_s;
    }
    row.wall_per_step = results.empty() ? 0.0 : step_seconds / static_cast<double>(results.size());
    if (!results.empty()) {
      const fem::ContactResult& last = results.back();
      row.last_mean_pressure = last.mean_pressure_mpa;
      row.last_area = last.contact_area_mm2;
      row.last_translation =
          last.rigid_translation_mm.empty() ? 0.0 : last.rigid_translation_mm[fem::kFemurBody].norm();
    }
    rows.push_back(std::move(row));
  }
  if (rank != 0 || rows.empty()) return;
  const LevelRow& finest = rows.back();
  const std::vector<std::string>& bodies = finest.summary.bodies;

  const std::filesystem::path dir(options.out_dir);
  {
    AtomicFile csv_file(dir / "levels.csv");
    std::ofstream csv(csv_file.partial_path());
    csv << "level,hexahedra,dofs,steps,not_converged,wall_s,wall_per_step_s,peak_pressure_mpa,"
           "peak_pressure_diff_percent";
    for (const std::string& body : bodies) csv << ",peak_von_mises_mpa " << body << ",diff_percent";
    for (const std::string& body : bodies) csv << ",peak_p95_von_mises_mpa " << body << ",diff_percent";
    csv << ",last_mean_pressure_mpa,diff_percent,last_contact_area_mm2,diff_percent,last_translation_mm,diff_percent";
    csv << ",peak_radius_mm,ball_peak_pressure_mpa,diff_percent";
    for (const std::string& body : bodies) csv << ",ball_peak_von_mises_mpa " << body << ",diff_percent";
    csv << ",max_pressure_x_mm,max_pressure_y_mm,max_pressure_z_mm,max_pressure_surface"
           ",ball_peak_pressure_x_mm,ball_peak_pressure_y_mm,ball_peak_pressure_z_mm,ball_peak_pressure_surface\n";
    csv.precision(10);
    for (const LevelRow& row : rows) {
      csv << row.level << ',' << row.summary.hexes << ','
          << (row.summary.results.empty() ? 0ul : row.summary.results.front().n_dofs) << ','
          << row.summary.results.size() << ',' << row.summary.failed << ',' << row.summary.seconds << ','
          << row.wall_per_step << ',' << row.peak_pressure << ','
          << relative_difference_percent(row.peak_pressure, finest.peak_pressure);
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        csv << ',' << row.peak_vm[b] << ',' << relative_difference_percent(row.peak_vm[b], finest.peak_vm[b]);
      }
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        csv << ',' << row.peak_p95[b] << ',' << relative_difference_percent(row.peak_p95[b], finest.peak_p95[b]);
      }
      csv << ',' << row.last_mean_pressure << ','
          << relative_difference_percent(row.last_mean_pressure, finest.last_mean_pressure) << ',' << row.last_area
          << ',' << relative_difference_percent(row.last_area, finest.last_area) << ',' << row.last_translation << ','
          << relative_difference_percent(row.last_translation, finest.last_translation);
      csv << ',' << options.run.peak_radius_mm << ',' << row.ball_peak_pressure << ','
          << relative_difference_percent(row.ball_peak_pressure, finest.ball_peak_pressure);
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        csv << ',' << row.ball_peak_vm[b] << ','
            << relative_difference_percent(row.ball_peak_vm[b], finest.ball_peak_vm[b]);
      }
      for (unsigned int d = 0; d < 3; ++d) csv << ',' << row.max_pressure_position[d];
      csv << ',' << row.max_pressure_surface;
      for (unsigned int d = 0; d < 3; ++d) csv << ',' << row.ball_peak_pressure_position[d];
      csv << ',' << row.ball_peak_pressure_surface << '\n';
    }
    csv.close();
    if (!csv) throw_error(csv_file.target().string(), ": write failed");
    csv_file.commit();
  }

  // Plots: difference from the finest level, and wall time per step, against the DOFs.
  studies::LineChart accuracy;
  accuracy.title = "Peak values: difference from the finest level";
  accuracy.x_label = "degrees of freedom";
  accuracy.y_label = "difference from " + finest.level + " (%)";
  accuracy.log_x = true;
  auto dofs_of = [](const LevelRow& row) {
    return row.summary.results.empty() ? 0.0 : static_cast<double>(row.summary.results.front().n_dofs);
  };
  {
    studies::Series pressure{"peak contact pressure", {}, {}, false};
    for (const LevelRow& row : rows) {
      pressure.x.push_back(dofs_of(row));
      pressure.y.push_back(relative_difference_percent(row.peak_pressure, finest.peak_pressure));
    }
    accuracy.series.push_back(pressure);
    studies::Series ball_pressure{"ball-averaged peak pressure", {}, {}, true};
    for (const LevelRow& row : rows) {
      ball_pressure.x.push_back(dofs_of(row));
      ball_pressure.y.push_back(relative_difference_percent(row.ball_peak_pressure, finest.ball_peak_pressure));
    }
    accuracy.series.push_back(ball_pressure);
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      studies::Series vm{"max von Mises, " + bodies[b], {}, {}, false};
      studies::Series p95{"p95 von Mises, " + bodies[b], {}, {}, true};
      for (const LevelRow& row : rows) {
        vm.x.push_back(dofs_of(row));
        vm.y.push_back(relative_difference_percent(row.peak_vm[b], finest.peak_vm[b]));
        p95.x.push_back(dofs_of(row));
        p95.y.push_back(relative_difference_percent(row.peak_p95[b], finest.peak_p95[b]));
      }
      studies::Series ball{"ball-averaged von Mises, " + bodies[b], {}, {}, true};
      for (const LevelRow& row : rows) {
        ball.x.push_back(dofs_of(row));
        ball.y.push_back(relative_difference_percent(row.ball_peak_vm[b], finest.ball_peak_vm[b]));
      }
      accuracy.series.push_back(vm);
      accuracy.series.push_back(p95);
      accuracy.series.push_back(ball);
    }
  }
  studies::write_svg(accuracy, dir / "levels_accuracy.svg");
  studies::LineChart cost;
  cost.title = "Wall time per step (this machine)";
  cost.x_label = "degrees of freedom";
  cost.y_label = "seconds per step";
  cost.log_x = cost.log_y = true;
  studies::Series time{"wall time per step", {}, {}, false};
  for (const LevelRow& row : rows) {
    time.x.push_back(dofs_of(row));
    time.y.push_back(row.wall_per_step);
  }
  cost.series.push_back(time);
  studies::write_svg(cost, dir / "levels_time.svg");

  // Markdown report.
  AtomicFile md_file(dir / "levels.md");
  std::ofstream md(md_file.partial_path());
  char line[512];
  // One " value | diff from the finest |" pair of cells per body.
  const auto body_cells = [&md](const std::vector<double>& values, const std::vector<double>& reference) {
    char cells[64];
    for (std::size_t b = 0; b < values.size(); ++b) {
      std::snprintf(cells, sizeof cells, " %.4f | %+.1f %% |", values[b], relative_difference_percent(values[b], reference[b]));
      md << cells;
    }
  };
  md << "# Hip FE model: mesh levels, accuracy and cost\n\n";
  md << "Model `" << options.run.model_dir << "`, "
     << (options.run.motion_file.empty() ? "standing-to-sitting in " + std::to_string(options.run.steps) + " steps"
                                         : "motion `" + options.run.motion_file + "`")
     << ", " << finest.summary.results.size() << " step(s) per level"
     << (options.run.labrum_refinement > 1
             ? ", labrum meshed " + std::to_string(options.run.labrum_refinement) + " times finer than each level"
             : std::string())
     << ". Peak = maximum over the steps. "
     << "Differences are relative to the finest level run (" << finest.level << "). Times are wall "
     << "times on this machine (" << std::thread::hardware_concurrency() << " hardware threads).\n\n";
  md << "| level | hexahedra | DOFs | not converged | wall per step (s) | wall per model (s) | peak pressure (MPa) | diff |";
  for (const std::string& body : bodies) md << " max VM " << body << " (MPa) | diff |";
  md << "\n|---|---:|---:|---:|---:|---:|---:|---:|";
  for (std::size_t b = 0; b < bodies.size(); ++b) md << "---:|---:|";
  md << '\n';
  for (const LevelRow& row : rows) {
    std::snprintf(line, sizeof line, "| %s | %zu | %.0f | %zu | %.2f | %.1f | %.4f | %+.1f %% |", row.level.c_str(),
                  row.summary.hexes, dofs_of(row), row.summary.failed, row.wall_per_step, row.summary.seconds,
                  row.peak_pressure, relative_difference_percent(row.peak_pressure, finest.peak_pressure));
    md << line;
    body_cells(row.peak_vm, finest.peak_vm);
    md << '\n';
  }
  md << "\n95th percentile of von Mises over each tissue's Gauss points (peak over the steps):\n\n| level |";
  for (const std::string& body : bodies) md << " p95 VM " << body << " (MPa) | diff |";
  md << "\n|---|";
  for (std::size_t b = 0; b < bodies.size(); ++b) md << "---:|---:|";
  md << '\n';
  for (const LevelRow& row : rows) {
    md << "| " << row.level << " |";
    body_cells(row.peak_p95, finest.peak_p95);
    md << '\n';
  }
  md << "\nIntegral quantities at the last step (mean pressure = normal force / contact area):\n\n"
     << "| level | mean pressure (MPa) | diff | contact area (mm^2) | diff | femur translation (mm) | diff |\n"
     << "|---|---:|---:|---:|---:|---:|---:|\n";
  for (const LevelRow& row : rows) {
    std::snprintf(line, sizeof line, "| %s | %.4f | %+.1f %% | %.0f | %+.1f %% | %.4f | %+.1f %% |\n", row.level.c_str(),
                  row.last_mean_pressure, relative_difference_percent(row.last_mean_pressure, finest.last_mean_pressure),
                  row.last_area, relative_difference_percent(row.last_area, finest.last_area), row.last_translation,
                  relative_difference_percent(row.last_translation, finest.last_translation));
    md << line;
  }
  std::snprintf(line, sizeof line, "%g", options.run.peak_radius_mm);
  md << "\nBall-averaged peaks: the largest mean over a ball of radius " << line
     << " mm (fem/peak_measures.h; von Mises JxW-weighted over each tissue's Gauss points, pressure "
        "area-weighted over the active contact nodes), peak over the steps:\n\n| level | ball peak pressure (MPa) | diff |";
  for (const std::string& body : bodies) md << " ball VM " << body << " (MPa) | diff |";
  md << "\n|---|---:|---:|";
  for (std::size_t b = 0; b < bodies.size(); ++b) md << "---:|---:|";
  md << '\n';
  for (const LevelRow& row : rows) {
    std::snprintf(line, sizeof line, "| %s | %.4f | %+.1f %% |", row.level.c_str(), row.ball_peak_pressure,
                  relative_difference_percent(row.ball_peak_pressure, finest.ball_peak_pressure));
    md << line;
    body_cells(row.ball_peak_vm, finest.ball_peak_vm);
    md << '\n';
  }
  md << "\nWhere the pressure peaks sit (hip frame, mm, at the step of the peak; the slave surface of the node):\n\n"
     << "| level | max nodal pressure at | surface | ball peak centre | surface |\n|---|---|---|---|---|\n";
  for (const LevelRow& row : rows) {
    std::snprintf(line, sizeof line, "| %s | (%.2f, %.2f, %.2f) | %s | (%.2f, %.2f, %.2f) | %s |\n", row.level.c_str(),
                  row.max_pressure_position[0], row.max_pressure_position[1], row.max_pressure_position[2],
                  row.max_pressure_surface.c_str(), row.ball_peak_pressure_position[0],
                  row.ball_peak_pressure_position[1], row.ball_peak_pressure_position[2],
                  row.ball_peak_pressure_surface.c_str());
    md << line;
  }
  md << "\n![difference from the finest level](levels_accuracy.svg)\n\n![wall time per step](levels_time.svg)\n\n"
     << "Per level: `<level>.h5` (every step, docs/results-layout.md) and `<level>.csv`.\n";
  md.close();
  if (!md) throw_error(md_file.target().string(), ": write failed");
  md_file.commit();
  std::printf("fem levels: %s, %s, %s\n", (dir / "levels.md").c_str(), (dir / "levels.csv").c_str(),
              (dir / "levels_accuracy.svg").c_str());
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
  run->add_option("--level", run_options->level, "Mesh level (coarse, default, fine)")
      ->check(CLI::IsMember(fem::hip_fe_level_names()));
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
  run->add_option("--solver", run_options->solver, "Linear solver: direct (MUMPS) or cg (CG + GAMG)")
      ->check(CLI::IsMember({"direct", "cg"}));
  auto* vtu_prefix = run->add_option("--vtu-prefix", run_options->vtu_prefix,
                                     "Fields to <prefix>_<step>.vtu and <prefix>.pvd (ParaView)");
  run->add_option("--vtu-every", run_options->vtu_every, "Write VTU every N steps (and the last)")
      ->check(CLI::Range(0, 1000))
      ->needs(vtu_prefix);
  run->add_flag("--verbose", run_options->verbose, "Print active-set iterations");
  run->callback([run_options] { run_fem_hip(*run_options); });

  auto levels_options = std::make_shared<FemLevelsOptions>();
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
  levels->add_option("--levels", levels_options->levels, "Levels to run (the finest is the reference)")
      ->delimiter(',')
      ->check(CLI::IsMember(fem::hip_fe_level_names()));
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
  levels->add_option("--out", levels_options->out_dir,
                     "Output directory: levels.md, levels.csv, levels_*.svg, <level>.h5/.csv")
      ->required();
  levels->callback([levels_options] {
    if (levels_options->levels.size() < 2) throw_error("fem levels: --levels needs at least two levels");
    run_fem_levels(*levels_options);
  });
}};

}  // namespace
}  // namespace hipfai::app

#endif  // HIPFAI_WITH_FEM
