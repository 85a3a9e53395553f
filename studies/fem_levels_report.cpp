#ifdef HIPFAI_WITH_FEM

#include "studies/fem_levels_report.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "studies/reports/svg_plot.h"

#include <cstdio>
#include <sstream>
#include <thread>

namespace hipfai::studies {

namespace {

double relative_difference_percent(double value, double reference) {
  return reference != 0.0 ? 100.0 * (value - reference) / reference : 0.0;
}

double dofs_of(const FemLevelRow& row) {
  return row.summary.results.empty() ? 0.0 : static_cast<double>(row.summary.results.front().statistics.n_dofs);
}

std::string csv_header(const std::vector<std::string>& bodies) {
  std::ostringstream csv;
  csv << "level,hexahedra,dofs,steps,not_converged,wall_s,wall_per_step_s,peak_pressure_mpa,"
         "peak_pressure_diff_percent";
  for (const std::string& body : bodies) csv << ",peak_von_mises_mpa " << body << ",diff_percent";
  for (const std::string& body : bodies) csv << ",peak_p95_von_mises_mpa " << body << ",diff_percent";
  csv << ",last_mean_pressure_mpa,diff_percent,last_contact_area_mm2,diff_percent,last_translation_mm,diff_percent";
  csv << ",peak_radius_mm,ball_peak_pressure_mpa,diff_percent";
  for (const std::string& body : bodies) csv << ",ball_peak_von_mises_mpa " << body << ",diff_percent";
  csv << ",max_pressure_x_mm,max_pressure_y_mm,max_pressure_z_mm,max_pressure_surface"
         ",ball_peak_pressure_x_mm,ball_peak_pressure_y_mm,ball_peak_pressure_z_mm,ball_peak_pressure_surface\n";
  return csv.str();
}

// One ",value,diff" pair of cells per body.
void write_body_csv_cells(std::ostream& csv, std::size_t bodies, const std::vector<double>& values,
                          const std::vector<double>& reference) {
  for (std::size_t b = 0; b < bodies; ++b) {
    csv << ',' << values[b] << ',' << relative_difference_percent(values[b], reference[b]);
  }
}

void write_csv_row(std::ostream& csv, const FemLevelRow& row, const FemLevelRow& finest, double peak_radius_mm) {
  csv << to_string(row.level) << ',' << row.summary.hexes << ','
      << (row.summary.results.empty() ? 0ul : row.summary.results.front().statistics.n_dofs) << ','
      << row.summary.results.size() << ',' << row.summary.failed << ',' << row.summary.seconds << ','
      << row.wall_per_step << ',' << row.peak_pressure << ','
      << relative_difference_percent(row.peak_pressure, finest.peak_pressure);
  write_body_csv_cells(csv, finest.summary.bodies.size(), row.peak_vm, finest.peak_vm);
  write_body_csv_cells(csv, finest.summary.bodies.size(), row.peak_p95, finest.peak_p95);
  csv << ',' << row.last_mean_pressure << ','
      << relative_difference_percent(row.last_mean_pressure, finest.last_mean_pressure) << ',' << row.last_area
      << ',' << relative_difference_percent(row.last_area, finest.last_area) << ',' << row.last_translation << ','
      << relative_difference_percent(row.last_translation, finest.last_translation);
  csv << ',' << peak_radius_mm << ',' << row.ball_peak_pressure << ','
      << relative_difference_percent(row.ball_peak_pressure, finest.ball_peak_pressure);
  write_body_csv_cells(csv, finest.summary.bodies.size(), row.ball_peak_vm, finest.ball_peak_vm);
  for (unsigned int d = 0; d < 3; ++d) csv << ',' << row.max_pressure_position[d];
  csv << ',' << row.max_pressure_surface;
  for (unsigned int d = 0; d < 3; ++d) csv << ',' << row.ball_peak_pressure_position[d];
  csv << ',' << row.ball_peak_pressure_surface << '\n';
}

void write_levels_csv(const std::vector<FemLevelRow>& rows, double peak_radius_mm, const std::filesystem::path& path) {
  std::ostringstream csv;
  csv << csv_header(rows.back().summary.bodies);
  csv.precision(10);
  for (const FemLevelRow& row : rows) write_csv_row(csv, row, rows.back(), peak_radius_mm);
  write_file_atomically(path, csv.str());
}

// One series of a measure's difference from the finest level against the DOFs.
Series difference_series(const std::string& name, bool dashed, const std::vector<FemLevelRow>& rows,
                         double FemLevelRow::*value) {
  Series series{name, {}, {}, dashed};
  for (const FemLevelRow& row : rows) {
    series.x.push_back(dofs_of(row));
    series.y.push_back(relative_difference_percent(row.*value, rows.back().*value));
  }
  return series;
}

// The same for one body of a per-body measure.
Series body_difference_series(const std::string& name, bool dashed, const std::vector<FemLevelRow>& rows,
                              std::vector<double> FemLevelRow::*values, std::size_t b) {
  Series series{name, {}, {}, dashed};
  for (const FemLevelRow& row : rows) {
    series.x.push_back(dofs_of(row));
    series.y.push_back(relative_difference_percent((row.*values)[b], (rows.back().*values)[b]));
  }
  return series;
}

// Plots: difference from the finest level, and wall time per step, against the DOFs.
void write_plots(const std::vector<FemLevelRow>& rows, const std::filesystem::path& dir) {
  const FemLevelRow& finest = rows.back();
  const std::vector<std::string>& bodies = finest.summary.bodies;
  LineChart accuracy;
  accuracy.title = "Peak values: difference from the finest level";
  accuracy.x_label = "degrees of freedom";
  accuracy.y_label = "difference from " + std::string(to_string(finest.level)) + " (%)";
  accuracy.log_x = true;
  accuracy.series.push_back(difference_series("peak contact pressure", false, rows, &FemLevelRow::peak_pressure));
  accuracy.series.push_back(
      difference_series("ball-averaged peak pressure", true, rows, &FemLevelRow::ball_peak_pressure));
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    accuracy.series.push_back(body_difference_series("max von Mises, " + bodies[b], false, rows, &FemLevelRow::peak_vm, b));
    accuracy.series.push_back(body_difference_series("p95 von Mises, " + bodies[b], true, rows, &FemLevelRow::peak_p95, b));
    accuracy.series.push_back(
        body_difference_series("ball-averaged von Mises, " + bodies[b], true, rows, &FemLevelRow::ball_peak_vm, b));
  }
  write_svg(accuracy, dir / "levels_accuracy.svg");
  LineChart cost;
  cost.title = "Wall time per step (this machine)";
  cost.x_label = "degrees of freedom";
  cost.y_label = "seconds per step";
  cost.log_x = cost.log_y = true;
  Series time{"wall time per step", {}, {}, false};
  for (const FemLevelRow& row : rows) {
    time.x.push_back(dofs_of(row));
    time.y.push_back(row.wall_per_step);
  }
  cost.series.push_back(time);
  write_svg(cost, dir / "levels_time.svg");
}

// One " value | diff from the finest |" pair of cells per body.
void write_body_cells(std::ostream& md, const std::vector<double>& values, const std::vector<double>& reference) {
  char cells[64];
  for (std::size_t b = 0; b < values.size(); ++b) {
    std::snprintf(cells, sizeof cells, " %.4f | %+.1f %% |", values[b], relative_difference_percent(values[b], reference[b]));
    md << cells;
  }
}

// The header row and rule of a table with a " <label> <body> (MPa) | diff |" pair per body.
void write_body_columns(std::ostream& md, const std::vector<std::string>& bodies, const char* label) {
  for (const std::string& body : bodies) md << ' ' << label << ' ' << body << " (MPa) | diff |";
}

void write_body_rule(std::ostream& md, std::size_t bodies) {
  for (std::size_t b = 0; b < bodies; ++b) md << "---:|---:|";
  md << '\n';
}

void write_introduction(std::ostream& md, const FemLevelsOptions& options, const FemLevelRow& finest) {
  md << "# Hip FE model: mesh levels, accuracy and cost\n\n";
  md << "Model `" << options.run.model_dir << "`, "
     << (options.run.motion_file.empty() ? "standing-to-sitting in " + std::to_string(options.run.steps) + " steps"
                                         : "motion `" + options.run.motion_file + "`")
     << ", " << finest.summary.results.size() << " step(s) per level"
     << (options.run.labrum_refinement > 1
             ? ", labrum meshed " + std::to_string(options.run.labrum_refinement) + " times finer than each level"
             : std::string())
     << ". Peak = maximum over the steps. "
     << "Differences are relative to the finest level run (" << to_string(finest.level) << "). Times are wall "
     << "times on this machine (" << std::thread::hardware_concurrency() << " hardware threads).\n\n";
}

// Size, cost, peak pressure and peak von Mises per level; then the 95th percentiles.
void write_peak_tables(std::ostream& md, const std::vector<FemLevelRow>& rows) {
  const FemLevelRow& finest = rows.back();
  const std::vector<std::string>& bodies = finest.summary.bodies;
  char line[512];
  md << "| level | hexahedra | DOFs | not converged | wall per step (s) | wall per model (s) | peak pressure (MPa) | diff |";
  write_body_columns(md, bodies, "max VM");
  md << "\n|---|---:|---:|---:|---:|---:|---:|---:|";
  write_body_rule(md, bodies.size());
  for (const FemLevelRow& row : rows) {
    std::snprintf(line, sizeof line, "| %s | %zu | %.0f | %zu | %.2f | %.1f | %.4f | %+.1f %% |", to_string(row.level),
                  row.summary.hexes, dofs_of(row), row.summary.failed, row.wall_per_step, row.summary.seconds,
                  row.peak_pressure, relative_difference_percent(row.peak_pressure, finest.peak_pressure));
    md << line;
    write_body_cells(md, row.peak_vm, finest.peak_vm);
    md << '\n';
  }
  md << "\n95th percentile of von Mises over each tissue's Gauss points (peak over the steps):\n\n| level |";
  write_body_columns(md, bodies, "p95 VM");
  md << "\n|---|";
  write_body_rule(md, bodies.size());
  for (const FemLevelRow& row : rows) {
    md << "| " << to_string(row.level) << " |";
    write_body_cells(md, row.peak_p95, finest.peak_p95);
    md << '\n';
  }
}

void write_integral_table(std::ostream& md, const std::vector<FemLevelRow>& rows) {
  const FemLevelRow& finest = rows.back();
  char line[512];
  md << "\nIntegral quantities at the last step (mean pressure = normal force / contact area):\n\n"
     << "| level | mean pressure (MPa) | diff | contact area (mm^2) | diff | femur translation (mm) | diff |\n"
     << "|---|---:|---:|---:|---:|---:|---:|\n";
  for (const FemLevelRow& row : rows) {
    std::snprintf(line, sizeof line, "| %s | %.4f | %+.1f %% | %.0f | %+.1f %% | %.4f | %+.1f %% |\n", to_string(row.level),
                  row.last_mean_pressure, relative_difference_percent(row.last_mean_pressure, finest.last_mean_pressure),
                  row.last_area, relative_difference_percent(row.last_area, finest.last_area), row.last_translation,
                  relative_difference_percent(row.last_translation, finest.last_translation));
    md << line;
  }
}

void write_ball_table(std::ostream& md, const std::vector<FemLevelRow>& rows, double peak_radius_mm) {
  const FemLevelRow& finest = rows.back();
  char line[512];
  std::snprintf(line, sizeof line, "%g", peak_radius_mm);
  md << "\nBall-averaged peaks: the largest mean over a ball of radius " << line
     << " mm (fem/peak_measures.h; von Mises JxW-weighted over each tissue's Gauss points, pressure "
        "area-weighted over the active contact nodes), peak over the steps:\n\n| level | ball peak pressure (MPa) | diff |";
  write_body_columns(md, finest.summary.bodies, "ball VM");
  md << "\n|---|---:|---:|";
  write_body_rule(md, finest.summary.bodies.size());
  for (const FemLevelRow& row : rows) {
    std::snprintf(line, sizeof line, "| %s | %.4f | %+.1f %% |", to_string(row.level), row.ball_peak_pressure,
                  relative_difference_percent(row.ball_peak_pressure, finest.ball_peak_pressure));
    md << line;
    write_body_cells(md, row.ball_peak_vm, finest.ball_peak_vm);
    md << '\n';
  }
}

void write_peak_positions(std::ostream& md, const std::vector<FemLevelRow>& rows) {
  char line[512];
  md << "\nWhere the pressure peaks sit (hip frame, mm, at the step of the peak; the slave surface of the node):\n\n"
     << "| level | max nodal pressure at | surface | ball peak centre | surface |\n|---|---|---|---|---|\n";
  for (const FemLevelRow& row : rows) {
    std::snprintf(line, sizeof line, "| %s | (%.2f, %.2f, %.2f) | %s | (%.2f, %.2f, %.2f) | %s |\n", to_string(row.level),
                  row.max_pressure_position[0], row.max_pressure_position[1], row.max_pressure_position[2],
                  row.max_pressure_surface.c_str(), row.ball_peak_pressure_position[0],
                  row.ball_peak_pressure_position[1], row.ball_peak_pressure_position[2],
                  row.ball_peak_pressure_surface.c_str());
    md << line;
  }
}

}  // namespace

void write_fem_levels_report(const FemLevelsResult& result, const FemLevelsOptions& options) {
  if (!result.writer || result.rows.empty()) return;
  const std::filesystem::path dir(options.out_dir);
  write_levels_csv(result.rows, options.run.peak_radius_mm, dir / "levels.csv");
  write_plots(result.rows, dir);
  std::ostringstream md;
  write_introduction(md, options, result.rows.back());
  write_peak_tables(md, result.rows);
  write_integral_table(md, result.rows);
  write_ball_table(md, result.rows, options.run.peak_radius_mm);
  write_peak_positions(md, result.rows);
  md << "\n![difference from the finest level](levels_accuracy.svg)\n\n![wall time per step](levels_time.svg)\n\n"
     << "Per level: `<level>.h5` (every step, docs/results-layout.md) and `<level>.csv`.\n";
  write_file_atomically(dir / "levels.md", md.str());
  std::printf("fem levels: %s, %s, %s\n", (dir / "levels.md").c_str(), (dir / "levels.csv").c_str(),
              (dir / "levels_accuracy.svg").c_str());
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
