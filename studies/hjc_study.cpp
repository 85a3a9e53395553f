#include "studies/hjc_study.h"

#include "contact/range_finder.h"
#include "core/error.h"
#include "core/literature.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "geometry/hip_generator.h"
#include "geometry/mesh_io.h"
#include "studies/hjc_cohort.h"
#include "studies/hjc_study_report.h"
#include "studies/pipeline/penetration_run.h"
#include "studies/pipeline/segmented_hip.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/hjc_ranks.h"
#endif

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <tuple>

namespace hipfai::studies {
namespace {

using geometry::Vec3;

// ---- bones-only mode ---------------------------------------------------------------------------

// (rotation name, axis index, anticlockwise?) for a right hip: flexion +X, adduction +Y, IR +Z.
const std::vector<std::tuple<std::string, int, bool>>& bone_directions() {
  static const std::vector<std::tuple<std::string, int, bool>> directions{
      {"flexion", 0, true}, {"extension", 0, false}, {"internal_rotation", 2, true},
      {"external_rotation", 2, false}, {"adduction", 1, true}, {"abduction", 1, false}};
  return directions;
}

// Where the first contact is: within the head's radius + 4 mm of the centre it is the head
// meeting its own socket (h), farther out the neck or trochanter meeting the rim (r).
std::string contact_site(const geometry::TriMesh& mobile, const geometry::TriMesh& pelvis,
                         const contact::LimitingContact& limit, const Vec3& centre, double head_radius) {
  Vec3 p = Vec3::Zero();
  switch (limit.kind) {
    case contact::ContactKind::kMobileVertexOnFixedTriangle: p = mobile.vertices[static_cast<std::size_t>(limit.vertex)]; break;
    case contact::ContactKind::kFixedVertexOnMobileTriangle: p = pelvis.vertices[static_cast<std::size_t>(limit.vertex)]; break;
    case contact::ContactKind::kEdgeOnEdge: p = mobile.vertices[static_cast<std::size_t>(limit.mobile_edge[0])]; break;
    case contact::ContactKind::kNone: return "-";
  }
  return (p - centre).norm() < head_radius + 4.0 ? "h" : "r";
}

// The exact range of motion of one femur about each method's centre and the frame's axes.
HjcBonesVariant bones_range_of_motion(const std::string& name, const geometry::TriMesh& mobile,
                                      const geometry::TriMesh& pelvis, const HjcBonesResult& bones,
                                      double head_radius, ProgressBar& progress) {
  HjcBonesVariant variant{name, {}, {}};
  for (const auto& m : bones.hjc.methods) {
    for (int a = 0; a < 3; ++a) {
      const contact::RangeOfMotion range = contact::range_of_motion(pelvis, mobile, m.center_mm, bones.frame.col(a));
      if (range.status == contact::QueryStatus::kInvalidInput) throw_error("study hjc: range of motion: ", range.message);
      for (const auto& [rotation, index, anticlockwise] : bone_directions()) {
        if (index != a) continue;
        variant.rom_deg[m.name][rotation] = anticlockwise ? range.anticlockwise_deg : range.clockwise_deg;
        variant.site[m.name][rotation] = contact_site(
            mobile, pelvis, anticlockwise ? range.anticlockwise_limit : range.clockwise_limit, m.center_mm, head_radius);
      }
      progress.advance();
    }
  }
  return variant;
}

HjcStudyResult compute_bones(const HjcStudyOptions& options) {
  HjcStudyResult result;
  result.options = options;
  const geometry::TriMesh femur = geometry::read_mesh(options.femur);
  const geometry::TriMesh pelvis = geometry::read_mesh(options.pelvis);
  geometry::HjcRequest request;
  request.femur = &femur;
  request.pelvis = &pelvis;
  request.femur_name = options.femur.string();
  request.pelvis_name = options.pelvis.string();
  HjcBonesResult& bones = result.bones;
  bones.hjc = geometry::estimate_hjc(request);

  // Approximate hip frame from the bones (hjc_study.h), about the fitted head.
  const geometry::HjcMethodResult& head = bones.hjc.method("femoralheadsphere");
  bones.frame = approximate_hip_frame(femur, pelvis, head.center_mm);
  // Second femur: the head removed (triangles with a corner within the head radius + 1.5 mm of the
  // femoralheadsphere centre), so that only the neck and trochanter can meet the pelvis: the
  // impingement range of motion of bony ROM simulations, which let the head turn in its socket.
  const Vec3 head_centre = head.center_mm;
  const double head_radius = head.radius_mm;
  const geometry::TriMesh headless = geometry::submesh_where(
      femur, [&](const Vec3& p) { return (p - head_centre).norm() > head_radius + 1.5; });
  const std::vector<std::pair<std::string, const geometry::TriMesh*>> variants{{"whole femur", &femur},
                                                                               {"head removed", &headless}};
  ProgressBar progress("hjc bones rom", bones.hjc.methods.size() * 3 * variants.size(), options.progress);
  for (const auto& [name, mobile] : variants) {
    bones.variants.push_back(bones_range_of_motion(name, *mobile, pelvis, bones, head_radius, progress));
  }
  progress.finish();
  const HjcBonesVariant& impingement = bones.variants.back();
  for (const auto& m : bones.hjc.methods) {
    for (int a = 0; a < 3; ++a) {
      for (const auto& [rotation, index, anticlockwise] : bone_directions()) {
        if (index == a) result.rom.push_back({m.name, rotation, impingement.rom_deg.at(m.name).at(rotation)});
      }
    }
  }
  return result;
}

// ---- generated subjects ------------------------------------------------------------------------

// The subject's centres: five methods on its "segmented" articular surfaces, the truth and the
// truth's offsets; returns their labels in the order the depths are computed.
std::vector<std::string> place_centres(HjcSubjectResult& subject, const geometry::HipModel& model,
                                       const HjcStudyOptions& options, unsigned seed) {
  geometry::TriMesh head = model.tissue("femoral_cartilage");
  geometry::TriMesh socket = model.tissue("acetabular_cartilage");
  perturb_like_segmentation(head, socket, model, kHjcSegmentationNoiseMm, kHjcSegmentationAsphericityMm,
                            kHjcSegmentationUnevenGapMm, seed);
  geometry::HjcRequest request;
  request.femur = &head;
  request.pelvis = &socket;
  request.femur_long_axis = model.superior;
  request.femur_name = subject.id + " femoral_cartilage";
  request.pelvis_name = subject.id + " acetabular_cartilage";
  const geometry::HjcResult hjc = geometry::estimate_hjc(request);
  std::vector<std::string> labels;
  for (const auto& m : hjc.methods) {
    if (!m.ok) throw_error("study hjc: ", subject.id, ": ", m.name, " failed: ", m.message);
    subject.centres_mm[m.name] = m.center_mm;
    labels.push_back(m.name);
  }
  subject.centres_mm["truth"] = model.hjc_mm;
  labels.push_back("truth");
  Eigen::Matrix3d frame;
  frame << model.axes.flexion_axis, model.axes.adduction_axis, model.axes.internal_rotation_axis;
  for (const double offset : options.centre_offsets_mm) {
    for (const auto& [name, direction] : hjc_offset_directions()) {
      const std::string label = hjc_offset_label(name, offset);
      subject.centres_mm[label] = model.hjc_mm + offset * (frame * direction);
      labels.push_back(label);
    }
  }
  return labels;
}

// Maximum depths per step of the six rotations about each centre.
void rotate_about_centres(HjcSubjectResult& subject, const geometry::HipModel& model,
                          const std::vector<std::string>& labels, const HjcStudyOptions& options,
                          ProgressBar& progress) {
  LoadedHip hip = loaded_hip_from_model(model, subject.id, {"femur_bone", "femoral_cartilage", "acetabular_cartilage", "labrum"});
  PenetrationOptions penetration;
  penetration.threads = options.threads;
  StageLog log;
  for (const auto& label : labels) {
    hip.hjc_mm = subject.centres_mm[label];
    for (const auto& [rotation, amplitude] : hjc_study_rotations()) {
      const int steps = std::max(1, static_cast<int>(std::lround(amplitude / options.step_deg)));
      const Motion motion = medical_rotation(rotation, amplitude, steps);
      const PenetrationRun run = compute_penetration(hip, motion, penetration, log);
      HjcRotationDepths& d = subject.depths[label][rotation];
      for (std::size_t k = 0; k < run.steps.size(); ++k) {
        d.angle_deg.push_back(amplitude * static_cast<double>(k + 1) / steps);
        d.curvilinear_mm.push_back(run.steps[k].curvilinear_max_mm());
        d.radial_mm.push_back(run.steps[k].radial_max_mm());
      }
      progress.advance();
    }
  }
}

}  // namespace

HjcSubjectResult compute_hjc_subject(const HjcStudyOptions& options, std::size_t si, ProgressBar& progress) {
  const auto [ce, alpha] = options.subjects[si];
  geometry::HipParameters parameters;
  parameters.ce_deg = ce;
  parameters.alpha_deg = alpha;
  parameters.edge_mm = options.edge_mm;
  const geometry::HipModel model = geometry::generate_hip(parameters).model;
  HjcSubjectResult subject;
  char id[48];
  std::snprintf(id, sizeof(id), "ce%.0f_alpha%.0f", ce, alpha);
  subject.id = id;
  subject.true_centre_mm = model.hjc_mm;
  const std::vector<std::string> labels = place_centres(subject, model, options, 4242u + static_cast<unsigned>(si));
  rotate_about_centres(subject, model, labels, options, progress);
  return subject;
}

const std::vector<std::pair<std::string, double>>& hjc_study_rotations() {
  static const std::vector<std::pair<std::string, double>> rotations{
      {"flexion", literature::kAaosFlexionDeg},
      {"extension", literature::kAaosExtensionDeg},
      {"internal_rotation", literature::kAaosInternalRotationDeg},
      {"external_rotation", literature::kAaosExternalRotationDeg},
      {"adduction", literature::kAaosAdductionDeg},
      {"abduction", literature::kAaosAbductionDeg}};
  return rotations;
}

const std::array<std::pair<const char*, Eigen::Vector3d>, 6>& hjc_offset_directions() {
  static const std::array<std::pair<const char*, Vec3>, 6> directions{
      {{"+X", Vec3::UnitX()}, {"-X", -Vec3::UnitX()}, {"+Y", Vec3::UnitY()}, {"-Y", -Vec3::UnitY()},
       {"+Z", Vec3::UnitZ()}, {"-Z", -Vec3::UnitZ()}}};
  return directions;
}

std::string hjc_offset_label(const char* direction, double offset_mm) {
  char millimetres[64];
  std::snprintf(millimetres, sizeof(millimetres), "%.0f", offset_mm);
  return "truth " + std::string(direction) + " " + millimetres + "mm";
}

HjcStudyResult compute_hjc_study(const HjcStudyOptions& options) {
#ifdef HIPFAI_WITH_FEM
  const bool over_ranks = options.spread == UnitSpread::kMpiRanks && join_mpi_world().size > 1;
#else
  const bool over_ranks = false;
#endif
  if (!options.femur.empty() || !options.pelvis.empty()) {
    if (options.femur.empty() || options.pelvis.empty()) throw_error("study hjc: bones-only mode needs both a femur and a pelvis");
#ifdef HIPFAI_WITH_FEM
    // One hip: rank 0 computes it, the other ranks have nothing to do.
    if (over_ranks && join_mpi_world().rank != 0) {
      HjcStudyResult nothing;
      nothing.holds_results = false;
      return nothing;
    }
#endif
    return compute_bones(options);
  }
  if (options.subjects.empty()) throw_error("study hjc: no subjects");
  HjcStudyResult result;
  result.options = options;
#ifdef HIPFAI_WITH_FEM
  if (over_ranks) {
    HjcRankRun ranks = run_hjc_subjects_over_ranks(options);
    result.holds_results = ranks.holds_results;
    result.subjects = std::move(ranks.subjects);
    result.failed = std::move(ranks.failed);
    return result;
  }
#endif
  const std::size_t centres_per_subject = geometry::hjc_method_names().size() + 1 +
                                          options.centre_offsets_mm.size() * hjc_offset_directions().size();
  ProgressBar progress("hjc study", options.subjects.size() * centres_per_subject * hjc_study_rotations().size(),
                       options.progress);
  for (std::size_t si = 0; si < options.subjects.size(); ++si) {
    result.subjects.push_back(compute_hjc_subject(options, si, progress));
  }
  progress.finish();
  return result;
}

HjcStudyResult run_hjc_study(const HjcStudyOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  HjcStudyResult result = compute_hjc_study(options);
  // Nothing to write on the ranks other than 0, nor when every subject of a spread study failed.
  if (!result.holds_results || (result.subjects.empty() && !result.failed.empty())) return result;
  result.report_path = write_hjc_study_report(result, options.out_dir);
  result.seconds = seconds_since(start);
  return result;
}

HjcStudyOptions quick_hjc_study_options(HjcStudyOptions base) {
  base.subjects = {{20.0, 40.0}, {30.0, 70.0}};
  base.edge_mm = 3.0;
  base.step_deg = 5.0;
  base.centre_offsets_mm = {2.0};
  return base;
}

}  // namespace hipfai::studies
