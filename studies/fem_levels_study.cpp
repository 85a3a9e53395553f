#ifdef HIPFAI_WITH_FEM

#include "studies/fem_levels_study.h"

#include "fem/hip_fe_model.h"
#include "fem/motion_solver.h"
#include "geometry/hip_model.h"

#include <mpi.h>

#include <algorithm>

namespace hipfai::studies {

FemLevelsResult compute_fem_levels(const FemLevelsOptions& options) {
  fem::ensure_mpi_initialized();
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  // Levels in the order of refinement; the finest one is the reference.
  std::vector<FeLevel> levels;
  for (const FeLevel level : kFeLevels) {
    if (std::find(options.levels.begin(), options.levels.end(), level) != options.levels.end()) levels.push_back(level);
  }
  // A model directory that cannot be read fails here, before the output directory exists.
  (void)geometry::load_hip_model(options.run.model_dir,
                                 {"femur_bone", "femoral_cartilage", "acetabular_cartilage", "labrum"});
  std::filesystem::create_directories(options.out_dir);
  FemLevelsResult result;
  result.writer = rank == 0;
  std::vector<FemLevelRow>& rows = result.rows;
  for (const FeLevel level : levels) {
    HipFeRunOptions run = options.run;
    run.level = level;
    run.out_file = (options.out_dir / (std::string(to_string(level)) + ".h5")).string();
    run.csv_file = (options.out_dir / (std::string(to_string(level)) + ".csv")).string();
    FemLevelRow row;
    row.level = level;
    row.summary = run_hip_fe(run, false);
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
      if (r.peaks.max_pressure_mpa > row.peak_pressure) {
        row.max_pressure_position = r.peaks.max_pressure_position_mm;
        row.max_pressure_surface = surface(r.peaks.max_pressure_pair);
      }
      if (r.peaks.ball_peak_pressure_mpa > row.ball_peak_pressure) {
        row.ball_peak_pressure = r.peaks.ball_peak_pressure_mpa;
        row.ball_peak_pressure_position = r.peaks.ball_peak_pressure_position_mm;
        row.ball_peak_pressure_surface = surface(r.peaks.ball_peak_pressure_pair);
      }
      for (std::size_t b = 0; b < bodies && b < r.peaks.ball_peak_von_mises_mpa.size(); ++b) {
        row.ball_peak_vm[b] = std::max(row.ball_peak_vm[b], r.peaks.ball_peak_von_mises_mpa[b]);
      }
      row.peak_pressure = std::max(row.peak_pressure, r.peaks.max_pressure_mpa);
      for (std::size_t b = 0; b < bodies && b < r.peaks.max_von_mises_mpa.size(); ++b) {
        row.peak_vm[b] = std::max(row.peak_vm[b], r.peaks.max_von_mises_mpa[b]);
        row.peak_p95[b] = std::max(row.peak_p95[b], r.peaks.p95_von_mises_mpa[b]);
      }
      step_seconds += r.statistics.wall_time_s;
    }
    row.wall_per_step = results.empty() ? 0.0 : step_seconds / static_cast<double>(results.size());
    if (!results.empty()) {
      const fem::ContactResult& last = results.back();
      row.last_mean_pressure = last.peaks.mean_pressure_mpa;
      row.last_area = last.peaks.contact_area_mm2;
      row.last_translation =
          last.rigid_translation_mm.empty() ? 0.0 : last.rigid_translation_mm[fem::kFemurBody].norm();
    }
    rows.push_back(std::move(row));
  }
  return result;
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
