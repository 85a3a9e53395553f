#include "studies/validation_hip.h"

#include "core/error.h"
#include "core/stopwatch.h"
#include "geometry/mesh_io.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/penetration_run.h"
#include "studies/pipeline/scene.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/results/hip_fe_table.h"
#endif

#include <fstream>
#include <map>

namespace hipfai::studies {
namespace {

// The hip of thesis Figs. 60-61 (CE 40 / alpha 60).
constexpr double kFigureCe = 40.0, kFigureAlpha = 60.0;

bool is_figure_hip(double ce, double alpha) { return ce == kFigureCe && alpha == kFigureAlpha; }

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

}  // namespace

ValidationHip run_validation_penetration(double ce, double alpha, const Motion& motion,
                                         const ValidationOptions& options, int threads) {
  ValidationHip run;
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
  StageLog log;
  const auto start = SteadyClock::now();
  const LoadedHip hip = acquire_hip(scene, scene.tissues, options.cache_dir, log);
  run.id = hip.id;
  run.dir = hip.dir;
  run.timing.generate_s = log.executed_count(StageKind::kGenerateHip) > 0 ? seconds_since(start) : 0.0;
  PenetrationOptions penetration;
  penetration.threads = threads;
  penetration.cache_dir = options.cache_dir;
  StepObserver observer;
  if (is_figure_hip(ce, alpha)) {
    observer = [&](std::size_t step, const DepthFields& fields) {
      if (step + 1 == motion.steps.size()) {
        write_end_pose_vtp(hip, motion.steps.back(), fields, options.out_dir / "fig61");
      }
    };
  }
  const PenetrationRun depths = compute_penetration(hip, motion, penetration, log, observer);
  run.timing.penetration_tables_ms = depths.curvilinear_preprocessing_ms + depths.radial_preprocessing_ms;
  for (const StepPenetration& step : depths.steps) {
    run.timing.penetration_query_ms += step.curvilinear_ms + step.radial_ms;
    run.curvilinear_max_mm.push_back(step.curvilinear_max_mm());
    run.radial_max_mm.push_back(step.radial_max_mm());
  }
  return run;
}

#ifdef HIPFAI_WITH_FEM

FeBatchJob validation_fe_job(const ValidationHip& hip, const ValidationOptions& options) {
  FeBatchJob job;
  job.id = hip.id;
  job.run.model_dir = hip.dir.string();
  job.run.steps = options.sub_motions;
  job.run.level = options.fe_level;
  if (options.body_weight_n > 0) job.run.body_weight_n = options.body_weight_n;
  job.run.vtu_every = static_cast<unsigned int>(options.sub_motions);  // the end pose only
  return job;
}

void read_validation_fe_entry(ValidationHip& hip, const FeBatchEntry& done, const Motion& motion,
                              const ValidationOptions& options) {
  hip.timing.fe_reused = done.reused;
  const std::filesystem::path& entry = done.entry;
  const HipFeTable table = read_hip_fe_csv(entry / "fe.csv");
  hip.fe = validation_fe_measures_of(table, motion.steps.size(), entry / "fe.csv");
  for (const FeStepRecord& step : table.steps) {
    hip.timing.fe_step_s += step.wall_time_s;
    hip.timing.fe_steps_failed += !step.converged();
  }
  hip.timing.fe_dofs = table.steps.empty() ? 0.0 : table.steps.front().dofs;
  std::ifstream timing(entry / "timing.txt");
  std::string word;
  if (timing >> word >> hip.timing.fe_s; !timing) hip.timing.fe_s = hip.timing.fe_step_s;
  // The end pose of the figure's hip: the FE fields beside the depths.
  if (is_figure_hip(hip.ce, hip.alpha)) {
    const std::filesystem::path vtu = entry / ("fe_" + std::to_string(motion.steps.size()) + ".vtu");
    if (std::filesystem::exists(vtu)) {
      std::filesystem::create_directories(options.out_dir / "fig61");
      std::filesystem::copy_file(vtu, options.out_dir / "fig61" / "fe.vtu",
                                 std::filesystem::copy_options::overwrite_existing);
    }
  }
}

#endif  // HIPFAI_WITH_FEM

}  // namespace hipfai::studies
