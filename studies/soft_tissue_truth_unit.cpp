// hipfai — one hip of the soft-tissue known-truth study (see soft_tissue_truth_unit.h).
#include "studies/soft_tissue_truth_unit.h"

#include "anatomy/frame_file.h"
#include "core/literature.h"
#include "core/stopwatch.h"
#include "geometry/hip_generator.h"
#include "geometry/hip_model.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/penetration_run.h"
#include "studies/pipeline/soft_tissue_model.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/results/hip_fe_table.h"
#endif

#include <algorithm>
#include <cmath>
#include <fstream>

namespace hipfai::studies {
namespace {


PenetrationRun depths(const geometry::HipModel& model, const std::string& id, const Motion& motion, int threads,
                      double contact_tolerance_mm) {
  const LoadedHip hip =
      loaded_hip_from_model(model, id, {"femur_bone", "femoral_cartilage", "acetabular_cartilage", "labrum"});
  PenetrationOptions options;
  options.threads = threads;
  options.contact_tolerance_mm = contact_tolerance_mm;
  StageLog log;
  return compute_penetration(hip, motion, options, log);
}

}  // namespace

std::vector<std::pair<double, double>> soft_tissue_truth_grid(const SoftTissueTruthOptions& options) {
  if (!options.hips.empty()) return options.hips;
  return options.quick ? std::vector<std::pair<double, double>>{{20.0, 80.0}, {40.0, 40.0}} : study_grid_angles();
}

Motion soft_tissue_truth_motion(const SoftTissueTruthOptions& options) {
  return standing_to_sitting(options.quick ? 10 : options.sub_motions);
}

#ifdef HIPFAI_WITH_FEM
// Peaks of a finished FE run (its cache entry's fe.csv and timing.txt).
SoftTissueFePeaks soft_tissue_fe_peaks(const std::filesystem::path& entry) {
  const HipFeTable table = read_hip_fe_csv(entry / "fe.csv");
  SoftTissueFePeaks peaks;
  peaks.steps = static_cast<int>(table.steps.size());
  // The largest over the converged steps; 0 when none has a number (a tissue the run lacks).
  const auto peak_of = [&](const auto& value_of) {
    double peak = 0.0;
    for (const FeStepRecord& step : table.steps) {
      const double value = value_of(step);
      if (step.converged() && std::isfinite(value)) peak = std::max(peak, value);
    }
    return peak;
  };
  for (const FeStepRecord& step : table.steps) peaks.unconverged += !step.converged();
  peaks.pressure_mpa = peak_of([](const FeStepRecord& step) { return step.pressure(PressureStat::kMax); });
  peaks.ball_pressure_mpa = peak_of([](const FeStepRecord& step) { return step.pressure(PressureStat::kBall); });
  for (const FeTissue tissue : kFeTissues) {
    const auto t = static_cast<std::size_t>(tissue);
    peaks.von_mises_mpa[t] =
        peak_of([&](const FeStepRecord& step) { return step.von_mises(VonMisesStat::kMax, tissue); });
    peaks.ball_von_mises_mpa[t] =
        peak_of([&](const FeStepRecord& step) { return step.von_mises(VonMisesStat::kBall, tissue); });
  }
  std::ifstream timing(entry / "timing.txt");
  std::string word;
  if (!(timing >> word >> peaks.seconds)) peaks.seconds = 0.0;
  return peaks;
}

std::array<FeBatchJob, 2> soft_tissue_fe_jobs(const SoftTissueTruthRow& row, const SoftTissueTruthOptions& options,
                                              const Motion& motion) {
  std::array<FeBatchJob, 2> jobs;
  const char* which[2] = {"generated", "synthesised"};
  for (std::size_t k = 0; k < 2; ++k) {
    FeBatchJob& job = jobs[k];
    job.id = row.hip + " (" + which[k] + ")";
    job.run.model_dir = (options.out_dir / "hips" / row.hip / which[k]).string();
    job.run.steps = static_cast<int>(motion.steps.size());
    job.run.level = *options.fe_level;
    // The end pose's fields, as `study validate` keeps them: the two studies share cache entries.
    job.run.vtu_every = static_cast<unsigned int>(job.run.steps);
  }
  return jobs;
}
#endif


// One hip: generated (written to hips/<hip>/generated), stripped to its bones and its soft tissues
// synthesised (hips/<hip>/synthesised); the volumes, thicknesses and both maximum depths of each.
// Widens `tolerance_mm` to the contact tolerances used.
SoftTissueTruthRow compare_soft_tissue_hip(double ce, double alpha, const SoftTissueTruthOptions& options,
                                           const Motion& motion, double& tolerance_mm) {
  geometry::HipParameters p;
  p.ce_deg = ce;
  p.alpha_deg = alpha;
  p.edge_mm = options.quick ? 3.0 : options.edge_mm;
  const geometry::HipModel generated = geometry::generate_hip(p).model;
  SoftTissueTruthRow row;
  row.hip = parametric_hip_id(ce, alpha);
  const std::filesystem::path dir = options.out_dir / "hips" / row.hip;
  geometry::write_hip_model(generated, dir / "generated");

  SoftTissueModelRequest request;
  request.assessment.femur = &generated.tissue("femur_bone");
  request.assessment.pelvis = &generated.tissue("acetabular_bone");
  request.assessment.femur_name = "femur_bone";
  request.assessment.pelvis_name = "acetabular_bone";
  request.assessment.frame = anatomy::read_frame_file(dir / "generated" / "model.json");
  const auto t0 = SteadyClock::now();
  const SoftTissueModel synthesised = build_soft_tissue_model(request);
  row.synthesis_seconds = seconds_since(t0);
  write_soft_tissue_model(synthesised, "femur_bone (generated)", "acetabular_bone (generated)", dir / "synthesised");

  row.generated_femoral_cartilage_mm3 = geometry::signed_volume(generated.tissue("femoral_cartilage"));
  row.synthesised_femoral_cartilage_mm3 = geometry::signed_volume(synthesised.model.tissue("femoral_cartilage"));
  row.generated_acetabular_cartilage_mm3 = geometry::signed_volume(generated.tissue("acetabular_cartilage"));
  row.synthesised_acetabular_cartilage_mm3 = geometry::signed_volume(synthesised.model.tissue("acetabular_cartilage"));
  row.generated_labrum_mm3 = geometry::signed_volume(generated.tissue("labrum"));
  row.synthesised_labrum_mm3 = geometry::signed_volume(synthesised.model.tissue("labrum"));
  row.synthesised_femoral_mean_thickness_mm = synthesised.report.femoral.mean_thickness_mm;
  row.synthesised_acetabular_mean_thickness_mm = synthesised.report.acetabular.mean_thickness_mm;

  // Both with the generated hip's contact tolerance (its rule: the sagitta of the longest edge of
  // the tissues): the synthesised tissues have longer edges (the labrum's sweep, the layers' side
  // walls), and a tolerance computed from them would also move the striking region out past the
  // cam (R + tolerance), comparing the rule instead of the tissues.
  const PenetrationRun a = depths(generated, row.hip, motion, options.threads, -1.0);
  const PenetrationRun b =
      depths(synthesised.model, row.hip + "-synthesised", motion, options.threads, a.contact_tolerance_mm);
  row.generated_curvilinear_mm = a.max_curvilinear_mm();
  row.synthesised_curvilinear_mm = b.max_curvilinear_mm();
  row.generated_radial_mm = a.max_radial_mm();
  row.synthesised_radial_mm = b.max_radial_mm();
  tolerance_mm = std::max({tolerance_mm, a.contact_tolerance_mm, b.contact_tolerance_mm});
  return row;
}

}  // namespace hipfai::studies
