// hipfai — the assessment against known truth (see assessment_truth.h).
#include "studies/assessment_truth.h"

#include "anatomy/frame_file.h"
#include "anatomy/side.h"
#include "core/literature.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "geometry/hip_generator.h"
#include "geometry/hip_measure.h"
#include "geometry/hip_model.h"
#include "studies/pipeline/assessment.h"
#include "studies/pipeline/hip_source.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace hipfai::studies {
namespace {

using geometry::Vec3;

Eigen::Affine3d random_motion(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.linear() = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
  t.translation() = Vec3(u(rng), u(rng), u(rng)) * 200.0;
  return t;
}

std::vector<double> measure_values(const AssessmentResult& r) {
  const auto& m = r.before.measures;
  return {m.lateral_ce.ce_deg, m.alpha.alpha_deg, m.alpha.max_alpha_deg, m.acetabular_inclination_deg,
          m.acetabular_version_deg, m.neck_shaft_deg};
}

std::vector<double> rom_values(const AssessmentResult& r) {
  std::vector<double> values;
  for (const auto* o : r.before.rom.motions()) values.push_back(o->limit ? o->limit->angle_deg : std::nan(""));
  return values;
}

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double largest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) != std::isnan(b[i])) return std::numeric_limits<double>::infinity();
    if (!std::isnan(a[i])) largest = std::max(largest, std::abs(a[i] - b[i]));
  }
  return largest;
}

AssessmentResult assess(const geometry::TriMesh& femur, const geometry::TriMesh& pelvis, const anatomy::UserFrame& frame) {
  AssessmentRequest request;
  request.femur = &femur;
  request.pelvis = &pelvis;
  request.frame = frame;
  return assess_hip(request);
}

}  // namespace

AssessmentTruthResult run_assessment_truth(const AssessmentTruthOptions& options) {
  const auto start = SteadyClock::now();
  AssessmentTruthResult result;
  result.options = options;
  const std::vector<std::pair<double, double>> grid =
      options.quick ? std::vector<std::pair<double, double>>{{20.0, 80.0}, {40.0, 40.0}} : study_grid_angles();
  const double edge = options.quick ? 3.0 : options.edge_mm;
  std::mt19937 rng(options.seed);
  ProgressBar progress("assessment known truth", grid.size());
  for (const auto& [ce, alpha] : grid) {
    geometry::HipParameters p;
    p.ce_deg = ce;
    p.alpha_deg = alpha;
    p.edge_mm = edge;
    const geometry::HipModel model = geometry::generate_hip(p).model;
    AssessmentTruthRow row;
    row.hip = parametric_hip_id(ce, alpha);
    const std::filesystem::path dir = options.out_dir / "hips" / row.hip;
    geometry::write_hip_model(model, dir);
    const anatomy::UserFrame frame = anatomy::read_frame_file(dir / "model.json");
    const geometry::TriMesh& femur = model.tissue("femur_bone");
    const geometry::TriMesh& pelvis = model.tissue("acetabular_bone");

    const auto t0 = SteadyClock::now();
    const AssessmentResult original = assess(femur, pelvis, frame);
    row.assess_seconds = seconds_since(t0);
    row.model_ce_deg = model.measured_ce_deg;
    row.model_alpha_deg = model.measured_alpha_notzli_deg;
    row.bone_alpha_reference_deg =
        geometry::measure_alpha_angle({&femur}, model.hjc_mm, model.neck_axis, model.superior, Vec3::UnitY()).alpha_deg;
    const auto& m = original.before.measures;
    row.measured_ce_deg = m.lateral_ce.ce_deg;
    row.measured_alpha_deg = m.alpha.alpha_deg;
    row.measured_alpha_max_deg = m.alpha.max_alpha_deg;
    row.acetabular_inclination_deg = m.acetabular_inclination_deg;
    row.acetabular_version_deg = m.acetabular_version_deg;
    const auto& fadir = original.before.rom.fadir_internal_rotation;
    row.fadir_internal_rotation_deg = fadir.limit ? fadir.limit->angle_deg : std::nan("");

    for (const bool mirrored : {false, true}) {
      Eigen::Affine3d t = random_motion(rng);
      if (mirrored) t = t * anatomy::reflection(Vec3::Zero(), Vec3::UnitX());
      const AssessmentResult again =
          assess(anatomy::transformed(femur, t), anatomy::transformed(pelvis, t), anatomy::transformed(frame, t));
      const double measures = largest_difference(measure_values(again), measure_values(original));
      const double rom = largest_difference(rom_values(again), rom_values(original));
      if (mirrored) {
        row.mirrored_measure_diff_deg = measures;
        row.mirrored_rom_diff_deg = rom;
        row.mirrored_side_left = again.side == anatomy::Side::kLeft;
      } else {
        row.moved_measure_diff_deg = measures;
        row.moved_rom_diff_deg = rom;
      }
    }
    result.rows.push_back(row);
    progress.advance();
  }
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace hipfai::studies
