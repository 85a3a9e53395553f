#ifdef HIPFAI_WITH_FEM

#include "studies/pipeline/hip_fe_run.h"

#include "core/atomic_file.h"
#include "core/cache_entry.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/literature.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "core/source_hashes.h"
#include "fem/fem_results.h"
#include "fem/motion_solver.h"
#include "geometry/hip_model.h"
#include "geometry/hip_volume_mesh.h"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <set>
#include <sstream>

namespace hipfai::studies {

namespace {

const std::set<std::string>& fe_tissues() {
  static const std::set<std::string> tissues{"femur_bone", "femoral_cartilage", "acetabular_cartilage",
                                                "labrum"};
  return tissues;
}

// Rotation and joint force per step; steps without a force get `default_force_n`.
std::vector<fem::MotionStep> to_fem_steps(const Motion& motion, const Eigen::Vector3d& default_force_n) {
  std::vector<fem::MotionStep> steps;
  for (const MotionStep& step : motion.steps) {
    steps.push_back(fem::make_hip_motion_step(step.rotation, step.force_N.value_or(default_force_n)));
  }
  return steps;
}

// Name of a contact pair's slave surface (the hip model's boundary ids are SurfaceTag values).
std::string slave_surface_name(const std::vector<std::string>& pair_surfaces, int pair) {
  if (pair < 0 || pair >= static_cast<int>(pair_surfaces.size())) return "none";
  return pair_surfaces[static_cast<std::size_t>(pair)];
}

geometry::HipVolumeOptions volume_options_of(const HipFeRunOptions& options) {
  geometry::HipVolumeOptions volume = fem::hip_volume_options(options.level);
  if (options.labrum_refinement > 1) {
    volume.labrum_edge_mm = volume.edge_mm / options.labrum_refinement;
    volume.labrum_layers = volume.layers * options.labrum_refinement;
  }
  return volume;
}

}  // namespace

Motion hip_fe_motion(const HipFeRunOptions& options) {
  if (options.motion) return *options.motion;
  if (!options.motion_file.empty()) return read_motion_csv(options.motion_file);
  Motion motion = standing_to_sitting(options.steps);
  SittingDownLoadOptions load;
  load.body_weight_n = options.body_weight_n;
  attach_sitting_down_load(motion, load);
  return motion;
}

HipFeRunSummary run_hip_fe(const HipFeRunOptions& options, bool throw_on_failure) {
  fem::limit_threads(options.threads);
  const MPI_Comm communicator = options.ranks == FeRanks::kThisRank ? MPI_COMM_SELF : MPI_COMM_WORLD;
  int rank = 0;
  MPI_Comm_rank(communicator, &rank);
  const auto start = std::chrono::steady_clock::now();
  // Everything that can fail on the user's input is read before the first solve.
  // Joint force: the motion's own where it has one (standing-to-sitting: the sitting-down profile);
  // elsewhere the constant peak load (kStandToSitPeakForcePercentBW of body weight, superior).
  const Motion motion = hip_fe_motion(options);
  const std::vector<fem::MotionStep> steps =
      to_fem_steps(motion, fem::constant_joint_force_n(options.body_weight_n));
  const geometry::HipModel model = geometry::load_hip_model(options.model_dir, fe_tissues());
  const geometry::HipVolumeMesh volume = geometry::build_hip_volume_mesh(model, volume_options_of(options));

  fem::ContactOptions solver;
  solver.verbose = options.verbose;
  solver.peak_average_radius_mm = options.peak_radius_mm;
  solver.team_columns = options.team_columns;
  // Direct (MUMPS) by default: the hip meshes have 15-150 k DOFs with thin, nearly incompressible
  // layers, where CG + GAMG needs ~600 iterations per solve (127 s vs 13 s per coarse step).
  switch (options.solver) {
    case FeSolver::kSubstructured: solver.linear_solver = fem::LinearSolver::kSubstructured; break;
    case FeSolver::kDirect: solver.linear_solver = fem::LinearSolver::kDirect; break;
    case FeSolver::kCg: solver.linear_solver = fem::LinearSolver::kCgAmg; break;
  }
  fem::ContactProblem problem(communicator, solver);
  fem::build_hip_fe_model(problem, volume.mesh, model.tissue("femur_bone"), model.hjc_mm);

  HipFeRunSummary summary;
  summary.hexes = volume.mesh.hexes.size();
  summary.min_scaled_jacobian = volume.min_scaled_jacobian;
  summary.bodies = fem::hip_fe_body_names(problem);
  for (const fem::ContactPair& pair : problem.model().contact_pairs) {
    summary.pair_surfaces.push_back(geometry::to_string(static_cast<geometry::SurfaceTag>(pair.slave_boundary_id)));
  }
  summary.mesh_seconds = seconds_since(start);

  if (rank == 0 && !options.csv_file.empty()) {
    // Fail on an unwritable table before the solve (and before the results file is begun), not after it.
    const std::filesystem::path probe = options.csv_file + ".partial";
    if (!std::ofstream(probe)) throw_error(options.csv_file, ": cannot open for writing (--csv)");
    std::filesystem::remove(probe);
  }
  if (rank == 0 && !options.vtu_prefix.empty()) {
    // The same for the fields' folder (made when missing): deal.II's writer would stop the run
    // after its last step with an internal error.
    const std::filesystem::path probe = options.vtu_prefix + ".partial";
    std::error_code ec;
    if (probe.has_parent_path()) std::filesystem::create_directories(probe.parent_path(), ec);
    if (ec || !std::ofstream(probe)) throw_error(options.vtu_prefix, ": cannot write the VTU files there (--vtu-prefix)");
    std::filesystem::remove(probe);
  }
  std::unique_ptr<fem::FemResultsWriter> writer;
  if (rank == 0) {
    writer = std::make_unique<fem::FemResultsWriter>(options.out_file, summary.bodies, fem::kFemurBody);
    if (options.progress || options.verbose) {
      std::printf("%s: %s, level %s: %zu hexahedra (min scaled Jacobian %.2f), %zu steps\n",
                  options.label.c_str(), options.model_dir.c_str(), to_string(options.level), summary.hexes,
                  volume.min_scaled_jacobian, steps.size());
      std::fflush(stdout);
    }
  }
  fem::MotionOptions motion_options;
  motion_options.moving_body = fem::kFemurBody;
  motion_options.vtu_every = options.vtu_every;
  motion_options.vtu_prefix = options.vtu_prefix;
  motion_options.search_ahead = options.search_ahead;
  ProgressBar progress(options.label, steps.size(), rank == 0 && options.progress && !options.verbose);
  summary.results = fem::run_motion(problem, steps, motion_options,
                                    [&](std::size_t k, const fem::ContactResult& result) {
                                      if (writer) writer->append(steps[k], result);
                                      progress.advance();
                                    });
  progress.finish();
  double peak_pressure = 0.0;
  for (const auto& result : summary.results) {
    summary.failed += result.status != fem::ContactStatus::kConverged;
    peak_pressure = std::max(peak_pressure, result.peaks.max_pressure_mpa);
  }
  summary.seconds = seconds_since(start);
  if (rank == 0 && !options.csv_file.empty()) write_hip_fe_csv(options.csv_file, summary);
  if (rank == 0 && options.progress) {
    std::printf("%s: %zu steps, %zu not converged, %lu dofs, peak pressure %.4g MPa, %.1f s; results in %s\n",
                options.label.c_str(), summary.results.size(), summary.failed,
                summary.results.empty() ? 0ul : summary.results.front().statistics.n_dofs, peak_pressure, summary.seconds,
                (options.results_location.empty() ? options.out_file : options.results_location).c_str());
  }
  if (summary.failed > 0 && throw_on_failure) {
    throw_error(options.label, ": ", summary.failed, " step(s) did not converge (see ", options.out_file, ")");
  }
  return summary;
}

void write_hip_fe_csv(const std::filesystem::path& file, const HipFeRunSummary& summary) {
  const std::vector<std::string>& bodies = summary.bodies;
  std::ostringstream csv;
  csv << "step,status,ranks,dofs,active_set_iterations,max_pressure_mpa,mean_pressure_mpa,"
         "contact_area_mm2,max_penetration_mm,tx_mm,ty_mm,tz_mm";
  for (const std::string& body : bodies) csv << ",max_von_mises_mpa " << body;
  for (const std::string& body : bodies) csv << ",p95_von_mises_mpa " << body;
  csv << ",wall_time_s,sub_steps,cutbacks,linear_solves";
  // Appended after the older columns, so that scripts indexing those keep working.
  csv << ",peak_radius_mm,ball_peak_pressure_mpa";
  for (const std::string& body : bodies) csv << ",ball_peak_von_mises_mpa " << body;
  csv << ",max_pressure_x_mm,max_pressure_y_mm,max_pressure_z_mm,max_pressure_surface"
         ",ball_peak_pressure_x_mm,ball_peak_pressure_y_mm,ball_peak_pressure_z_mm,ball_peak_pressure_surface";
  for (const std::string& body : bodies) {
    for (const char* axis : {"x", "y", "z"}) csv << ",ball_peak_von_mises_" << axis << "_mm " << body;
  }
  csv << '\n';
  csv.precision(17);
  for (std::size_t k = 0; k < summary.results.size(); ++k) {
    const fem::ContactResult& r = summary.results[k];
    csv << k + 1 << ',' << static_cast<int>(r.status) << ',' << r.statistics.n_ranks << ',' << r.statistics.n_dofs << ','
        << r.statistics.active_set_iterations << ',' << r.peaks.max_pressure_mpa << ',' << r.peaks.mean_pressure_mpa << ','
        << r.peaks.contact_area_mm2 << ',' << r.peaks.max_penetration_mm;
    for (unsigned int d = 0; d < 3; ++d) {
      csv << ',' << (r.rigid_translation_mm.empty() ? 0.0 : r.rigid_translation_mm[fem::kFemurBody][d]);
    }
    for (const double v : r.peaks.max_von_mises_mpa) csv << ',' << v;
    for (const double v : r.peaks.p95_von_mises_mpa) csv << ',' << v;
    csv << ',' << r.statistics.wall_time_s << ',' << r.statistics.sub_steps << ',' << r.statistics.cutbacks << ',' << r.statistics.linear_solves;
    csv << ',' << r.peaks.peak_average_radius_mm << ',' << r.peaks.ball_peak_pressure_mpa;
    for (const double v : r.peaks.ball_peak_von_mises_mpa) csv << ',' << v;
    for (unsigned int d = 0; d < 3; ++d) csv << ',' << r.peaks.max_pressure_position_mm[d];
    csv << ',' << slave_surface_name(summary.pair_surfaces, r.peaks.max_pressure_pair);
    for (unsigned int d = 0; d < 3; ++d) csv << ',' << r.peaks.ball_peak_pressure_position_mm[d];
    csv << ',' << slave_surface_name(summary.pair_surfaces, r.peaks.ball_peak_pressure_pair);
    for (const dealii::Point<3>& centre : r.peaks.ball_peak_von_mises_position_mm) {
      for (unsigned int d = 0; d < 3; ++d) csv << ',' << centre[d];
    }
    csv << '\n';
  }
  write_file_atomically(file, csv.str());
}

std::string hip_fe_cache_key(const HipFeRunOptions& options) {
  Hasher hasher;
  hasher.add(std::string_view("hip-fe-v1"));
  hasher.add(std::string_view(kFeSourceHash));
  // The volume mesh is a function of the tissue meshes and the level's options.
  const geometry::HipModel model = geometry::load_hip_model(options.model_dir, fe_tissues());
  for (const std::string& tissue : fe_tissues()) {
    hasher.add(std::string_view(tissue));
    const geometry::TriMesh& mesh = model.tissue(tissue);
    for (const auto& v : mesh.vertices) hasher.add(v.x()).add(v.y()).add(v.z());
    for (const auto& t : mesh.triangles) {
      for (int c = 0; c < 3; ++c) hasher.add(static_cast<std::int64_t>(t[c]));
    }
  }
  for (int d = 0; d < 3; ++d) hasher.add(model.hjc_mm[d]);
  const geometry::HipVolumeOptions volume = volume_options_of(options);
  hasher.add(std::string_view(to_string(options.level)));
  hasher.add(volume.edge_mm).add(static_cast<std::int64_t>(volume.layers));
  hasher.add(volume.labrum_edge_mm).add(static_cast<std::int64_t>(volume.labrum_layers));
  // Materials (thesis §4.3.2.3) and the load.
  hasher.add(literature::kCartilageYoungsModulusMPa).add(literature::kCartilagePoissonRatio);
  hasher.add(literature::kLabrumYoungsModulusMPa).add(literature::kLabrumPoissonRatio);
  hasher.add(options.body_weight_n).add(options.peak_radius_mm);
  hasher.add(std::string_view(to_string(options.solver)));
  // How the volume mesher reads the tissues' outlines (geometry/hip_volume_mesh.h); generated
  // models keep the keys they had before the flag existed.
  if (model.soft_tissue != geometry::SoftTissueSource::kGenerated) hasher.add(std::string_view(geometry::to_string(model.soft_tissue)));
  const Motion motion = hip_fe_motion(options);
  const Eigen::Vector3d default_force = fem::constant_joint_force_n(options.body_weight_n);
  for (const MotionStep& step : motion.steps) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) hasher.add(step.rotation(i, j));
    }
    const Eigen::Vector3d force = step.force_N.value_or(default_force);
    for (int d = 0; d < 3; ++d) hasher.add(force[d]);
  }
  return hasher.hex();
}

std::filesystem::path hip_fe_cache_entry(const std::filesystem::path& cache_dir, const std::string& key) {
  return cache_dir / "fe" / key;
}

CachedHipFe run_hip_fe_cached(HipFeRunOptions options, const std::filesystem::path& cache_dir) {
  const auto start = std::chrono::steady_clock::now();
  CachedHipFe cached;
  cached.entry = hip_fe_cache_entry(cache_dir, hip_fe_cache_key(options));
  const auto has_table = [](const std::filesystem::path& entry) { return std::filesystem::exists(entry / "fe.csv"); };
  const EntrySource source = make_cache_entry(cached.entry, has_table, [&](AtomicDirectory& staging) {
    options.out_file = (staging.partial_path() / "results.h5").string();
    options.csv_file = (staging.partial_path() / "fe.csv").string();
    options.results_location = (cached.entry / "results.h5").string();
    (void)run_hip_fe(options, false);
  });
  cached.reused = source != EntrySource::kMade;
  cached.table = read_hip_fe_csv(cached.entry / "fe.csv");
  cached.seconds = seconds_since(start);
  return cached;
}

std::vector<std::string> hip_fe_command_arguments(const HipFeRunOptions& options) {
  if (options.motion) throw_error("hip FE: a motion given in memory cannot be passed to another process");
  auto number = [](double value) {
    std::ostringstream out;
    out.precision(17);
    out << value;
    return out.str();
  };
  std::vector<std::string> args{"fem", "run", "--model", options.model_dir, "--level", to_string(options.level),
                                "--body-weight-n", number(options.body_weight_n), "--peak-radius-mm",
                                number(options.peak_radius_mm), "--labrum-refinement",
                                std::to_string(options.labrum_refinement), "--solver", to_string(options.solver),
                                "--out", options.out_file};
  if (options.motion_file.empty()) {
    args.insert(args.end(), {"--steps", std::to_string(options.steps)});
  } else {
    args.insert(args.end(), {"--motion", options.motion_file});
  }
  if (!options.csv_file.empty()) args.insert(args.end(), {"--csv", options.csv_file});
  if (options.threads > 0) args.insert(args.end(), {"--threads", std::to_string(options.threads)});
  if (options.vtu_every > 0) {
    args.insert(args.end(), {"--vtu-prefix", options.vtu_prefix, "--vtu-every", std::to_string(options.vtu_every)});
  }
  return args;
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
