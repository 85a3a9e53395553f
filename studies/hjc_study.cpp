#include "studies/hjc_study.h"

#include "contact/range_finder.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/literature.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "core/version.h"
#include "geometry/hip_generator.h"
#include "geometry/hjc.h"
#include "geometry/mesh_io.h"
#include "studies/hjc_cohort.h"
#include "studies/penetration_run.h"
#include "studies/results_file.h"
#include "studies/svg_plot.h"
#include "studies/segmented_hip.h"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <sstream>

namespace hipfai::studies {
namespace {

using geometry::Vec3;

constexpr double kSegmentationNoiseMm = 1.0;
constexpr double kSegmentationAsphericityMm = 0.5;
constexpr double kSegmentationUnevenGapMm = 0.5;

std::string fmt(double value, int digits = 2) {
  if (!std::isfinite(value)) return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

double mean_of(const std::vector<double>& v) {
  return v.empty() ? std::numeric_limits<double>::quiet_NaN()
                   : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double sd_of(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean_of(v);
  double s = 0.0;
  for (const double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

// Eq. 13 for one subject: |depth_i - depth_ref| over every step of every rotation. Curvilinear in
// mm; radial in % of the reference where the reference is > 0, and in mm.
struct Differences {
  std::vector<double> curvilinear_mm, radial_percent, radial_mm;
};

Differences differences(const HjcSubjectResult& s, const std::string& label, const std::string& reference,
                        const std::string& only_rotation = "") {
  Differences d;
  const auto& a = s.depths.at(label);
  const auto& b = s.depths.at(reference);
  for (const auto& [rotation, amplitude] : hjc_study_rotations()) {
    (void)amplitude;
    if (!only_rotation.empty() && rotation != only_rotation) continue;
    const auto& x = a.at(rotation);
    const auto& y = b.at(rotation);
    for (std::size_t k = 0; k < x.angle_deg.size(); ++k) {
      d.curvilinear_mm.push_back(std::abs(x.curvilinear_mm[k] - y.curvilinear_mm[k]));
      const double dr = std::abs(x.radial_mm[k] - y.radial_mm[k]);
      d.radial_mm.push_back(dr);
      if (y.radial_mm[k] > 0.0) d.radial_percent.push_back(100.0 * dr / y.radial_mm[k]);
    }
  }
  return d;
}

// ---- bones-only mode ---------------------------------------------------------------------------

HjcStudyResult run_bones(const HjcStudyOptions& options) {
  HjcStudyResult result;
  const geometry::TriMesh femur = geometry::read_mesh(options.femur);
  const geometry::TriMesh pelvis = geometry::read_mesh(options.pelvis);
  geometry::HjcRequest request;
  request.femur = &femur;
  request.pelvis = &pelvis;
  request.femur_name = options.femur.string();
  request.pelvis_name = options.pelvis.string();
  const geometry::HjcResult hjc = geometry::estimate_hjc(request);

  // Approximate hip frame from the bones (hjc_study.h), about the fitted head.
  const Eigen::Matrix3d frame = approximate_hip_frame(femur, pelvis, hjc.method("femoralheadsphere").center_mm);
  const std::array<Eigen::Vector3d, 3> axes{frame.col(0), frame.col(1), frame.col(2)};
  // (rotation name, axis index, anticlockwise?) for a right hip: flexion +X, adduction +Y, IR +Z.
  const std::vector<std::tuple<std::string, int, bool>> directions{
      {"flexion", 0, true}, {"extension", 0, false}, {"internal_rotation", 2, true},
      {"external_rotation", 2, false}, {"adduction", 1, true}, {"abduction", 1, false}};
  // Second femur: the head removed (triangles with a corner within the head radius + 1.5 mm of the
  // femoralheadsphere centre), so that only the neck and trochanter can meet the pelvis: the
  // impingement range of motion of bony ROM simulations, which let the head turn in its socket.
  const Vec3 head_centre = hjc.method("femoralheadsphere").center_mm;
  const double head_radius = hjc.method("femoralheadsphere").radius_mm;
  const geometry::TriMesh headless = geometry::submesh_where(
      femur, [&](const Vec3& p) { return (p - head_centre).norm() > head_radius + 1.5; });
  const std::vector<std::pair<std::string, const geometry::TriMesh*>> variants{{"whole femur", &femur},
                                                                               {"head removed", &headless}};
  ProgressBar progress("hjc bones rom", hjc.methods.size() * 3 * variants.size(), options.progress);
  std::map<std::string, std::map<std::string, std::map<std::string, double>>> rom_of;
  std::map<std::string, std::map<std::string, std::map<std::string, std::string>>> where_of;
  // Where the first contact is: within the head's radius + 4 mm of the centre it is the head
  // meeting its own socket (h), farther out the neck or trochanter meeting the rim (r).
  auto contact_site = [&](const geometry::TriMesh& mobile, const contact::LimitingContact& limit,
                          const Vec3& centre) -> std::string {
    Vec3 p = Vec3::Zero();
    switch (limit.kind) {
      case contact::ContactKind::kMobileVertexOnFixedTriangle: p = mobile.vertices[static_cast<std::size_t>(limit.vertex)]; break;
      case contact::ContactKind::kFixedVertexOnMobileTriangle: p = pelvis.vertices[static_cast<std::size_t>(limit.vertex)]; break;
      case contact::ContactKind::kEdgeOnEdge: p = mobile.vertices[static_cast<std::size_t>(limit.mobile_edge[0])]; break;
      case contact::ContactKind::kNone: return "-";
    }
    return (p - centre).norm() < head_radius + 4.0 ? "h" : "r";
  };
  for (const auto& [variant, mobile] : variants) {
    for (const auto& m : hjc.methods) {
      for (int a = 0; a < 3; ++a) {
        const contact::RangeOfMotion range = contact::range_of_motion(pelvis, *mobile, m.center_mm, axes[static_cast<std::size_t>(a)]);
        if (range.status == contact::QueryStatus::kInvalidInput) throw_error("study hjc: range of motion: ", range.message);
        for (const auto& [name, index, anticlockwise] : directions) {
          if (index != a) continue;
          const double deg = anticlockwise ? range.anticlockwise_deg : range.clockwise_deg;
          rom_of[variant][m.name][name] = deg;
          where_of[variant][m.name][name] =
              contact_site(*mobile, anticlockwise ? range.anticlockwise_limit : range.clockwise_limit, m.center_mm);
          if (variant == "head removed") result.rom.push_back({m.name, name, deg});
        }
        progress.advance();
      }
    }
  }
  progress.finish();

  // Report.
  std::ostringstream md;
  md << "# HJC on bones: " << options.femur.filename().string() << " + " << options.pelvis.filename().string()
     << "\n\nCode " << kGitSha << ". Femoral head: " << hjc.head_source << ", " << hjc.head_vertices
     << " vertices; lunate surface: " << hjc.lunate_source << ", " << hjc.lunate_vertices
     << " vertices. Centres in the input meshes' coordinates (mm).\n\n"
     << "| method | centre (mm) | radius (mm) | fit RMS (mm) | fit max (mm) | residual motion RMS / max (mm) | "
        "distance to the mean centre (mm) |\n|---|---|---|---|---|---|---|\n";
  Vec3 mean_centre = Vec3::Zero();
  for (const auto& m : hjc.methods) mean_centre += m.center_mm;
  mean_centre /= static_cast<double>(hjc.methods.size());
  double spread = 0.0;
  for (const auto& a : hjc.methods)
    for (const auto& b : hjc.methods) spread = std::max(spread, (a.center_mm - b.center_mm).norm());
  for (const auto& m : hjc.methods) {
    const bool functional = m.name == "dconst" || m.name == "dref";
    md << "| " << m.name << " | (" << fmt(m.center_mm.x(), 2) << ", " << fmt(m.center_mm.y(), 2) << ", "
       << fmt(m.center_mm.z(), 2) << ") | " << (functional ? "-" : fmt(m.radius_mm, 2)) << " | " << fmt(m.rms_mm, 3)
       << " | " << fmt(m.max_mm, 3) << " | "
       << (functional ? fmt(m.residual_motion_rms_mm, 3) + " / " + fmt(m.residual_motion_max_mm, 3) : "-") << " | "
       << fmt((m.center_mm - mean_centre).norm(), 2) << " |\n";
  }
  md << "\nSpread (largest distance between two centres): **" << fmt(spread, 2) << " mm**. For the sphere fits the "
     << "residual is the distance to the fitted sphere; for dconst/dref it is the inter-articular distance minus its "
     << "target after the per-pose shifts (the head is not a perfect sphere).\n\n"
     << "## Bone-to-bone range of motion per method (exact range finder)\n\n"
     << "Approximate hip frame (no anatomical landmarks in the CT): Z = femur principal axis towards the head ("
     << fmt(axes[2].x(), 3) << ", " << fmt(axes[2].y(), 3) << ", " << fmt(axes[2].z(), 3) << "), X = from the pelvis centroid towards the "
     << "head, orthogonal to Z (" << fmt(axes[0].x(), 3) << ", " << fmt(axes[0].y(), 3) << ", " << fmt(axes[0].z(), 3) << "), Y = Z x X ("
     << fmt(axes[1].x(), 3) << ", " << fmt(axes[1].y(), 3) << ", " << fmt(axes[1].z(), 3) << "). Rotations start from the scanned "
     << "pose, which is not the anatomical neutral pose. Bones only: cartilage and labrum absent, so these are the "
     << "bony limits, larger than a living hip's. Whole femur: every contact counts, the head's in its own socket "
     << "too. Head removed: the femur without its head (radius + 1.5 mm about the femoralheadsphere centre), the "
     << "neck and trochanter against the pelvis: the impingement range of bony ROM simulations.\n";
  for (const auto& [variant, mobile] : variants) {
    (void)mobile;
    auto& rom = rom_of[variant];
    auto& where = where_of[variant];
    md << "\n### " << variant << "\n\n| method |";
    for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; md << ' ' << name << " |"; }
    md << "\n|---|---|---|---|---|---|---|\n";
    for (const auto& m : hjc.methods) {
      md << "| " << m.name << " |";
      for (const auto& [name, amplitude] : hjc_study_rotations()) {
        (void)amplitude;
        md << ' ' << fmt(rom[m.name][name], 1) << " (" << where[m.name][name] << ") |";
      }
      md << '\n';
    }
    md << "| spread over methods |";
    for (const auto& [name, amplitude] : hjc_study_rotations()) {
      (void)amplitude;
      double lo = 1e9, hi = -1e9;
      for (const auto& m : hjc.methods) { lo = std::min(lo, rom[m.name][name]); hi = std::max(hi, rom[m.name][name]); }
      md << ' ' << fmt(hi - lo, 1) << " |";
    }
    md << "\n| clinical norm (AAOS 1965) |";
    for (const auto& [name, amplitude] : hjc_study_rotations()) md << ' ' << fmt(amplitude, 0) << " |";
    md << '\n';
  }
  md << "\n(h): the first contact lies within the head radius + 4 mm of the centre: the head (whole femur) or the "
        "head-neck junction (head removed) against the socket or its rim; (r): farther out, neck or trochanter "
        "against the pelvis.\n\nClinical norms: American Academy of Orthopaedic Surgeons, Joint Motion: Method of Measuring and "
        "Recording (1965); supine rotations measured in 120 adults: ER "
     << fmt(literature::kSupineExternalRotationDeg, 1) << ", IR " << fmt(literature::kSupineInternalRotationDeg, 1)
     << " deg (Kouyoumdjian et al. 2012, Orthop Traumatol Surg Res 98:17). core/literature.h.\n";
  std::filesystem::create_directories(options.out_dir);
  result.report_path = options.out_dir / "bones.md";
  write_file_atomically(result.report_path, md.str());
  std::ostringstream csv;
  csv << "method,center_x_mm,center_y_mm,center_z_mm,radius_mm,fit_rms_mm,fit_max_mm,residual_motion_rms_mm";
  for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; csv << ',' << name << "_rom_deg"; }
  for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; csv << ',' << name << "_rom_whole_femur_deg"; }
  csv << '\n';
  csv.precision(8);
  for (const auto& m : hjc.methods) {
    csv << m.name << ',' << m.center_mm.x() << ',' << m.center_mm.y() << ',' << m.center_mm.z() << ',' << m.radius_mm
        << ',' << m.rms_mm << ',' << m.max_mm << ',' << m.residual_motion_rms_mm;
    for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; csv << ',' << rom_of["head removed"][m.name][name]; }
    for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; csv << ',' << rom_of["whole femur"][m.name][name]; }
    csv << '\n';
  }
  write_file_atomically(options.out_dir / "bones.csv", csv.str());
  {
    ResultsFile h5(options.out_dir / "bones.h5");
    h5.set_attribute("/", "units", "mm, deg");
    h5.set_attribute("/", "git_sha", kGitSha);
    h5.set_attribute("/", "femur", options.femur.string());
    h5.set_attribute("/", "pelvis", options.pelvis.string());
    std::vector<std::string> names;
    std::vector<double> centres, roms;
    for (const auto& m : hjc.methods) {
      names.push_back(m.name);
      centres.insert(centres.end(), {m.center_mm.x(), m.center_mm.y(), m.center_mm.z(), m.rms_mm, m.max_mm});
      for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; roms.push_back(rom_of["head removed"][m.name][name]); }
    }
    h5.write_strings("/methods", names);
    h5.write("/centres", centres, 5, "mm");
    h5.set_attribute("/centres", "columns", "x,y,z,fit_rms,fit_max");
    h5.write("/rom_deg", roms, 6, "deg");
    h5.set_attribute("/rom_deg", "femur", "head removed (impingement range; whole-femur ranges in bones.csv)");
    h5.set_attribute("/rom_deg", "columns", "flexion,extension,internal_rotation,external_rotation,adduction,abduction");
    h5.commit();
  }
  return result;
}

}  // namespace

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

HjcStudyResult run_hjc_study(const HjcStudyOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.femur.empty() || !options.pelvis.empty()) {
    if (options.femur.empty() || options.pelvis.empty()) throw_error("study hjc: bones-only mode needs both a femur and a pelvis");
    HjcStudyResult r = run_bones(options);
    r.seconds = seconds_since(start);
    return r;
  }
  if (options.subjects.empty()) throw_error("study hjc: no subjects");
  HjcStudyResult result;
  const auto& methods = geometry::hjc_method_names();
  const std::array<std::pair<const char*, Vec3>, 6> directions{
      {{"+X", Vec3::UnitX()}, {"-X", -Vec3::UnitX()}, {"+Y", Vec3::UnitY()}, {"-Y", -Vec3::UnitY()},
       {"+Z", Vec3::UnitZ()}, {"-Z", -Vec3::UnitZ()}}};
  const std::size_t centres_per_subject = methods.size() + 1 + options.centre_offsets_mm.size() * directions.size();
  ProgressBar progress("hjc study", options.subjects.size() * centres_per_subject * hjc_study_rotations().size(),
                       options.progress);
  for (std::size_t si = 0; si < options.subjects.size(); ++si) {
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
    // The centres: five methods on the "segmented" articular surfaces, the truth, offsets.
    geometry::TriMesh head = model.tissue("femoral_cartilage");
    geometry::TriMesh socket = model.tissue("acetabular_cartilage");
    perturb_like_segmentation(head, socket, model, kSegmentationNoiseMm, kSegmentationAsphericityMm,
                              kSegmentationUnevenGapMm, 4242u + static_cast<unsigned>(si));
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
      for (const auto& [name, direction] : directions) {
        const std::string label = "truth " + std::string(name) + " " + fmt(offset, 0) + "mm";
        subject.centres_mm[label] = model.hjc_mm + offset * (frame * direction);
        labels.push_back(label);
      }
    }
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
    result.subjects.push_back(std::move(subject));
  }
  progress.finish();

  // ---- report -----------------------------------------------------------------------------------
  std::filesystem::create_directories(options.out_dir);
  const std::vector<std::string> compared{"femoralheadsphere", "acetabulumsphere", "doublesphere", "dconst"};
  std::ostringstream md;
  md << "# HJC sensitivity study (thesis §4.4) with a known centre\n\n"
     << "Code " << kGitSha << ". " << result.subjects.size() << " generated subjects at " << options.edge_mm
     << " mm edges; each subject's centres estimated on its articular surfaces perturbed like a segmentation (noise "
     << kSegmentationNoiseMm << " mm RMS, asphericity " << kSegmentationAsphericityMm << " mm, uneven joint space "
     << kSegmentationUnevenGapMm << " mm; studies/hjc_study.h). Six medical rotations to the AAOS normal range in "
     << options.step_deg << " deg steps; per step the maximum curvilinear (femur bone vs labrum) and radial "
     << "(femoral cartilage vs acetabular cartilage + labrum) depth.\n\n## Centre errors of the subjects (mm, vs the true centre)\n\n| subject |";
  for (const auto& m : methods) md << ' ' << m << " |";
  md << "\n|---|---|---|---|---|---|\n";
  for (const auto& s : result.subjects) {
    md << "| " << s.id << " |";
    for (const auto& m : methods) md << ' ' << fmt((s.centres_mm.at(m) - s.true_centre_mm).norm(), 2) << " |";
    md << '\n';
  }
  // Eq. 13 per subject, then mean over subjects; against dref and against the truth.
  auto overall = [&](const std::string& label, const std::string& reference, double& radial_percent,
                     double& radial_percent_sd, double& curvilinear_mm, double& curvilinear_sd, double& radial_mm) {
    std::vector<double> rp, cm, rm, rps, cms;
    for (const auto& s : result.subjects) {
      const Differences d = differences(s, label, reference);
      rp.push_back(mean_of(d.radial_percent));
      rps.push_back(sd_of(d.radial_percent));
      cm.push_back(mean_of(d.curvilinear_mm));
      cms.push_back(sd_of(d.curvilinear_mm));
      rm.push_back(mean_of(d.radial_mm));
    }
    radial_percent = mean_of(rp);
    radial_percent_sd = mean_of(rps);
    curvilinear_mm = mean_of(cm);
    curvilinear_sd = mean_of(cms);
    radial_mm = mean_of(rm);
  };
  md << "\n## Differences to dref over all six rotations (thesis Eq. 13, Figs. 68-69)\n\n"
     << "Mean over subjects of each subject's mean |depth - depth_dref| (SD: mean of the subjects' SDs). Thesis "
     << "(10 MRI subjects): radial about " << fmt(literature::kThesisHjcRadialDiffPercent, 0)
     << " % on average; femoralheadsphere and doublesphere < " << fmt(literature::kThesisHjcSphereRadialDiffPercent, 0)
     << " % and < " << fmt(literature::kThesisHjcSphereCurvilinearDiffMm, 2) << " mm curvilinear; dconst about "
     << fmt(literature::kThesisHjcDconstRadialDiffPercent, 0) << " % and "
     << fmt(literature::kThesisHjcDconstCurvilinearDiffMm, 2) << " mm.\n\n"
     << "| method | radial (% of dref) | radial (mm) | curvilinear (mm) | thesis radial | thesis curvilinear |\n"
     << "|---|---|---|---|---|---|\n";
  std::vector<std::vector<double>> fig68(compared.size()), fig69(compared.size());
  for (std::size_t i = 0; i < compared.size(); ++i) {
    double rp, rps, cm, cms, rm;
    overall(compared[i], "dref", rp, rps, cm, cms, rm);
    const bool small = compared[i] == "femoralheadsphere" || compared[i] == "doublesphere";
    const bool dconst = compared[i] == "dconst";
    md << "| " << compared[i] << " | " << fmt(rp, 1) << " +- " << fmt(rps, 1) << " | " << fmt(rm, 3) << " | "
       << fmt(cm, 3) << " +- " << fmt(cms, 3) << " | "
       << (small    ? "< " + fmt(literature::kThesisHjcSphereRadialDiffPercent, 0) + " %"
           : dconst ? "~" + fmt(literature::kThesisHjcDconstRadialDiffPercent, 0) + " %"
                    : "~" + fmt(literature::kThesisHjcRadialDiffPercent, 0) + " % (all methods)")
       << " | "
       << (small    ? "< " + fmt(literature::kThesisHjcSphereCurvilinearDiffMm, 2) + " mm"
           : dconst ? fmt(literature::kThesisHjcDconstCurvilinearDiffMm, 2) + " mm"
                    : std::string("-"))
       << " |\n";
    for (const auto& s : result.subjects) {
      const Differences d = differences(s, compared[i], "dref");
      fig68[i].push_back(mean_of(d.radial_percent));
      fig69[i].push_back(mean_of(d.curvilinear_mm));
    }
  }
  md << "\n## Differences to the true centre over all six rotations\n\n"
     << "| centre | radial (% of truth) | radial (mm) | curvilinear (mm) |\n|---|---|---|---|\n";
  for (const auto& m : methods) {
    double rp, rps, cm, cms, rm;
    overall(m, "truth", rp, rps, cm, cms, rm);
    md << "| " << m << " | " << fmt(rp, 1) << " +- " << fmt(rps, 1) << " | " << fmt(rm, 3) << " | " << fmt(cm, 3)
       << " +- " << fmt(cms, 3) << " |\n";
  }
  md << "\n## Effect of a known centre error (true centre displaced along +-X, +-Y, +-Z of the hip frame)\n\n"
     << "| centre error | radial (% of truth) | radial (mm) | curvilinear (mm) | max curvilinear difference (mm) |\n|---|---|---|---|---|\n";
  for (const double offset : options.centre_offsets_mm) {
    std::vector<double> rp, rm, cm;
    double cmax = 0.0;
    for (const auto& s : result.subjects) {
      for (const auto& [name, direction] : directions) {
        (void)direction;
        const Differences d = differences(s, "truth " + std::string(name) + " " + fmt(offset, 0) + "mm", "truth");
        rp.push_back(mean_of(d.radial_percent));
        rm.push_back(mean_of(d.radial_mm));
        cm.push_back(mean_of(d.curvilinear_mm));
        for (const double x : d.curvilinear_mm) cmax = std::max(cmax, x);
      }
    }
    md << "| " << fmt(offset, 0) << " mm | " << fmt(mean_of(rp), 1) << " | " << fmt(mean_of(rm), 3) << " | "
       << fmt(mean_of(cm), 3) << " | " << fmt(cmax, 2) << " |\n";
  }
  // Eq. 14-15 per rotation (Figs. 70-71) and the sensitivity ranking.
  md << "\n## Per rotation (thesis Eq. 14-15, Figs. 70-71): mean over subjects of the mean difference to dref, [min, max]\n\n"
     << "| rotation |";
  for (const auto& m : compared) md << ' ' << m << " radial % | " << m << " curv. mm |";
  md << " mean radial % | mean curv. mm |\n|---|";
  for (std::size_t i = 0; i < compared.size() * 2 + 2; ++i) md << "---|";
  md << '\n';
  std::vector<std::vector<double>> fig70(compared.size()), fig71(compared.size());
  std::vector<std::pair<double, std::string>> rank_radial, rank_curvilinear;
  for (const auto& [rotation, amplitude] : hjc_study_rotations()) {
    (void)amplitude;
    md << "| " << rotation << " |";
    std::vector<double> all_rp, all_cm;
    for (std::size_t i = 0; i < compared.size(); ++i) {
      std::vector<double> rp, cm;
      for (const auto& s : result.subjects) {
        const Differences d = differences(s, compared[i], "dref", rotation);
        rp.push_back(mean_of(d.radial_percent));
        cm.push_back(mean_of(d.curvilinear_mm));
      }
      std::vector<double> rp_finite;
      for (const double x : rp) if (std::isfinite(x)) rp_finite.push_back(x);
      const double rpm = mean_of(rp_finite), cmm = mean_of(cm);
      fig70[i].push_back(rpm);
      fig71[i].push_back(cmm);
      if (std::isfinite(rpm)) all_rp.push_back(rpm);
      all_cm.push_back(cmm);
      auto range = [](const std::vector<double>& v, int digits) {
        double lo = 1e300, hi = -1e300;
        for (const double x : v) if (std::isfinite(x)) { lo = std::min(lo, x); hi = std::max(hi, x); }
        return lo > hi ? std::string("-") : "[" + fmt(lo, digits) + ", " + fmt(hi, digits) + "]";
      };
      md << ' ' << fmt(rpm, 1) << ' ' << range(rp_finite, 1) << " | " << fmt(cmm, 3) << ' ' << range(cm, 2) << " |";
    }
    const double mr = mean_of(all_rp), mc = mean_of(all_cm);
    md << ' ' << fmt(mr, 1) << " | " << fmt(mc, 3) << " |\n";
    rank_radial.push_back({std::isfinite(mr) ? mr : -1.0, rotation});
    rank_curvilinear.push_back({mc, rotation});
  }
  std::sort(rank_radial.rbegin(), rank_radial.rend());
  std::sort(rank_curvilinear.rbegin(), rank_curvilinear.rend());
  md << "\nSensitivity ranking, most sensitive first (thesis: flexion among the most sensitive, adduction and "
        "external rotation the least). Radial: ";
  for (std::size_t i = 0; i < rank_radial.size(); ++i) md << (i ? " > " : "") << rank_radial[i].second;
  md << ". Curvilinear: ";
  for (std::size_t i = 0; i < rank_curvilinear.size(); ++i) md << (i ? " > " : "") << rank_curvilinear[i].second;
  md << ".\n\nA radial percentage is undefined where dref's radial depth is 0 ('-'). Figures: fig67_radial.svg, "
        "fig67_curvilinear.svg (first subject, extension), fig68.svg, fig69.svg (per subject), fig70.svg, fig71.svg "
        "(per rotation).\n";

  // Figures.
  {
    const HjcSubjectResult& s = result.subjects.front();
    for (const bool radial : {true, false}) {
      LineChart chart;
      chart.title = std::string("Fig. 67 analogue: ") + (radial ? "radial" : "curvilinear") + " depth, extension, " + s.id;
      chart.x_label = "extension (deg)";
      chart.y_label = "maximum depth (mm)";
      for (const std::string label : {"dref", "acetabulumsphere", "doublesphere", "femoralheadsphere", "dconst", "truth"}) {
        const auto& d = s.depths.at(label).at("extension");
        chart.series.push_back({label, d.angle_deg, radial ? d.radial_mm : d.curvilinear_mm, label == "truth"});
      }
      write_svg(chart, options.out_dir / (radial ? "fig67_radial.svg" : "fig67_curvilinear.svg"));
    }
    std::vector<std::string> subject_names;
    for (const auto& x : result.subjects) subject_names.push_back(x.id);
    std::vector<std::string> rotation_names;
    for (const auto& [rotation, amplitude] : hjc_study_rotations()) { (void)amplitude; rotation_names.push_back(rotation); }
    auto heat = [&](const std::string& title, const std::vector<std::string>& columns,
                    const std::vector<std::vector<double>>& values, const std::string& unit, const char* file) {
      HeatMap map;
      map.title = title;
      map.row_label = "method";
      map.column_label = columns == subject_names ? "subject" : "rotation";
      map.unit = unit;
      map.row_names = compared;
      map.column_names = columns;
      map.values = values;
      write_svg(map, options.out_dir / file);
    };
    heat("Fig. 68 analogue: mean radial difference to dref", subject_names, fig68, "%", "fig68.svg");
    heat("Fig. 69 analogue: mean curvilinear difference to dref", subject_names, fig69, "mm", "fig69.svg");
    heat("Fig. 70 analogue: radial difference to dref per rotation", rotation_names, fig70, "%", "fig70.svg");
    heat("Fig. 71 analogue: curvilinear difference to dref per rotation", rotation_names, fig71, "mm", "fig71.svg");
  }
  result.report_path = options.out_dir / "report.md";
  write_file_atomically(result.report_path, md.str());

  std::ostringstream steps;
  steps << "subject,centre,center_x_mm,center_y_mm,center_z_mm,rotation,angle_deg,curvilinear_mm,radial_mm\n";
  steps.precision(8);
  for (const auto& s : result.subjects) {
    for (const auto& [label, rotations] : s.depths) {
      const Vec3& c = s.centres_mm.at(label);
      for (const auto& [rotation, d] : rotations) {
        for (std::size_t k = 0; k < d.angle_deg.size(); ++k) {
          steps << s.id << ',' << label << ',' << c.x() << ',' << c.y() << ',' << c.z() << ',' << rotation << ','
                << d.angle_deg[k] << ',' << d.curvilinear_mm[k] << ',' << d.radial_mm[k] << '\n';
        }
      }
    }
  }
  write_file_atomically(options.out_dir / "steps.csv", steps.str());
  {
    ResultsFile h5(options.out_dir / "results.h5");
    h5.set_attribute("/", "units", "mm, deg");
    h5.set_attribute("/", "git_sha", kGitSha);
    h5.set_attribute("/", "study", "hjc sensitivity (thesis 4.4)");
    for (const auto& s : result.subjects) {
      for (const auto& [label, rotations] : s.depths) {
        std::string group = "/" + s.id + "/" + label;
        for (char& ch : group) if (ch == ' ') ch = '_';
        const Vec3& c = s.centres_mm.at(label);
        h5.write(group + "/center_mm", {c.x(), c.y(), c.z()}, 3, "mm");
        for (const auto& [rotation, d] : rotations) {
          std::vector<double> table;
          for (std::size_t k = 0; k < d.angle_deg.size(); ++k) table.insert(table.end(), {d.angle_deg[k], d.curvilinear_mm[k], d.radial_mm[k]});
          h5.write(group + "/" + rotation, table, 3, "deg, mm, mm");
          h5.set_attribute(group + "/" + rotation, "columns", "angle_deg,curvilinear_mm,radial_mm");
        }
      }
    }
    h5.commit();
  }
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
