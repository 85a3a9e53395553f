// hipfai — the radiographic measures of a right hip in 3D (see clinical_measures.h).
#include "anatomy/clinical_measures.h"

#include "core/error.h"
#include "core/literature.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace hipfai::anatomy {
namespace {

using geometry::Vec3;

// Contour sampling along the section segments and the neck's bins along the axis, mm: a tenth of
// the thinnest cortical feature that matters here, well under the 1 mm CT voxel.
constexpr double kContourStepMm = 0.25;
constexpr double kNeckBinMm = 0.5;
// The neck is searched from the head centre to this many head radii along the axis (the femoral
// neck is about one head diameter long; beyond it the intertrochanteric region widens).
constexpr double kNeckSearchRadii = 2.0;
// Alpha on a real head (clinical_measures.h): off the sphere beyond this many RMS residuals of the
// head's fit (3: 99.7 % of a normal scatter stays on it), gaps in the articular run up to 3 deg.
constexpr double kScatterRms = 3.0;
constexpr double kArticularGapDeg = 3.0;

std::string fixed(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.1f", value);
  return buffer;
}

}  // namespace

const char* morphology_name(Morphology morphology) {
  switch (morphology) {
    case Morphology::kNormal: return "normal";
    case Morphology::kCam: return "cam";
    case Morphology::kPincer: return "pincer";
    case Morphology::kCombined: return "combined";
    case Morphology::kDysplasia: return "dysplasia";
    case Morphology::kCamWithDysplasia: return "cam_with_dysplasia";
  }
  return "normal";
}

HeadNeckOffset measure_head_neck_offset(const geometry::TriMesh& femur, const Vec3& centre, double head_radius_mm,
                                        const Vec3& neck_axis, const Vec3& anterior) {
  HeadNeckOffset result;
  const Vec3 n = neck_axis.normalized();
  Vec3 u = anterior - anterior.dot(n) * n;
  if (u.norm() < 1e-9) {
    result.reason = "the anterior direction lies along the neck axis";
    return result;
  }
  u.normalize();
  const auto segments = geometry::plane_section(femur, centre, n.cross(u));
  const double reach = kNeckSearchRadii * head_radius_mm;
  const int bins = static_cast<int>(std::ceil(reach / kNeckBinMm));
  std::vector<double> outermost(bins, -std::numeric_limits<double>::infinity());
  double head = -std::numeric_limits<double>::infinity();
  auto visit = [&](const Vec3& p) {
    const double t = n.dot(p - centre), s = u.dot(p - centre);
    if (s <= 0.0) return;
    if (t <= 0.0 && t >= -head_radius_mm * 1.5) head = std::max(head, s);
    if (t >= 0.0 && t < reach) {
      const int bin = std::min(bins - 1, static_cast<int>(t / kNeckBinMm));
      outermost[bin] = std::max(outermost[bin], s);
    }
  };
  for (const auto& segment : segments) {
    const double length = (segment.b - segment.a).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(length / kContourStepMm)));
    for (int k = 0; k <= steps; ++k) visit(segment.a + (segment.b - segment.a) * (static_cast<double>(k) / steps));
  }
  if (!std::isfinite(head)) {
    result.reason = "no anterior head contour in Nötzli's plane";
    return result;
  }
  // The waist: the least outermost radius over the neck, past the head's equator.
  double waist = std::numeric_limits<double>::infinity();
  int waist_bin = -1;
  for (int b = 0; b < bins; ++b) {
    if (std::isfinite(outermost[b]) && outermost[b] < waist) {
      waist = outermost[b];
      waist_bin = b;
    }
  }
  if (waist_bin < 0) {
    result.reason = "no anterior neck contour in Nötzli's plane";
    return result;
  }
  result.measured = true;
  result.head_radius_mm = head;
  result.neck_radius_mm = waist;
  result.neck_waist_mm = (waist_bin + 0.5) * kNeckBinMm;
  result.offset_mm = head - waist;
  result.ratio = result.offset_mm / (2.0 * head_radius_mm);
  return result;
}

ClinicalMeasures measure_clinical(const ClinicalMeasuresRequest& request) {
  if (request.pelvis == nullptr || request.femur == nullptr || request.femur_landmarks == nullptr ||
      request.acetabulum == nullptr) {
    throw_error("clinical measures: pelvis, femur, femur landmarks and acetabulum are required");
  }
  const FemurLandmarks& femur = *request.femur_landmarks;
  const Acetabulum& acetabulum = *request.acetabulum;
  ClinicalMeasures m;
  m.lateral_ce = geometry::measure_ce_angle({request.pelvis}, request.hjc_mm, request.pelvis_frame.right,
                                            request.pelvis_frame.superior);
  if (m.lateral_ce.status != geometry::MeasureStatus::kOk) {
    throw_error("pelvis: no acetabular roof in the coronal plane through the femoral head (lateral CE)");
  }
  m.acetabular_inclination_deg = acetabulum.radiographic_inclination_deg;
  m.acetabular_version_deg = acetabulum.radiographic_anteversion_deg;
  m.acetabular_inclination_anatomic_deg = acetabulum.anatomic_inclination_deg;
  m.acetabular_version_anatomic_deg = acetabulum.anatomic_anteversion_deg;

  geometry::AlphaOptions alpha;
  alpha.head_centre_mm = femur.head_centre_mm;
  alpha.head_radius_mm = femur.head_radius_mm;
  alpha.articular_gap_deg = kArticularGapDeg;
  alpha.tolerance_mm = 0.0;
  // The automatic tolerance comes from the sphere and the mesh alone: one plane, no profile, is
  // enough to read it.
  geometry::AlphaOptions probe = alpha;
  probe.profile_step_deg = 0.0;
  probe.sector_end_deg = probe.sector_begin_deg;
  const geometry::AlphaMeasurement automatic =
      geometry::measure_alpha_angle({request.femur}, femur.head_centre_mm, femur.neck_axis, request.femur_frame.superior,
                                    request.femur_frame.anterior, probe);
  alpha.tolerance_mm = std::max(automatic.tolerance_mm, kScatterRms * femur.head_fit_rms_mm);
  m.alpha = geometry::measure_alpha_angle({request.femur}, femur.head_centre_mm, femur.neck_axis,
                                          request.femur_frame.superior, request.femur_frame.anterior, alpha);
  if (m.alpha.status != geometry::MeasureStatus::kOk) {
    throw_error("femur: no head-neck contour about the neck axis (alpha angle)");
  }
  m.head_neck_offset = measure_head_neck_offset(*request.femur, m.alpha.head_centre_mm, m.alpha.head_radius_mm,
                                                femur.neck_axis, request.femur_frame.anterior);
  m.neck_shaft_deg = femur.neck_shaft_angle_deg;
  m.femoral_version_deg = femur.version_deg;
  m.femoral_version_reason = femur.version_missing_reason;

  const double ce = m.lateral_ce.ce_deg;
  const bool dysplasia = ce < literature::kDysplasiaMaxLateralCeDeg;
  const bool pincer = ce > literature::kPincerMinLateralCeDeg;
  const bool cam = m.alpha.alpha_deg > literature::kCamMinAlphaDeg;
  if (dysplasia) m.findings.push_back("lateral CE " + fixed(ce) + " deg < " + fixed(literature::kDysplasiaMaxLateralCeDeg) + ": dysplasia (Tannast et al. 2007)");
  if (pincer) m.findings.push_back("lateral CE " + fixed(ce) + " deg > " + fixed(literature::kPincerMinLateralCeDeg) + ": over-coverage, pincer (Tannast et al. 2007)");
  if (cam) m.findings.push_back("alpha " + fixed(m.alpha.alpha_deg) + " deg > " + fixed(literature::kCamMinAlphaDeg) + " in Nötzli's plane: cam (Nötzli et al. 2002)");
  if (!cam && m.alpha.max_alpha_deg > literature::kCamMinAlphaDeg) {
    m.findings.push_back("alpha " + fixed(m.alpha.max_alpha_deg) + " deg at " + geometry::clock_label(m.alpha.max_plane_deg) +
                         ", outside Nötzli's plane: a cam it does not see");
  }
  if (m.head_neck_offset.measured && m.head_neck_offset.ratio < literature::kCamMaxHeadNeckOffsetRatio) {
    m.findings.push_back("head-neck offset ratio " + fixed(100.0 * m.head_neck_offset.ratio) + " % < " +
                         fixed(100.0 * literature::kCamMaxHeadNeckOffsetRatio) + " %: reduced offset (Beaulé et al. 2005)");
  }
  if (cam && pincer) m.morphology = Morphology::kCombined;
  else if (cam && dysplasia) m.morphology = Morphology::kCamWithDysplasia;
  else if (cam) m.morphology = Morphology::kCam;
  else if (pincer) m.morphology = Morphology::kPincer;
  else if (dysplasia) m.morphology = Morphology::kDysplasia;
  return m;
}

}  // namespace hipfai::anatomy
