#include "studies/validation_study.h"

#include "studies/validation_hip.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "studies/pipeline/motion.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/pipeline/fe_batch.h"
#include "studies/pipeline/hip_fe_run.h"
#include "studies/validation_ranks.h"
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>


namespace hipfai::studies {

namespace {

using Clock = SteadyClock;

std::string csv_number(double value) {
  if (!std::isfinite(value)) return "";
  std::ostringstream out;
  out << std::setprecision(10) << value;
  return out.str();
}

#ifdef HIPFAI_WITH_FEM

// A validation measure of one step: a pressure as the table has it; a von Mises statistic as the
// largest over the measure's tissues (its one, or all of the model's), from 0, so that a tissue
// the run does not have (NaN in the record) counts as no stress.
double validation_value(const FeStepRecord& step, const FeMeasure& measure) {
  if (const auto* pressure = std::get_if<PressureStat>(&measure)) return step.pressure(*pressure);
  const auto& von_mises = std::get<VonMisesMeasure>(measure);
  double value = 0.0;
  for (const FeTissue tissue : kFeTissues) {
    if (von_mises.tissue && *von_mises.tissue != tissue) continue;
    value = std::max(value, step.von_mises(von_mises.stat, tissue));
  }
  return value;
}

}  // namespace

std::vector<std::vector<double>> validation_fe_measures_of(const HipFeTable& table, std::size_t steps,
                                                           const std::filesystem::path& file) {
  if (table.steps.size() != steps) {
    throw_error(file.string(), ": ", table.steps.size(), " FE steps, the motion has ", steps);
  }
  std::vector<std::vector<double>> out;
  for (const FeMeasure& measure : validation_fe_measures()) {
    std::vector<double> values;
    for (const FeStepRecord& step : table.steps) {
      values.push_back(step.converged() ? validation_value(step, measure) : std::numeric_limits<double>::quiet_NaN());
    }
    out.push_back(std::move(values));
  }
  return out;
}

namespace {

FeBatchOptions validation_fe_batch(const ValidationOptions& options) {
  FeBatchOptions batch;
  batch.cache_dir = options.cache_dir;
  batch.program = options.program;
  batch.jobs = options.jobs;
  batch.progress = options.progress;
  batch.label = "validate";
  return batch;
}

// The hips made and their depths computed one after the other in this process, each hip's FE
// started in a worker process as soon as the hip is made (while the next ones are made), then
// read back from the cache. `order`: the order in which the hips are started.
std::vector<ValidationHip> run_on_this_machine(const std::vector<std::pair<double, double>>& grid,
                                               const std::vector<std::size_t>& order, const Motion& motion,
                                               const ValidationOptions& options) {
  std::vector<ValidationHip> hips(grid.size());
  FeBatch fe(validation_fe_batch(options));
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto [ce, alpha] = grid[order[k]];
    const auto hip_start = Clock::now();
    ValidationHip& hip = hips[order[k]];
    hip = run_validation_penetration(ce, alpha, motion, options, options.threads);
    if (options.progress) {
      std::printf("validate: penetration [%zu/%zu] %s: max curvilinear %.2f mm, radial %.2f mm (%.1f s)\n",
                  k + 1, grid.size(), hip.id.c_str(), *std::max_element(hip.curvilinear_max_mm.begin(), hip.curvilinear_max_mm.end()),
                  *std::max_element(hip.radial_max_mm.begin(), hip.radial_max_mm.end()), seconds_since(hip_start));
      std::fflush(stdout);
    }
    fe.add(validation_fe_job(hip, options));
  }
  const std::vector<FeBatchEntry> done = fe.finish();
  for (std::size_t k = 0; k < order.size(); ++k) read_validation_fe_entry(hips[order[k]], done[k], motion, options);
  return hips;
}

#endif  // HIPFAI_WITH_FEM

void write_steps_csv(const std::vector<ValidationHip>& hips, const Motion& motion, const std::filesystem::path& path) {
  std::ostringstream csv;
  csv << "ce_deg,alpha_deg,step,angle_deg,max_curvilinear_mm,max_radial_mm";
  for (const FeMeasure& measure : validation_fe_measures()) csv << ',' << fe_measure_name(measure);
  csv << '\n';
  for (const ValidationHip& run : hips) {
    for (std::size_t k = 0; k < motion.steps.size(); ++k) {
      csv << run.ce << ',' << run.alpha << ',' << k + 1 << ',' << csv_number(motion.steps[k].angle_deg) << ','
          << csv_number(run.curvilinear_max_mm[k]) << ',' << csv_number(run.radial_max_mm[k]);
      for (std::size_t m = 0; m < validation_fe_measures().size(); ++m) {
        csv << ',' << (m < run.fe.size() ? csv_number(run.fe[m][k]) : std::string());
      }
      csv << '\n';
    }
  }
  write_file_atomically(path, csv.str());
}

void write_timings_csv(const std::vector<ValidationHip>& hips, const ValidationOptions& options, int steps,
                       const std::filesystem::path& path) {
  std::ostringstream csv;
  csv << "ce_deg,alpha_deg,edge_mm,steps,fe_level,generate_s,penetration_tables_ms,penetration_query_ms,"
         "fe_s,fe_step_s,fe_reused,fe_steps_failed,fe_dofs\n";
  for (const ValidationHip& run : hips) {
    const ValidationHipTiming& t = run.timing;
    csv << run.ce << ',' << run.alpha << ',' << options.edge_mm << ',' << steps << ',' << to_string(options.fe_level) << ','
        << csv_number(t.generate_s) << ',' << csv_number(t.penetration_tables_ms) << ',' << csv_number(t.penetration_query_ms)
        << ',' << csv_number(t.fe_s) << ',' << csv_number(t.fe_step_s) << ',' << (t.fe_reused ? 1 : 0) << ','
        << t.fe_steps_failed << ',' << csv_number(t.fe_dofs) << '\n';
  }
  write_file_atomically(path, csv.str());
}

void check_options(const ValidationOptions& options) {
  if (options.hips.empty() && (options.ce_deg.empty() || options.alpha_deg.empty())) {
    throw_error("validate: empty CE or alpha grid");
  }
  if (options.sub_motions < 3) throw_error("validate: --steps must be at least 3 (a correlation needs 3 pairs)");
  if (!(options.edge_mm > 0)) throw_error("validate: --edge-mm must be > 0");
  if (options.jobs < 1) throw_error("validate: --jobs must be at least 1");
#ifdef HIPFAI_WITH_FEM
  if (!options.program.empty() && !std::filesystem::exists(options.program)) {
    throw_error("validate: FE worker program ", options.program.string(), " not found");
  }
#else
  throw_error("validate: this build has no FE module (configure with HIPFAI_WITH_FEM=ON)");
#endif
}

}  // namespace

const std::vector<FeMeasure>& validation_fe_measures() {
  using enum VonMisesStat;
  static const std::vector<FeMeasure> measures{
      VonMisesMeasure{kBall, std::nullopt},
      VonMisesMeasure{kMax, std::nullopt},
      VonMisesMeasure{kBall, FeTissue::kLabrum},
      VonMisesMeasure{kMax, FeTissue::kLabrum},
      VonMisesMeasure{kP95, FeTissue::kLabrum},
      VonMisesMeasure{kBall, FeTissue::kFemoralCartilage},
      VonMisesMeasure{kMax, FeTissue::kFemoralCartilage},
      VonMisesMeasure{kP95, FeTissue::kFemoralCartilage},
      VonMisesMeasure{kBall, FeTissue::kAcetabularCartilage},
      VonMisesMeasure{kMax, FeTissue::kAcetabularCartilage},
      VonMisesMeasure{kP95, FeTissue::kAcetabularCartilage},
      PressureStat::kMax,
      PressureStat::kBall,
      PressureStat::kMean};
  return measures;
}

ValidationResult run_validation_study(const ValidationOptions& options) {
  check_options(options);
  const auto start = Clock::now();
  std::filesystem::create_directories(options.out_dir);
  const Motion motion = standing_to_sitting(options.sub_motions);
  std::vector<std::pair<double, double>> grid = options.hips;
  if (grid.empty()) {
    for (double ce : options.ce_deg) {
      for (double alpha : options.alpha_deg) grid.emplace_back(ce, alpha);
    }
  }
  // The hips are made, and their FE started, in decreasing CE then alpha: a larger socket has a
  // larger contact zone and a longer FE run (15 s at CE 0 to 29 s at CE 40 at default), so with
  // the workers busy from the start the short runs fill the end (longest first). The results
  // keep the grid's order.
  std::vector<std::size_t> order(grid.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&grid](std::size_t a, std::size_t b) { return grid[a] > grid[b]; });
  ValidationResult result;
  std::vector<ValidationHip> hips;
#ifdef HIPFAI_WITH_FEM
  if (options.spread == UnitSpread::kMpiRanks && join_mpi_world().size > 1) {
    ValidationRankRun ranks = run_validation_over_ranks(grid, order, motion, options);
    if (!ranks.writes) {
      result.wrote_tables = false;
      return result;
    }
    hips = std::move(ranks.hips);
    result.failed = std::move(ranks.failed);
  } else {
    hips = run_on_this_machine(grid, order, motion, options);
  }
#endif
  write_steps_csv(hips, motion, options.out_dir / "steps.csv");
  write_timings_csv(hips, options, static_cast<int>(motion.steps.size()), options.out_dir / "timings.csv");
  for (const ValidationHip& run : hips) result.hips.push_back(run.timing);
  result.steps = static_cast<int>(motion.steps.size());
  result.fe_level = options.fe_level;
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace hipfai::studies
