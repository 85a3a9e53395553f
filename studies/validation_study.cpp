#include "studies/validation_study.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "geometry/mesh_io.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/motion.h"
#include "studies/pipeline/penetration_run.h"
#include "studies/pipeline/scene.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/pipeline/fe_batch.h"
#include "studies/pipeline/hip_fe_run.h"
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

// The hip of thesis Figs. 60-61 (CE 40 / alpha 60).
constexpr double kFigureCe = 40.0, kFigureAlpha = 60.0;

struct HipRun {
  double ce = 0, alpha = 0;
  LoadedHip hip;
  PenetrationRun penetration;
  ValidationHipTiming timing;
  std::vector<std::vector<double>> fe;  // [measure][step], NaN where the FE step failed
};

// Femur-side tissues move with the femur; the others stay with the pelvis.
bool moves_with_femur(const std::string& tissue) {
  return tissue == "femur_bone" || tissue == "femoral_cartilage";
}

// The tissues with the last step's depth fields, the femur's at the end pose (as the FE's VTU).
void write_end_pose_vtp(const LoadedHip& hip, const MotionStep& last, const DepthFields& fields,
                        const std::filesystem::path& dir) {
  std::map<std::string, geometry::TriMesh> coloured;
  for (const auto& [tissue, mesh] : hip.tissues) coloured.emplace(tissue, mesh);
  for (const auto& [key, values] : fields) {
    const std::string tissue = key.substr(0, key.find('/'));
    coloured.at(tissue).vertex_fields[key.substr(key.find('/') + 1)] = values;
  }
  const Eigen::Matrix3d rotation = hip.frame * last.rotation * hip.frame.transpose();
  std::filesystem::create_directories(dir);
  for (auto& [tissue, mesh] : coloured) {
    if (moves_with_femur(tissue)) {
      for (auto& v : mesh.vertices) v = hip.hjc_mm + rotation * (v - hip.hjc_mm);
    }
    geometry::write_mesh(mesh, dir / (tissue + ".vtp"));
  }
}

HipRun run_penetration(double ce, double alpha, const Motion& motion, const ValidationOptions& options,
                       StageLog& log) {
  HipRun run;
  run.ce = ce;
  run.alpha = alpha;
  run.timing.ce_deg = ce;
  run.timing.alpha_deg = alpha;
  Scene scene;
  scene.name = parametric_hip_id(ce, alpha);
  scene.parametric = ParametricHip{ce, alpha, options.edge_mm};
  scene.outputs = {Output::kCurvilinearDepth, Output::kRadialDepth};
  for (Output output : scene.outputs) {
    const auto tissues = tissues_for(output);
    scene.tissues.insert(tissues.begin(), tissues.end());
  }
  const int generated_before = log.executed_count(StageKind::kGenerateHip);
  const auto start = Clock::now();
  run.hip = acquire_hip(scene, scene.tissues, options.cache_dir, log);
  run.timing.generate_s = log.executed_count(StageKind::kGenerateHip) > generated_before ? seconds_since(start) : 0.0;
  PenetrationOptions penetration;
  penetration.threads = options.threads;
  penetration.cache_dir = options.cache_dir;
  const bool figure = ce == kFigureCe && alpha == kFigureAlpha;
  StepObserver observer;
  if (figure) {
    observer = [&](std::size_t step, const DepthFields& fields) {
      if (step + 1 == motion.steps.size()) {
        write_end_pose_vtp(run.hip, motion.steps.back(), fields, options.out_dir / "fig61");
      }
    };
  }
  run.penetration = compute_penetration(run.hip, motion, penetration, log, observer);
  run.timing.penetration_tables_ms =
      run.penetration.curvilinear_preprocessing_ms + run.penetration.radial_preprocessing_ms;
  for (const StepPenetration& step : run.penetration.steps) {
    run.timing.penetration_query_ms += step.curvilinear_ms + step.radial_ms;
  }
  return run;
}

std::string number(double value) {
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

// The FE run of one hip, for the batch.
FeBatchJob validation_fe_job(const HipRun& hip, const ValidationOptions& options) {
  FeBatchJob job;
  job.id = hip.hip.id;
  job.run.model_dir = hip.hip.dir.string();
  job.run.steps = options.sub_motions;
  job.run.level = options.fe_level;
  if (options.body_weight_n > 0) job.run.body_weight_n = options.body_weight_n;
  job.run.vtu_every = static_cast<unsigned int>(options.sub_motions);  // the end pose only
  return job;
}

FeBatchOptions validation_fe_batch(const ValidationOptions& options) {
  FeBatchOptions batch;
  batch.cache_dir = options.cache_dir;
  batch.program = options.program;
  batch.jobs = options.jobs;
  batch.progress = options.progress;
  batch.label = "validate";
  return batch;
}

// Every hip's FE results from its cache entry (one entry per hip, in the hips' order).
void read_fe_entries(std::vector<HipRun>& hips, const std::vector<FeBatchEntry>& done, const Motion& motion,
                     const ValidationOptions& options) {
  std::vector<std::filesystem::path> entries;
  for (std::size_t h = 0; h < hips.size(); ++h) {
    hips[h].timing.fe_reused = done[h].reused;
    entries.push_back(done[h].entry);
  }
  // Read every hip's entry back.
  for (std::size_t h = 0; h < hips.size(); ++h) {
    HipRun& run = hips[h];
    const std::filesystem::path& entry = entries[h];
    const HipFeTable table = read_hip_fe_csv(entry / "fe.csv");
    run.fe = validation_fe_measures_of(table, motion.steps.size(), entry / "fe.csv");
    for (const FeStepRecord& step : table.steps) {
      run.timing.fe_step_s += step.wall_time_s;
      run.timing.fe_steps_failed += !step.converged();
    }
    run.timing.fe_dofs = table.steps.empty() ? 0.0 : table.steps.front().dofs;
    std::ifstream timing(entry / "timing.txt");
    std::string word;
    if (timing >> word >> run.timing.fe_s; !timing) run.timing.fe_s = run.timing.fe_step_s;
    // The end pose of the figure's hip: the FE fields beside the depths.
    if (run.ce == kFigureCe && run.alpha == kFigureAlpha) {
      const std::filesystem::path vtu = entry / ("fe_" + std::to_string(motion.steps.size()) + ".vtu");
      if (std::filesystem::exists(vtu)) {
        std::filesystem::create_directories(options.out_dir / "fig61");
        std::filesystem::copy_file(vtu, options.out_dir / "fig61" / "fe.vtu",
                                   std::filesystem::copy_options::overwrite_existing);
      }
    }
  }
}

#endif  // HIPFAI_WITH_FEM

void write_steps_csv(const std::vector<HipRun>& hips, const Motion& motion, const std::filesystem::path& path) {
  std::ostringstream csv;
  csv << "ce_deg,alpha_deg,step,angle_deg,max_curvilinear_mm,max_radial_mm";
  for (const FeMeasure& measure : validation_fe_measures()) csv << ',' << fe_measure_name(measure);
  csv << '\n';
  for (const HipRun& run : hips) {
    for (std::size_t k = 0; k < motion.steps.size(); ++k) {
      const StepPenetration& step = run.penetration.steps[k];
      csv << run.ce << ',' << run.alpha << ',' << k + 1 << ',' << number(motion.steps[k].angle_deg) << ','
          << number(step.curvilinear_max_mm()) << ',' << number(step.radial_max_mm());
      for (std::size_t m = 0; m < validation_fe_measures().size(); ++m) {
        csv << ',' << (m < run.fe.size() ? number(run.fe[m][k]) : std::string());
      }
      csv << '\n';
    }
  }
  write_file_atomically(path, csv.str());
}

void write_timings_csv(const std::vector<HipRun>& hips, const ValidationOptions& options, int steps,
                       const std::filesystem::path& path) {
  std::ostringstream csv;
  csv << "ce_deg,alpha_deg,edge_mm,steps,fe_level,generate_s,penetration_tables_ms,penetration_query_ms,"
         "fe_s,fe_step_s,fe_reused,fe_steps_failed,fe_dofs\n";
  for (const HipRun& run : hips) {
    const ValidationHipTiming& t = run.timing;
    csv << run.ce << ',' << run.alpha << ',' << options.edge_mm << ',' << steps << ',' << to_string(options.fe_level) << ','
        << number(t.generate_s) << ',' << number(t.penetration_tables_ms) << ',' << number(t.penetration_query_ms)
        << ',' << number(t.fe_s) << ',' << number(t.fe_step_s) << ',' << (t.fe_reused ? 1 : 0) << ','
        << t.fe_steps_failed << ',' << number(t.fe_dofs) << '\n';
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
  StageLog log;
  std::vector<HipRun> hips;
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
  hips.resize(grid.size());
#ifdef HIPFAI_WITH_FEM
  // Each hip's FE starts in a worker as soon as the hip is made, while the next ones are made.
  FeBatch fe(validation_fe_batch(options));
#endif
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto [ce, alpha] = grid[order[k]];
    const auto hip_start = Clock::now();
    HipRun& hip = hips[order[k]];
    hip = run_penetration(ce, alpha, motion, options, log);
    if (options.progress) {
      std::printf("validate: penetration [%zu/%zu] %s: max curvilinear %.2f mm, radial %.2f mm (%.1f s)\n",
                  k + 1, grid.size(), hip.hip.id.c_str(), hip.penetration.max_curvilinear_mm(),
                  hip.penetration.max_radial_mm(), seconds_since(hip_start));
      std::fflush(stdout);
    }
#ifdef HIPFAI_WITH_FEM
    fe.add(validation_fe_job(hip, options));
#endif
  }
#ifdef HIPFAI_WITH_FEM
  const std::vector<FeBatchEntry> done = fe.finish();
  std::vector<FeBatchEntry> by_hip(done.size());
  for (std::size_t k = 0; k < order.size(); ++k) by_hip[order[k]] = done[k];
  read_fe_entries(hips, by_hip, motion, options);
#endif
  write_steps_csv(hips, motion, options.out_dir / "steps.csv");
  write_timings_csv(hips, options, static_cast<int>(motion.steps.size()), options.out_dir / "timings.csv");
  ValidationResult result;
  for (const HipRun& run : hips) result.hips.push_back(run.timing);
  result.steps = static_cast<int>(motion.steps.size());
  result.fe_level = options.fe_level;
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace hipfai::studies
