// hipfai — the patient-specific FAI assessment (see assessment.h for the pipeline).
#include "studies/pipeline/assessment.h"

#include "anatomy/mesh_boolean.h"
#include "anatomy/resection.h"
#include "core/error.h"
#include "core/stopwatch.h"

#include <cmath>
#include <cstdio>
#include <iostream>

namespace hipfai::studies {
namespace {

using geometry::Vec3;
using anatomy::AnatomicalFrame;
using anatomy::Side;

// Radial depths of a user motion count within this many head radii of the HJC
// (anatomy::MotionDepthsRequest::radial_reach_mm says why).
constexpr double kRadialReachHeadRadii = 2.0;

// One line per stage on stdout (errors alone go to stderr, one line), and the stage's time kept for the report.
class Stages {
 public:
  Stages(AssessmentResult& result, bool progress) : result_(result), progress_(progress) {}

  template <typename F>
  auto run(const std::string& name, F&& work) {
    if (progress_) {
      std::printf("assess: %s ...", name.c_str());
      std::fflush(stdout);
    }
    const auto start = SteadyClock::now();
    if constexpr (std::is_void_v<decltype(work())>) {
      work();
      finish(name, start);
    } else {
      auto value = work();
      finish(name, start);
      return value;
    }
  }

 private:
  void finish(const std::string& name, SteadyClock::time_point start) {
    const double seconds = seconds_since(start);
    result_.stage_seconds.emplace_back(name, seconds);
    if (progress_) std::printf(" %.2f s\n", seconds);
  }

  AssessmentResult& result_;
  bool progress_;
};

AnatomicalFrame mirror_frame(const AnatomicalFrame& frame, const Eigen::Affine3d& mirror) {
  AnatomicalFrame out;
  out.origin_mm = mirror * frame.origin_mm;
  out.anterior = mirror.linear() * frame.anterior;
  out.superior = mirror.linear() * frame.superior;
  out.right = -(mirror.linear() * frame.right);  // the mirror image's right is the original's left
  return out;
}

Vec3 perpendicular_part(const Vec3& v, const Vec3& axis) {
  const Vec3 p = v - v.dot(axis) * axis;
  return p.normalized();
}

// The femur frame of the working (right) hip: the landmarks' ISB frame when the distal femur is
// there, else superior along the shaft and right from the pelvis.
AnatomicalFrame femur_frame_of(const anatomy::FemurLandmarks& femur, const AnatomicalFrame& pelvis,
                               std::string& source) {
  if (femur.frame && femur.has_distal) {
    source = "found on the bone: mechanical axis and epicondyles (Wu et al. 2002)";
    return *femur.frame;
  }
  AnatomicalFrame frame;
  frame.origin_mm = femur.head_centre_mm;
  frame.superior = femur.shaft_axis.normalized();
  frame.right = perpendicular_part(pelvis.right, frame.superior);
  frame.anterior = frame.superior.cross(frame.right);
  source = "shaft axis found on the bone; rotation about it from the pelvis frame (no condyles)";
  return frame;
}

// The femoral head's clock face: about the neck axis, 3:00 towards the femur's anterior.
anatomy::ClockFace femoral_clock_face(const Vec3& head_centre, const Vec3& neck_axis, const AnatomicalFrame& femur) {
  return anatomy::make_clock_face(head_centre, neck_axis, femur.anterior, true);
}

anatomy::ClockFace acetabular_clock_face(const anatomy::Acetabulum& acetabulum) {
  anatomy::ClockFace face;
  face.centre_mm = acetabulum.centre_mm;
  face.axis = acetabulum.axis;
  face.anterior = acetabulum.clock_anterior;
  face.superior = acetabulum.clock_superior;
  return face;
}

geometry::TriMesh rotated_about(const geometry::TriMesh& mesh, const Eigen::Matrix3d& rotation, const Vec3& centre) {
  geometry::TriMesh out = mesh;
  for (Vec3& v : out.vertices) v = centre + rotation * (v - centre);
  return out;
}

// Measures and motions of one pair of bones (scanned-pose femur, pelvis).
AssessmentState evaluate(const AssessmentResult& r, const geometry::TriMesh& pelvis, const geometry::TriMesh& femur,
                         const anatomy::Acetabulum& acetabulum, int threads, geometry::TriMesh* femur_neutral) {
  AssessmentState state;
  anatomy::FemurLandmarks landmarks = r.femur_landmarks;
  landmarks.neck_axis = r.neck_axis;
  anatomy::ClinicalMeasuresRequest measures;
  measures.pelvis = &pelvis;
  measures.femur = &femur;
  measures.pelvis_frame = r.pelvis_frame;
  measures.femur_frame = r.femur_frame;
  measures.femur_landmarks = &landmarks;
  measures.acetabulum = &acetabulum;
  measures.hjc_mm = r.hjc_mm;
  state.measures = anatomy::measure_clinical(measures);

  *femur_neutral = rotated_about(femur, r.neutral_rotation, r.hjc_mm);
  anatomy::ClinicalRomRequest rom;
  rom.pelvis = &pelvis;
  rom.femur = femur_neutral;
  rom.hjc_mm = r.hjc_mm;
  rom.hip_axes = r.pelvis_frame.axes();
  rom.acetabulum = acetabular_clock_face(acetabulum);
  AnatomicalFrame femur_at_neutral = r.femur_frame;
  femur_at_neutral.anterior = r.neutral_rotation * r.femur_frame.anterior;
  femur_at_neutral.superior = r.neutral_rotation * r.femur_frame.superior;
  rom.femoral_head = femoral_clock_face(r.hjc_mm + r.neutral_rotation * (landmarks.head_centre_mm - r.hjc_mm),
                                        r.neutral_rotation * r.neck_axis, femur_at_neutral);
  rom.num_threads = threads;
  state.rom = anatomy::clinical_range_of_motion(rom);
  return state;
}

std::vector<std::pair<double, double>> nonzero_bins(const std::vector<anatomy::ClockBinVolume>& bins) {
  std::vector<std::pair<double, double>> out;
  for (const auto& b : bins) {
    if (b.removed_mm3 > 0.0) out.emplace_back(0.5 * (b.from_deg + b.to_deg), b.removed_mm3);
  }
  return out;
}

// What a resection did (anatomy::CamResection or anatomy::RimTrim) to the bone `after`.
template <typename Done>
ResectionSummary summary(const char* kind, double requested_deg, const anatomy::SelfIntersectionRepair& solid,
                         const Done& done, const geometry::TriMesh& after) {
  ResectionSummary s;
  s.kind = kind;
  s.requested_deg = requested_deg;
  s.repaired_pairs = solid.pairs_before;
  s.repaired_near_mm = solid.where_mm;
  s.removed_volume_mm3 = done.removed_volume_mm3;
  s.original_volume_mm3 = done.original_volume_mm3;
  s.closed = anatomy::is_closed(after);
  s.manifold = anatomy::is_manifold(after);
  s.removed_by_clock = nonzero_bins(done.removed_by_clock);
  s.seconds = done.seconds;
  return s;
}

}  // namespace

AnatomicalFrame AssessmentResult::frame_to_input(const AnatomicalFrame& frame) const {
  if (side == Side::kRight) return frame;
  return mirror_frame(frame, to_input);
}

namespace {

// The pelvis frame in the input's coordinates: given (--frame), or the anterior pelvic plane found
// on the bone with its landmarks.
struct InputPelvis {
  AnatomicalFrame frame;
  std::optional<anatomy::PelvisLandmarks> landmarks;
};

InputPelvis pelvis_in_input(const AssessmentRequest& request, const anatomy::UserFrame* given, const Vec3& hjc_input,
                            const Vec3& towards_head, Stages& stages, AssessmentResult& r) {
  InputPelvis pelvis;
  if (given && given->pelvis) {
    pelvis.frame = *given->pelvis;
    pelvis.frame.origin_mm = hjc_input;
    r.pelvis_frame_source = "given (--frame, " + given->source_kind + ")";
    return pelvis;
  }
  anatomy::PelvisLandmarksRequest pelvis_request;
  pelvis_request.pelvis = request.pelvis;
  pelvis_request.hjc_mm = hjc_input;
  pelvis_request.superior_hint = towards_head;
  pelvis_request.what = request.pelvis_name;
  pelvis.landmarks = stages.run("pelvis landmarks", [&] { return anatomy::find_pelvis_landmarks(pelvis_request); });
  pelvis.frame = pelvis.landmarks->frame;
  r.pelvis_frame_source = "found on the bone: anterior pelvic plane (Lewinnek et al. 1978; Kai et al. 2014)";
  return pelvis;
}

// --side, else the frame's, else the half of the pelvis holding the head, else the femur's; a
// side given against the bones' is an error.
void choose_side(AssessmentResult& r, const AssessmentRequest& request, const anatomy::UserFrame* given,
                 const InputPelvis& pelvis, const anatomy::FemurLandmarks& femur) {
  std::optional<Side> from_bones;
  if (pelvis.landmarks) from_bones = pelvis.landmarks->side;
  std::optional<Side> from_frame = given ? given->side : std::nullopt;
  r.side = request.side.value_or(from_frame.value_or(from_bones.value_or(femur.side.value_or(Side::kRight))));
  r.side_source = request.side ? "--side" : from_frame ? "--frame" : from_bones ? "the half of the pelvis holding the femoral head"
                  : femur.side ? "the femur (" + femur.side_method + ")" : "assumed right (nothing tells)";
  if (from_bones && *from_bones != r.side) {
    throw_error("assess: the hip is given as ", anatomy::side_name(r.side), " but the femoral head lies in the ",
                anatomy::side_name(*from_bones), " half of the pelvis");
  }
}

// A left hip mirrored into a right one through the pelvis' midsagittal plane: the bones, the pelvis
// frame and landmarks (right and left swapped), and the femur's landmarks found again.
void mirror_left_hip(AssessmentResult& r, InputPelvis& pelvis, const Vec3& hjc_input, geometry::TriMesh& femur_mesh,
                     anatomy::FemurLandmarksRequest& femur_request, anatomy::FemurLandmarks& femur, Stages& stages) {
  const Vec3 midline = pelvis.landmarks ? Vec3(0.5 * (pelvis.landmarks->asis_right_mm + pelvis.landmarks->asis_left_mm))
                                        : hjc_input;
  r.to_input = anatomy::reflection(midline, pelvis.frame.right);
  femur_mesh = anatomy::reflected(femur_mesh, r.to_input);
  r.pelvis = anatomy::reflected(r.pelvis, r.to_input);
  pelvis.frame = mirror_frame(pelvis.frame, r.to_input);
  if (pelvis.landmarks) {
    anatomy::PelvisLandmarks m = *pelvis.landmarks;
    m.asis_right_mm = r.to_input * pelvis.landmarks->asis_left_mm;
    m.asis_left_mm = r.to_input * pelvis.landmarks->asis_right_mm;
    m.pubic_tubercle_right_mm = r.to_input * pelvis.landmarks->pubic_tubercle_left_mm;
    m.pubic_tubercle_left_mm = r.to_input * pelvis.landmarks->pubic_tubercle_right_mm;
    m.frame = pelvis.frame;
    m.side = Side::kRight;
    pelvis.landmarks = m;
  }
  femur_request.femur = &femur_mesh;
  if (femur_request.head_centre_hint_mm) femur_request.head_centre_hint_mm = r.to_input * *femur_request.head_centre_hint_mm;
  femur_request.anterior_hint = pelvis.frame.anterior;
  femur = stages.run("femur landmarks (mirrored)", [&] { return anatomy::find_femur_landmarks(femur_request); });
}

// The femur frame (given, or found), the neck axis and the neutral rotation, in working coordinates.
void set_femur_frame(AssessmentResult& r, const anatomy::UserFrame* given, const anatomy::FemurLandmarks& femur) {
  if (given && given->femur) {
    r.femur_frame = r.side == Side::kLeft ? mirror_frame(*given->femur, r.to_input) : *given->femur;
    r.femur_frame_source = "given (--frame, " + given->source_kind + ")";
  } else {
    r.femur_frame = femur_frame_of(femur, r.pelvis_frame, r.femur_frame_source);
  }
  r.femur_frame.origin_mm = r.hjc_mm;
  r.femur_landmarks = femur;
  r.neck_axis = femur.neck_axis;
  r.neck_axis_source = "found on the bone";
  if (given && given->neck_axis) {
    r.neck_axis = (r.to_input.linear() * *given->neck_axis).normalized();
    r.neck_axis_source = "given (--frame)";
  }
  r.neutral_rotation = r.pelvis_frame.axes() * r.femur_frame.axes().transpose();
}

// Bone-to-bone depths over the user's motion, about the HJC in the hip frame.
anatomy::MotionDepths motion_depths(const AssessmentResult& r, const AssessmentRequest& request,
                                    const anatomy::FemurLandmarks& femur) {
  anatomy::MotionDepthsRequest depths;
  depths.pelvis = &r.pelvis;
  depths.femur = &r.femur_neutral;
  depths.hjc_mm = r.hjc_mm;
  depths.hip_axes = r.pelvis_frame.axes();
  depths.acetabulum = acetabular_clock_face(r.acetabulum);
  AnatomicalFrame femur_at_neutral = r.femur_frame;
  femur_at_neutral.anterior = r.neutral_rotation * r.femur_frame.anterior;
  femur_at_neutral.superior = r.neutral_rotation * r.femur_frame.superior;
  depths.femoral_head = femoral_clock_face(r.hjc_mm + r.neutral_rotation * (femur.head_centre_mm - r.hjc_mm),
                                           r.neutral_rotation * r.neck_axis, femur_at_neutral);
  for (const auto& step : request.motion->steps) depths.poses.push_back(step.pose);
  depths.num_threads = request.threads;
  depths.radial_reach_mm = kRadialReachHeadRadii * femur.head_radius_mm;
  return anatomy::bone_depths_over_motion(depths);
}

// Virtual osteochondroplasty down to --resect-alpha-deg; returns the resected femur.
geometry::TriMesh resect_cam(AssessmentResult& r, const AssessmentRequest& request,
                             const geometry::TriMesh& femur_mesh, Stages& stages) {
  const anatomy::SelfIntersectionRepair solid =
      stages.run("femur solid check", [&] { return anatomy::repair_self_intersections(femur_mesh, request.femur_name); });
  anatomy::CamResectionRequest cam;
  cam.femur = &solid.mesh;
  cam.head_centre_mm = r.before.measures.alpha.head_centre_mm;
  cam.head_radius_mm = r.before.measures.alpha.head_radius_mm;
  cam.neck_axis = r.neck_axis;
  cam.anterior = r.femur_frame.anterior;
  cam.superior = r.femur_frame.superior;
  cam.target_alpha_deg = *request.resect_alpha_deg;
  cam.tolerance_mm = r.before.measures.alpha.tolerance_mm;
  const anatomy::CamResection done = stages.run("cam resection", [&] { return anatomy::resect_cam(cam); });
  geometry::TriMesh femur_after = done.resected;
  r.resections.push_back(summary("cam", cam.target_alpha_deg, solid, done, femur_after));
  return femur_after;
}

// Virtual rim trimming by --trim-rim-deg; returns the trimmed pelvis.
geometry::TriMesh trim_rim(AssessmentResult& r, const AssessmentRequest& request, Stages& stages) {
  const anatomy::SelfIntersectionRepair solid =
      stages.run("pelvis solid check", [&] { return anatomy::repair_self_intersections(r.pelvis, request.pelvis_name); });
  anatomy::RimTrimRequest rim;
  rim.pelvis = &solid.mesh;
  rim.acetabular_centre_mm = r.acetabulum.centre_mm;
  rim.acetabular_radius_mm = r.acetabulum.radius_mm;
  rim.opening_axis = r.acetabulum.axis;
  rim.anterior = r.acetabulum.clock_anterior;
  rim.superior = r.acetabulum.clock_superior;
  for (const auto& p : r.acetabulum.rim) rim.rim.push_back({p.clock_deg, p.polar_deg});
  rim.trim_deg = *request.trim_rim_deg;
  const anatomy::RimTrim done = stages.run("rim trimming", [&] { return anatomy::trim_rim(rim); });
  geometry::TriMesh pelvis_after = done.trimmed;
  r.resections.push_back(summary("rim", rim.trim_deg, solid, done, pelvis_after));
  return pelvis_after;
}

// The resections asked for, then the measures and clinical motions again.
void resect(AssessmentResult& r, const AssessmentRequest& request, const geometry::TriMesh& femur_mesh, Stages& stages) {
  geometry::TriMesh femur_after = femur_mesh;
  geometry::TriMesh pelvis_after = r.pelvis;
  if (request.resect_alpha_deg) femur_after = resect_cam(r, request, femur_mesh, stages);
  if (request.trim_rim_deg) pelvis_after = trim_rim(r, request, stages);
  geometry::TriMesh femur_after_neutral;
  r.after = stages.run("measures and clinical motions after resection", [&] {
    return evaluate(r, pelvis_after, femur_after, r.acetabulum, request.threads, &femur_after_neutral);
  });
  r.pelvis_after = std::move(pelvis_after);
  r.femur_after_neutral = std::move(femur_after_neutral);
}

}  // namespace

AssessmentResult assess_hip(const AssessmentRequest& request) {
  if (request.femur == nullptr || request.pelvis == nullptr) throw_error("assess: a femur and a pelvis are required");
  geometry::validate_mesh(*request.femur, request.femur_name);
  geometry::validate_mesh(*request.pelvis, request.pelvis_name);
  const auto start = SteadyClock::now();
  AssessmentResult r;
  Stages stages(r, request.progress);
  const anatomy::UserFrame* given = request.frame ? &*request.frame : nullptr;

  // 1. Landmarks in the input's coordinates.
  anatomy::FemurLandmarksRequest femur_request;
  femur_request.femur = request.femur;
  femur_request.what = request.femur_name;
  if (given && given->hjc_mm) femur_request.head_centre_hint_mm = *given->hjc_mm;
  if (given && given->pelvis) femur_request.anterior_hint = given->pelvis->anterior;
  anatomy::FemurLandmarks femur = stages.run("femur landmarks", [&] { return anatomy::find_femur_landmarks(femur_request); });
  const Vec3 hjc_input = given && given->hjc_mm ? *given->hjc_mm : femur.head_centre_mm;
  const Vec3 towards_head =
      femur.mechanical_axis ? *femur.mechanical_axis : Vec3(femur.shaft_axis.normalized());
  InputPelvis pelvis = pelvis_in_input(request, given, hjc_input, towards_head, stages, r);

  // 2. Side; working coordinates.
  choose_side(r, request, given, pelvis, femur);
  geometry::TriMesh femur_mesh = *request.femur;
  r.pelvis = *request.pelvis;
  if (r.side == Side::kLeft) mirror_left_hip(r, pelvis, hjc_input, femur_mesh, femur_request, femur, stages);
  r.pelvis_landmarks = pelvis.landmarks;
  r.hjc_mm = r.to_input * hjc_input;
  pelvis.frame.origin_mm = r.hjc_mm;
  r.pelvis_frame = pelvis.frame;

  // 3. Femur frame.
  set_femur_frame(r, given, femur);

  // 4. Acetabulum.
  anatomy::AcetabulumRequest acetabulum_request;
  acetabulum_request.pelvis = &r.pelvis;
  acetabulum_request.head_centre_mm = femur.head_centre_mm;
  acetabulum_request.head_radius_mm = femur.head_radius_mm;
  acetabulum_request.pelvis_frame = r.pelvis_frame;
  acetabulum_request.what = request.pelvis_name;
  r.acetabulum = stages.run("acetabulum", [&] { return anatomy::find_acetabulum(acetabulum_request); });

  // 5. Measures and motions.
  r.before = stages.run("measures and clinical motions",
                        [&] { return evaluate(r, r.pelvis, femur_mesh, r.acetabulum, request.threads, &r.femur_neutral); });
  if (request.motion) {
    r.motion_name = request.motion->name;
    r.motion_depths = stages.run("motion depths", [&] { return motion_depths(r, request, femur); });
  }

  // 6. Resections.
  if (request.resect_alpha_deg || request.trim_rim_deg) resect(r, request, femur_mesh, stages);
  r.total_seconds = seconds_since(start);
  return r;
}

}  // namespace hipfai::studies
