// hipfai — a hip model folder from segmented bones with synthesised soft tissues (see
// soft_tissue_model.h).
#include "studies/pipeline/soft_tissue_model.h"

#include "studies/reports/svg_plot.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "geometry/hip_frame.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hipfai::studies {
namespace {

using geometry::TriMesh;
using geometry::Vec3;

// p -> axes^T (p - origin): working coordinates into the hip frame.
TriMesh to_hip_frame(const TriMesh& mesh, const Eigen::Matrix3d& axes, const Vec3& origin) {
  TriMesh out = mesh;
  for (Vec3& v : out.vertices) v = axes.transpose() * (v - origin);
  return out;
}

}  // namespace

SoftTissueModel build_soft_tissue_model(const SoftTissueModelRequest& request) {
  const auto start = SteadyClock::now();
  AssessmentRequest assessment = request.assessment;
  assessment.motion.reset();
  assessment.resect_alpha_deg.reset();
  assessment.trim_rim_deg.reset();
  assessment.progress = false;
  const AssessmentResult r = assess_hip(assessment);
  const double assessment_seconds = seconds_since(start);
  SoftTissueModel out = soft_tissue_model_from(r, request.options, assessment.femur_name, assessment.pelvis_name);
  out.assessment_seconds = assessment_seconds;
  out.total_seconds = seconds_since(start);
  return out;
}

SoftTissueModel soft_tissue_model_from(const AssessmentResult& r, const anatomy::SoftTissueOptions& options,
                                       const std::string& femur_name, const std::string& pelvis_name) {
  const auto start = SteadyClock::now();
  SoftTissueModel out;
  out.side = r.side;
  out.side_source = r.side_source;
  out.pelvis_frame_source = r.pelvis_frame_source;
  out.hjc_input_mm = r.point_to_input(r.hjc_mm);
  out.head_radius_mm = r.femur_landmarks.head_radius_mm;
  out.lunate_radius_mm = r.acetabulum.radius_mm;
  out.assessment_seconds = r.total_seconds;

  // The femur at neutral: its head centre moved with it about the HJC.
  anatomy::SoftTissueRequest tissues;
  tissues.femur = &r.femur_neutral;
  tissues.pelvis = &r.pelvis;
  tissues.femur_name = femur_name;
  tissues.pelvis_name = pelvis_name;
  tissues.head_centre_mm = r.hjc_mm + r.neutral_rotation * (r.femur_landmarks.head_centre_mm - r.hjc_mm);
  tissues.joint_centre_mm = r.hjc_mm;
  // The head ends where the assessment's alpha profile says (the femur turned to neutral).
  const geometry::AlphaMeasurement& measured_alpha = r.before.measures.alpha;
  tissues.neck_axis = r.neutral_rotation * r.neck_axis;
  for (std::size_t k = 0; k < measured_alpha.profile.size() && k < measured_alpha.profile_directions.size(); ++k) {
    tissues.head_neck_junction.emplace_back(r.neutral_rotation * measured_alpha.profile_directions[k],
                                            measured_alpha.profile[k].second);
  }
  tissues.head_radius_mm = r.femur_landmarks.head_radius_mm;
  tissues.head_fit_rms_mm = r.femur_landmarks.head_fit_rms_mm;
  tissues.acetabulum = &r.acetabulum;
  tissues.options = options;
  anatomy::SoftTissues made = anatomy::synthesise_soft_tissues(tissues);
  out.report = made.report;
  out.options = options;

  // The hip frame: origin the HJC, axes the pelvis frame (orthonormalised: the frame's axes are
  // unit and perpendicular to rounding; the reader checks unit axes).
  const Eigen::Matrix3d given = r.pelvis_frame.axes();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(given, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d axes = svd.matrixU() * svd.matrixV().transpose();
  geometry::HipModel& m = out.model;
  m.tissues["femur_bone"] = to_hip_frame(r.femur_neutral, axes, r.hjc_mm);
  m.tissues["acetabular_bone"] = to_hip_frame(r.pelvis, axes, r.hjc_mm);
  m.tissues["femoral_cartilage"] = to_hip_frame(made.femoral_cartilage, axes, r.hjc_mm);
  m.tissues["acetabular_cartilage"] = to_hip_frame(made.acetabular_cartilage, axes, r.hjc_mm);
  m.tissues["labrum"] = to_hip_frame(made.labrum, axes, r.hjc_mm);
  m.hjc_mm = Vec3::Zero();
  m.soft_tissue = geometry::SoftTissueSource::kSynthesised;
  m.lateral = Vec3::UnitX();
  m.superior = Vec3::UnitZ();
  m.neck_axis = (axes.transpose() * r.neutral_rotation * r.neck_axis).normalized();
  m.acetabular_axis = (axes.transpose() * r.acetabulum.axis).normalized();
  double polar = 0.0;
  int kept = 0;
  for (const auto& p : r.acetabulum.rim) {
    if (!p.in_plane_fit) continue;
    polar += p.polar_deg;
    ++kept;
  }
  if (kept > 0) m.socket_opening_deg = polar / kept;
  const anatomy::ClinicalMeasures& measures = r.before.measures;
  m.measured_ce_deg = measures.lateral_ce.ce_deg;
  m.measured_alpha_notzli_deg = measures.alpha.alpha_deg;
  m.measured_alpha_max_deg = measures.alpha.max_alpha_deg;
  m.measured_alpha_max_clock_deg = measures.alpha.max_plane_deg;
  for (const auto& [clock, alpha] : measures.alpha.profile) {
    if (std::isfinite(alpha)) m.alpha_profile.emplace_back(clock, alpha);
  }
  geometry::HipParameters& p = m.parameters;
  p.ce_deg = std::clamp(measures.lateral_ce.ce_deg, 0.0, 45.0);
  p.alpha_deg = std::clamp(measures.alpha.alpha_deg, 35.0, 90.0);
  // The common articular sphere of the synthesised layers (anatomy/soft_tissue.h): the studies'
  // striking region and contact tolerance are measured from it.
  p.articular_radius_mm = std::clamp(out.report.articular_radius_mm, 20.0, 30.0);
  p.femoral_cartilage_mm = options.femoral_max_thickness_mm;
  p.acetabular_cartilage_mm = options.acetabular_thickness_mm;
  p.labrum_height_mm = options.labrum_height_mm;
  p.labrum_base_mm = options.labrum_base_mm;
  p.edge_mm = std::clamp(geometry::mean_edge_length(r.femur_neutral), 0.2, 10.0);
  out.total_seconds = out.assessment_seconds + seconds_since(start);
  return out;
}

void write_soft_tissue_model(const SoftTissueModel& result, const std::string& femur_path,
                             const std::string& pelvis_path, const std::filesystem::path& dir) {
  AtomicDirectory staging(dir);
  geometry::write_hip_model(result.model, staging.partial_path(), "ply");
  const anatomy::SoftTissueReport& t = result.report;
  const anatomy::SoftTissueOptions& defaults = result.options;
  std::ostringstream md;
  md.setf(std::ios::fixed);
  md.precision(2);
  const auto layer = [&](const char* name, const anatomy::LayerReport& l) {
    md << "| " << name << " | " << l.covered_area_mm2 << " | " << l.mean_thickness_mm << " | " << l.min_thickness_mm
       << " | " << l.max_thickness_mm << " | " << l.volume_mm3 << " | " << l.articular_area_mm2 << " ("
       << (l.covered_area_mm2 > 0.0 ? 100.0 * l.articular_area_mm2 / l.covered_area_mm2 : 0.0) << " %) | "
       << l.overlap_area_mm2 << " |\n";
  };
  md << "# Soft tissues synthesised on segmented bones\n\n"
     << "Femur `" << femur_path << "`, pelvis `" << pelvis_path << "`: a " << anatomy::side_name(result.side)
     << " hip (" << result.side_source << ")"
     << (result.side == anatomy::Side::kLeft ? "; this folder holds its MIRROR IMAGE, a right hip (the hip frame and "
                                              "every hipfai hip model are right hips)" : "")
     << ". Pelvis frame: " << result.pelvis_frame_source << ". HJC in the input's coordinates: ["
     << result.hjc_input_mm.x() << ", " << result.hjc_input_mm.y() << ", " << result.hjc_input_mm.z()
     << "] mm; the model is in the hip frame (origin the HJC, +X lateral, +Y anterior, +Z superior), the femur at "
        "its neutral pose.\n\n"
     << "Femoral head sphere radius " << result.head_radius_mm << " mm; lunate sphere radius " << result.lunate_radius_mm
     << " mm. Measured CE " << result.model.measured_ce_deg << " deg, alpha (Nötzli plane) "
     << result.model.measured_alpha_notzli_deg << " deg (model.json \"measured\").\n\n"
     << "| layer | covered area (mm^2) | mean thickness (mm) | min | max | volume (mm^3) | on the articular sphere (mm^2) | "
        "bone within the minimum of the sphere (mm^2) |\n|---|---|---|---|---|---|---|---|\n";
  layer("femoral cartilage", t.femoral);
  layer("acetabular cartilage", t.acetabular);
  md << "\nLabrum: " << t.labrum_volume_mm3 << " mm^3, " << t.labrum_sections << " of " << t.labrum_sections_total
     << " sections (" << t.labrum_missing_rim << " without rim: the notch; " << t.labrum_dropped_femur
     << " over the femur; " << t.labrum_dropped_pelvis << " not clear of the pelvis), " << t.labrum_pieces
     << (t.labrum_closed_ring ? " closed ring" : " open piece(s) with end caps") << ".\n\n"
     << "Method (anatomy/soft_tissue.h): layers extruded radially about the HJC from the femoral head region "
        "(up to the head-neck junction of the alpha profile) and the lunate surface. The two articular surfaces "
        "are one sphere about the HJC (the thesis' model; sphericity < 0.1 mm, Macirowski et al. 1994), radius "
     << t.articular_radius_mm << " mm: it splits the bone-to-bone gap in the ratio of the literature thicknesses ("
     << defaults.femoral_max_thickness_mm << " mm femoral at its thickest, " << defaults.acetabular_thickness_mm
     << " mm acetabular) where the femoral cartilage is thickest. The acetabular cartilage fills the lunate bone to "
        "the sphere, the femoral cartilage the whole head region to the sphere (congruent in every pose); no layer "
        "under "
     << defaults.min_thickness_mm << " mm. Labrum: base " << defaults.labrum_base_mm << " mm on the rim, tip "
     << defaults.labrum_height_mm << " mm above it, swept along the rim.\n\n"
     << "Time: " << result.total_seconds << " s (assessment " << result.assessment_seconds << " s, tissues "
     << t.seconds << " s).\n\n"
     << "![acetabulum](acetabular_side.svg) ![femoral head](femoral_side.svg)\n";
  write_file_atomically(staging.partial_path() / "soft_tissue.md", md.str());
  // Pictures, coloured by cartilage thickness: the socket's cartilage and the labrum (grey) seen
  // from lateral, the head's cartilage seen from medial.
  const auto& m = result.model;
  const double top = std::max(t.femoral.max_thickness_mm, t.acetabular.max_thickness_mm);
  write_mesh_svg({&m.tissue("acetabular_cartilage"), &m.tissue("labrum")}, "thickness_mm",
                 top, -geometry::Vec3::UnitX(), geometry::Vec3::UnitZ(),
                 "Acetabular cartilage thickness (mm) and labrum, seen from lateral",
                 staging.partial_path() / "acetabular_side.svg");
  write_mesh_svg({&m.tissue("femoral_cartilage")}, "thickness_mm", top, geometry::Vec3::UnitX(),
                 geometry::Vec3::UnitZ(), "Femoral cartilage thickness (mm), seen from medial",
                 staging.partial_path() / "femoral_side.svg");
  staging.commit([](const std::filesystem::path&) { return false; });
}

}  // namespace hipfai::studies
