// hipfai — writes an assessment into an output folder (see assessment_report.h).
#include "studies/pipeline/assessment_report.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/literature.h"
#include "core/text_format.h"
#include "core/version.h"
#include "geometry/hip_measure.h"
#include "geometry/mesh_io.h"
#include "studies/pipeline/assessment_figures.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>

namespace hipfai::studies {
namespace {

using geometry::Vec3;
using Json = nlohmann::ordered_json;

// A vertex is in a motion's impingement zone within this of the limit's contact point: the
// assessment's meshes have ~ 1-2 mm edges, so 3 mm paints the contact's neighbourhood, not a point.
constexpr double kZoneRadiusMm = 3.0;

Json vec(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json frame_json(const anatomy::AnatomicalFrame& f, const std::string& source) {
  return Json{{"origin_mm", vec(f.origin_mm)}, {"right", vec(f.right)}, {"anterior", vec(f.anterior)},
              {"superior", vec(f.superior)}, {"source", source}};
}

Json measures_json(const anatomy::ClinicalMeasures& m) {
  Json j;
  j["lateral_ce_deg"] = m.lateral_ce.ce_deg;
  j["acetabular_inclination_deg"] = m.acetabular_inclination_deg;
  j["acetabular_version_deg"] = m.acetabular_version_deg;
  j["acetabular_inclination_anatomic_deg"] = m.acetabular_inclination_anatomic_deg;
  j["acetabular_version_anatomic_deg"] = m.acetabular_version_anatomic_deg;
  j["alpha_deg"] = m.alpha.alpha_deg;
  j["alpha_max_deg"] = m.alpha.max_alpha_deg;
  j["alpha_max_clock"] = geometry::clock_label(m.alpha.max_plane_deg);
  Json profile = Json::array();
  for (const auto& [clock, alpha] : m.alpha.profile) {
    profile.push_back({{"clock", geometry::clock_label(clock)}, {"clock_deg", clock},
                       {"alpha_deg", std::isfinite(alpha) ? Json(alpha) : Json(nullptr)}});
  }
  j["alpha_profile"] = profile;
  if (m.head_neck_offset.measured) {
    j["head_neck_offset_mm"] = m.head_neck_offset.offset_mm;
    j["head_neck_offset_ratio"] = m.head_neck_offset.ratio;
  } else {
    j["head_neck_offset_mm"] = nullptr;
    j["head_neck_offset_mm_reason"] = m.head_neck_offset.reason;
    j["head_neck_offset_ratio"] = nullptr;
  }
  j["neck_shaft_deg"] = m.neck_shaft_deg;
  if (m.femoral_version_deg) {
    j["femoral_version_deg"] = *m.femoral_version_deg;
  } else {
    j["femoral_version_deg"] = nullptr;
    j["femoral_version_deg_reason"] = m.femoral_version_reason;
  }
  return j;
}

// The limits' values ("rom_deg") and where the bones meet ("impingement"), points in the input's
// coordinates.
std::pair<Json, Json> rom_json(const AssessmentResult& r, const anatomy::ClinicalRom& rom) {
  Json values, where;
  for (const auto* outcome : rom.motions()) {
    if (!outcome->limit) continue;
  }
  static const char* kNames[] = {"flexion", "extension", "abduction", "adduction", "internal_rotation",
                                 "external_rotation", "internal_rotation_at_90_flexion",
                                 "external_rotation_at_90_flexion", "fadir_internal_rotation", "faber"};
  const auto motions = rom.motions();
  for (std::size_t i = 0; i < motions.size(); ++i) {
    const std::string name = kNames[i];
    const auto& outcome = *motions[i];
    if (!outcome.limit) {
      values[name] = nullptr;
      values[name + "_reason"] = outcome.reason;
      continue;
    }
    const auto& limit = *outcome.limit;
    values[name] = limit.angle_deg;
    if (limit.unlimited) {
      where[name] = {{"contact", nullptr}, {"reason", "no bony contact within a full turn"}};
      continue;
    }
    where[name] = {{"contact_point_mm", vec(r.point_to_input(limit.contact_point_mm))},
                   {"acetabular_clock", limit.acetabular_clock.label},
                   {"acetabular_clock_deg", limit.acetabular_clock.angle_deg},
                   {"femoral_clock", limit.femoral_clock.label},
                   {"femoral_clock_deg", limit.femoral_clock.angle_deg}};
  }
  return {values, where};
}

Json femur_landmarks_json(const AssessmentResult& r) {
  const auto& f = r.femur_landmarks;
  Json j{{"head_centre_mm", vec(r.point_to_input(f.head_centre_mm))},
         {"head_radius_mm", f.head_radius_mm},
         {"head_fit_rms_mm", f.head_fit_rms_mm},
         {"neck_axis", vec(r.direction_to_input(r.neck_axis))},
         {"neck_axis_source", r.neck_axis_source},
         {"shaft_axis", vec(r.direction_to_input(f.shaft_axis))},
         {"has_distal", f.has_distal}};
  auto optional_point = [&](const char* key, const std::optional<Vec3>& p) {
    j[key] = p ? vec(r.point_to_input(*p)) : Json(nullptr);
  };
  optional_point("knee_centre_mm", f.knee_centre_mm);
  // Medial/lateral are anatomical names: a mirrored left femur keeps them.
  optional_point("medial_epicondyle_mm", f.medial_epicondyle_mm);
  optional_point("lateral_epicondyle_mm", f.lateral_epicondyle_mm);
  optional_point("medial_posterior_condyle_mm", f.medial_posterior_condyle_mm);
  optional_point("lateral_posterior_condyle_mm", f.lateral_posterior_condyle_mm);
  if (!f.has_distal) j["distal_missing_reason"] = f.distal_missing_reason;
  return j;
}

Json pelvis_landmarks_json(const AssessmentResult& r) {
  if (!r.pelvis_landmarks) return nullptr;
  const auto& p = *r.pelvis_landmarks;
  // In working coordinates a left hip's "right" ASIS is the input's left one.
  const bool left = r.side == anatomy::Side::kLeft;
  return Json{{"asis_right_mm", vec(r.point_to_input(left ? p.asis_left_mm : p.asis_right_mm))},
              {"asis_left_mm", vec(r.point_to_input(left ? p.asis_right_mm : p.asis_left_mm))},
              {"pubic_tubercle_right_mm", vec(r.point_to_input(left ? p.pubic_tubercle_left_mm : p.pubic_tubercle_right_mm))},
              {"pubic_tubercle_left_mm", vec(r.point_to_input(left ? p.pubic_tubercle_right_mm : p.pubic_tubercle_left_mm))},
              {"refinement_rounds", p.iterations},
              {"symmetry_residual_mm", p.symmetry_residual_mm}};
}

// Per vertex: how many clinical motions' limits lie within kZoneRadiusMm. `femur_side`: the
// femur (contact points taken back from neutral to the scanned pose) or the pelvis.
std::vector<double> impingement_field(const AssessmentResult& r, const geometry::TriMesh& mesh, bool femur_side) {
  std::vector<double> field(mesh.num_vertices(), 0.0);
  for (const auto* outcome : r.before.rom.motions()) {
    if (!outcome->limit || outcome->limit->unlimited) continue;
    const auto& limit = *outcome->limit;
    Vec3 p = limit.contact_point_mm;
    if (femur_side) {
      // Undo the motion (start rotation, then the turn about the axis), then the neutral rotation.
      const Eigen::Matrix3d turn(Eigen::AngleAxisd(limit.sign * limit.angle_deg * geometry::kDegToRad, limit.axis));
      const Vec3 at_neutral = r.hjc_mm + (turn * limit.start_rotation).transpose() * (p - r.hjc_mm);
      p = r.hjc_mm + r.neutral_rotation.transpose() * (at_neutral - r.hjc_mm);
    }
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
      if ((mesh.vertices[v] - p).norm() <= kZoneRadiusMm) field[v] += 1.0;
    }
  }
  return field;
}

geometry::TriMesh to_input(const AssessmentResult& r, geometry::TriMesh mesh) {
  if (r.side == anatomy::Side::kLeft) return anatomy::reflected(mesh, r.to_input);
  return mesh;
}

geometry::TriMesh scanned(const AssessmentResult& r, const geometry::TriMesh& neutral) {
  geometry::TriMesh out = neutral;
  for (Vec3& v : out.vertices) v = r.hjc_mm + r.neutral_rotation.transpose() * (v - r.hjc_mm);
  return out;
}

}  // namespace

std::string assessment_json(const AssessmentResult& r, const AssessmentInputs& inputs, int indent) {
  Json j;
  j["format"] = "hipfai-assessment";
  j["version"] = 1;
  j["hipfai_revision"] = kGitSha;
  j["inputs"] = {{"femur", inputs.femur_path}, {"pelvis", inputs.pelvis_path},
                 {"frame", inputs.frame_path.empty() ? Json(nullptr) : Json(inputs.frame_path)},
                 {"motion", inputs.motion_path.empty() ? Json(nullptr) : Json(inputs.motion_path)}};
  j["side"] = anatomy::side_name(r.side);
  j["side_source"] = r.side_source;
  j["hjc_mm"] = vec(r.point_to_input(r.hjc_mm));
  j["frames"] = {{"pelvis", frame_json(r.frame_to_input(r.pelvis_frame), r.pelvis_frame_source)},
                 {"femur", frame_json(r.frame_to_input(r.femur_frame), r.femur_frame_source)}};
  j["measures"] = measures_json(r.before.measures);
  j["classification"] = anatomy::morphology_name(r.before.measures.morphology);
  j["findings"] = r.before.measures.findings;
  auto [values, where] = rom_json(r, r.before.rom);
  j["rom_deg"] = values;
  j["impingement"] = where;
  j["clinical_motion_definitions"] = {{"fadir_adduction_deg", r.before.rom.fadir_adduction_deg},
                                      {"faber_flexion_deg", r.before.rom.faber_flexion_deg},
                                      {"faber_abduction_deg", r.before.rom.faber_abduction_deg}};
  j["landmarks"] = {{"pelvis", pelvis_landmarks_json(r)}, {"femur", femur_landmarks_json(r)}};
  j["acetabulum"] = {{"centre_mm", vec(r.point_to_input(r.acetabulum.centre_mm))},
                     {"radius_mm", r.acetabulum.radius_mm},
                     {"axis", vec(r.direction_to_input(r.acetabulum.axis))},
                     {"rim_plane_rms_mm", r.acetabulum.rim_plane_rms_mm}};
  if (r.motion_depths) {
    Json steps = Json::array();
    for (const auto& s : r.motion_depths->steps) {
      steps.push_back({{"flexion_deg", s.pose.flexion_deg}, {"adduction_deg", s.pose.adduction_deg},
                       {"internal_rotation_deg", s.pose.internal_rotation_deg},
                       {"max_curvilinear_mm", s.max_curvilinear_mm}, {"max_radial_mm", s.max_radial_mm},
                       {"curvilinear_acetabular_clock", s.curvilinear_deepest.body == anatomy::DepthBody::kNone
                                                            ? Json(nullptr) : Json(s.curvilinear_deepest.acetabular_clock.label)},
                       {"penetrating_vertices", s.curvilinear_vertices}});
    }
    j["motion"] = {{"name", r.motion_name}, {"max_curvilinear_mm", r.motion_depths->max_curvilinear_mm()},
                   {"max_radial_mm", r.motion_depths->max_radial_mm()}, {"steps", steps}};
  }
  if (r.after) {
    Json ops = Json::array();
    for (const auto& s : r.resections) {
      Json bins = Json::array();
      for (const auto& [clock, volume] : s.removed_by_clock) bins.push_back({{"clock_deg", clock}, {"removed_mm3", volume}});
      ops.push_back({{"kind", s.kind}, {"requested_deg", s.requested_deg}, {"removed_volume_mm3", s.removed_volume_mm3},
                     {"original_volume_mm3", s.original_volume_mm3}, {"closed", s.closed}, {"manifold", s.manifold},
                     {"removed_by_clock", bins}, {"repaired_self_intersections", s.repaired_pairs},
                     {"repaired_near_mm", s.repaired_pairs ? vec(r.point_to_input(s.repaired_near_mm)) : Json(nullptr)},
                     {"seconds", s.seconds}});
    }
    auto [after_values, after_where] = rom_json(r, r.after->rom);
    Json gain;
    for (const auto& [key, value] : after_values.items()) {
      if (key.find("_reason") != std::string::npos) continue;
      const Json& before = values[key];
      gain[key] = (value.is_number() && before.is_number()) ? Json(value.get<double>() - before.get<double>()) : Json(nullptr);
    }
    j["resection"] = {{"operations", ops}, {"measures_after", measures_json(r.after->measures)},
                      {"classification_after", anatomy::morphology_name(r.after->measures.morphology)},
                      {"rom_deg_after", after_values}, {"impingement_after", after_where}, {"rom_gain_deg", gain}};
  }
  Json timings;
  for (const auto& [stage, seconds] : r.stage_seconds) timings[stage] = seconds;
  timings["total"] = r.total_seconds;
  j["timings_s"] = timings;
  return j.dump(indent);
}

namespace {

void write_introduction(std::ostream& md, const AssessmentResult& r, const AssessmentInputs& inputs) {
  const auto& m = r.before.measures;
  md << "# Hip assessment: " << anatomy::side_name(r.side) << " hip\n\n"
     << "Femur `" << inputs.femur_path << "`, pelvis `" << inputs.pelvis_path << "`"
     << (inputs.frame_path.empty() ? "" : ", frame `" + inputs.frame_path + "`") << ". Side: " << r.side_source
     << ".\n\nPelvis frame: " << r.pelvis_frame_source << ". Femur frame: " << r.femur_frame_source
     << ". Neck axis: " << r.neck_axis_source << ".\n\n"
     << "**Classification: " << anatomy::morphology_name(m.morphology) << "**";
  for (const auto& finding : m.findings) md << "\n- " << finding;
}

void write_measures(std::ostream& md, const anatomy::ClinicalMeasures& m) {
  md << "\n\n## Measures\n\n| measure | value | definition |\n|---|---|---|\n"
     << "| lateral CE | " << fixed(m.lateral_ce.ce_deg, 1) << "° | Wiberg, coronal plane of the APP frame |\n"
     << "| acetabular inclination | " << fixed(m.acetabular_inclination_deg, 1) << "° (anatomic "
     << fixed(m.acetabular_inclination_anatomic_deg, 1) << "°) | Murray 1993, radiographic |\n"
     << "| acetabular version | " << fixed(m.acetabular_version_deg, 1) << "° (anatomic "
     << fixed(m.acetabular_version_anatomic_deg, 1) << "°) | Murray 1993, radiographic |\n"
     << "| alpha | " << fixed(m.alpha.alpha_deg, 1) << "° | Nötzli 2002, Nötzli's plane |\n"
     << "| largest alpha | " << fixed(m.alpha.max_alpha_deg, 1) << "° at " << geometry::clock_label(m.alpha.max_plane_deg)
     << " | anterosuperior sector |\n";
  if (m.head_neck_offset.measured) {
    md << "| head-neck offset | " << fixed(m.head_neck_offset.offset_mm, 1) << " mm (ratio " << fixed(m.head_neck_offset.ratio, 2)
       << ") | Eijer 2001, Nötzli's plane |\n";
  } else {
    md << "| head-neck offset | not measured: " << m.head_neck_offset.reason << " | |\n";
  }
  md << "| neck-shaft angle | " << fixed(m.neck_shaft_deg, 1) << "° | 3D |\n"
     << "| femoral version | "
     << (m.femoral_version_deg ? fixed(*m.femoral_version_deg, 1) + "°" : "not measured: " + m.femoral_version_reason)
     << " | |\n\n![lateral CE](coronal_ce.svg) ![alpha](notzli_alpha.svg)\n\n![alpha profile](alpha_profile.svg)\n\n";
}

// The clinical normal range of each clinical motion, in the order of the motions' table.
std::vector<std::string> clinical_normals() {
  namespace lit = literature;
  auto pair = [](double male, double female) { return fixed(male, 0) + " m / " + fixed(female, 0) + " f (C)"; };
  return {
      fixed(lit::kAaosFlexionDeg, 0) + " (A); " + pair(lit::kCzupponFlexionMaleDeg, lit::kCzupponFlexionFemaleDeg),
      fixed(lit::kAaosExtensionDeg, 0) + " (A)",
      fixed(lit::kAaosAbductionDeg, 0) + " (A)",
      fixed(lit::kAaosAdductionDeg, 0) + " (A)",
      fixed(lit::kAaosInternalRotationDeg, 0) + " (A); " +
          pair(lit::kCzupponInternalRotationMaleDeg, lit::kCzupponInternalRotationFemaleDeg),
      fixed(lit::kAaosExternalRotationDeg, 0) + " (A); " +
          pair(lit::kCzupponExternalRotationMaleDeg, lit::kCzupponExternalRotationFemaleDeg),
      pair(lit::kCzupponInternalRotation90MaleDeg, lit::kCzupponInternalRotation90FemaleDeg),
      pair(lit::kCzupponExternalRotation90MaleDeg, lit::kCzupponExternalRotation90FemaleDeg),
      fixed(lit::kAudenaertImpingementIrHealthyDeg, 0) + " healthy / " + fixed(lit::kAudenaertImpingementIrFaiDeg, 0) +
          " FAI (Au)",
      ""};
}

void write_clinical_motions(std::ostream& md, const AssessmentResult& r) {
  md << "## Clinical motions to bony impingement\n\nExact range finder (thesis §4.2) about the frame found; "
        "FADIR: flexion 90° and adduction " << fixed(r.before.rom.fadir_adduction_deg, 1) << "°, then internal rotation; "
        "FABER: flexion " << fixed(r.before.rom.faber_flexion_deg, 1) << "° and abduction "
     << fixed(r.before.rom.faber_abduction_deg, 1) << "°, then external rotation.\n\n"
     << "Bony limits, no soft tissue: they exceed the clinical normal ranges, which capsule and muscles limit, "
        "given beside them: (A) AAOS 1965; (C) Czuppon et al. 2017, passive range of 430 asymptomatic hips, "
        "male / female means; (Au) Audenaert et al. 2012, internal rotation on impingement testing computed on 3D "
        "models of healthy and FAI hips.\n\n"
     << "| motion | range (deg) | rim clock | head-neck clock | clinical normal (deg) |"
     << (r.after ? " after (deg) | gain (deg) |" : "") << "\n|---|---|---|---|---|" << (r.after ? "---|---|" : "") << "\n";
  const auto before = r.before.rom.motions();
  static const char* kNames[] = {"flexion", "extension", "abduction", "adduction", "internal rotation",
                                 "external rotation", "internal rotation at 90° flexion",
                                 "external rotation at 90° flexion", "FADIR internal rotation", "FABER"};
  const std::vector<std::string> normal = clinical_normals();
  for (std::size_t i = 0; i < before.size(); ++i) {
    const auto& o = *before[i];
    md << "| " << kNames[i] << " | ";
    if (!o.limit) {
      md << "— (" << o.reason << ") | | |";
    } else if (o.limit->unlimited) {
      md << "no bony contact | | |";
    } else {
      md << fixed(o.limit->angle_deg, 1) << " | " << o.limit->acetabular_clock.label << " | " << o.limit->femoral_clock.label << " |";
    }
    md << " " << normal[i] << " |";
    if (r.after) {
      const auto& a = *r.after->rom.motions()[i];
      if (a.limit && o.limit && !a.limit->unlimited) {
        md << " " << fixed(a.limit->angle_deg, 1) << " | " << fixed(a.limit->angle_deg - o.limit->angle_deg, 1) << " |";
      } else {
        md << " — | — |";
      }
    }
    md << "\n";
  }
  md << "\n![clock faces](impingement_clock.svg)\n\n![range of motion](rom.svg)\n\n";
}

void write_resections(std::ostream& md, const AssessmentResult& r) {
  md << "## Virtual resection\n\n| operation | requested | volume removed (mm³) | closed | manifold |\n|---|---|---|---|---|\n";
  for (const auto& s : r.resections) {
    md << "| " << (s.kind == "cam" ? "osteochondroplasty to alpha" : "rim trimming by") << " | " << fixed(s.requested_deg, 1)
       << "° | " << fixed(s.removed_volume_mm3, 1) << " | " << (s.closed ? "yes" : "NO") << " | " << (s.manifold ? "yes" : "NO")
       << " |\n";
  }
  for (const auto& s : r.resections) {
    if (s.repaired_pairs == 0) continue;
    const Vec3 p = r.point_to_input(s.repaired_near_mm);
    md << "\nThe " << (s.kind == "cam" ? "femur" : "pelvis") << " had " << s.repaired_pairs
       << " self-intersecting triangle pairs (near " << fixed(p.x(), 1) << ", " << fixed(p.y(), 1) << ", " << fixed(p.z(), 1)
       << " mm), removed and refilled locally (CGAL) before the Boolean.\n";
  }
  md << "\nAfter: alpha " << fixed(r.after->measures.alpha.alpha_deg, 1) << "° (largest " << fixed(r.after->measures.alpha.max_alpha_deg, 1)
     << "°), lateral CE " << fixed(r.after->measures.lateral_ce.ce_deg, 1) << "°, classification "
     << anatomy::morphology_name(r.after->measures.morphology) << ".\n\n";
}

}  // namespace

std::string assessment_markdown(const AssessmentResult& r, const AssessmentInputs& inputs) {
  std::ostringstream md;
  write_introduction(md, r, inputs);
  write_measures(md, r.before.measures);
  write_clinical_motions(md, r);
  if (r.motion_depths) {
    md << "## Motion `" << r.motion_name << "`: bone-to-bone penetration\n\nMaximum curvilinear depth "
       << fixed(r.motion_depths->max_curvilinear_mm(), 2) << " mm, maximum radial depth "
       << fixed(r.motion_depths->max_radial_mm(), 2) << " mm over " << r.motion_depths->steps.size()
       << " steps (thesis ch. 3; per step in assessment.json).\n\n";
  }
  if (r.after) write_resections(md, r);
  md << "## Files\n\n`assessment.json` (every value, input coordinates), `pelvis.vtp`, `femur.vtp` (vertex field "
        "`impingement_motions`)" << (r.after ? ", `femur_resected.vtp`, `pelvis_trimmed.vtp`" : "") << ".\n\n"
     << "Time: " << fixed(r.total_seconds, 2) << " s (";
  for (std::size_t i = 0; i < r.stage_seconds.size(); ++i) {
    md << (i ? ", " : "") << r.stage_seconds[i].first << " " << fixed(r.stage_seconds[i].second, 2) << " s";
  }
  md << ").\n";
  return md.str();
}

void write_assessment(const AssessmentResult& r, const AssessmentInputs& inputs, const std::filesystem::path& dir) {
  AtomicDirectory folder(dir);
  const auto& out = folder.partial_path();
  write_file_atomically(out / "assessment.json", assessment_json(r, inputs) + "\n");
  write_file_atomically(out / "report.md", assessment_markdown(r, inputs));
  write_assessment_figures(r, out);
  geometry::TriMesh pelvis = r.pelvis;
  pelvis.vertex_fields["impingement_motions"] = impingement_field(r, pelvis, false);
  geometry::write_mesh(to_input(r, pelvis), out / "pelvis.vtp");
  geometry::TriMesh femur = scanned(r, r.femur_neutral);
  femur.vertex_fields["impingement_motions"] = impingement_field(r, femur, true);
  geometry::write_mesh(to_input(r, femur), out / "femur.vtp");
  if (r.femur_after_neutral) {
    bool cam = false, rim = false;
    for (const auto& s : r.resections) (s.kind == "cam" ? cam : rim) = true;
    if (cam) geometry::write_mesh(to_input(r, scanned(r, *r.femur_after_neutral)), out / "femur_resected.vtp");
    if (rim && r.pelvis_after) geometry::write_mesh(to_input(r, *r.pelvis_after), out / "pelvis_trimmed.vtp");
  }
  folder.commit([](const std::filesystem::path&) { return false; });
}

}  // namespace hipfai::studies
