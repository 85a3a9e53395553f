#include "studies/hip_sensitivity.h"

#include "contact/range_finder.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "geometry/hip_generator.h"
#include "geometry/hip_measure.h"
#include "geometry/sphere_split.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/motion.h"
#include "studies/pipeline/penetration_run.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <limits>

namespace hipfai::studies {
namespace {

// The triangles whose three vertices lie farther than `min_radius_mm` from `centre` (the striking
// part; see hip_sensitivity.h), re-indexed. With `exact_border` the surface is first split along
// that sphere (geometry::split_at_sphere), so the part is the whole surface beyond it, up to the
// chords that replace the border's arcs, instead of the triangles that happen to lie wholly beyond.
geometry::TriMesh striking_part(const geometry::TriMesh& surface, const geometry::Vec3& centre, double min_radius_mm,
                                bool exact_border) {
  if (exact_border) {
    // The new vertices lie on the sphere up to rounding: kept from a hair inside it.
    return striking_part(geometry::split_at_sphere(surface, centre, min_radius_mm).mesh, centre,
                         min_radius_mm * (1.0 - 1e-12), false);
  }
  const geometry::TriMesh& femur = surface;
  geometry::TriMesh out;
  std::vector<std::int32_t> index(femur.vertices.size(), -1);
  for (const auto& tri : femur.triangles) {
    bool striking = true;
    for (auto v : tri) striking = striking && (femur.vertices[static_cast<std::size_t>(v)] - centre).norm() > min_radius_mm;
    if (!striking) continue;
    geometry::Triangle mapped{};
    for (std::size_t c = 0; c < 3; ++c) {
      auto& slot = index[static_cast<std::size_t>(tri[c])];
      if (slot < 0) {
        slot = static_cast<std::int32_t>(out.vertices.size());
        out.vertices.push_back(femur.vertices[static_cast<std::size_t>(tri[c])]);
      }
      mapped[c] = slot;
    }
    out.triangles.push_back(mapped);
  }
  return out;
}

}  // namespace

double first_striking_contact_deg(const geometry::TriMesh& femur, const geometry::TriMesh& labrum,
                                  const geometry::Vec3& centre, const Eigen::Vector3d& axis, double min_radius_mm,
                                  int threads, bool exact_border) {
  // Both roles: the femur's striking part against the whole labrum, and the whole femur against
  // the labrum's striking part (a labrum vertex may enter the femur through a triangle that
  // straddles the R + tol sphere). The articular faces, on the R sphere, touch in neutral and
  // are left out on one side each.
  contact::RangeOfMotionOptions rom;
  rom.query.num_threads = threads;
  double first = std::numeric_limits<double>::infinity();
  const geometry::TriMesh femur_striking = striking_part(femur, centre, min_radius_mm, exact_border);
  if (!femur_striking.triangles.empty()) {
    first = std::min(first, contact::range_of_motion(labrum, femur_striking, centre, axis, rom).anticlockwise_deg);
  }
  const geometry::TriMesh labrum_striking = striking_part(labrum, centre, min_radius_mm, exact_border);
  if (!labrum_striking.triangles.empty()) {
    first = std::min(first, contact::range_of_motion(labrum_striking, femur, centre, axis, rom).anticlockwise_deg);
  }
  return first >= 360.0 ? std::numeric_limits<double>::infinity() : first;
}

namespace {

geometry::HipParameters with(geometry::HipParameters p, const std::string& field, double value) {
  nlohmann::json json = nlohmann::json::parse(geometry::hip_parameters_to_json(p));
  if (!json.contains(field)) throw_error("sensitivity: unknown hip parameter '", field, "'");
  json[field] = value;
  return geometry::hip_parameters_from_json(json.dump(), "sensitivity: " + field);
}

double field_value(const geometry::HipParameters& p, const std::string& field) {
  const nlohmann::json json = nlohmann::json::parse(geometry::hip_parameters_to_json(p));
  return json.at(field).get<double>();
}

}  // namespace

std::vector<SensitivityVariant> default_sensitivity_variants() {
  return {
      {"cam_end_deg", 22.5, "cam arc to 2:15 (narrower)"},
      {"cam_end_deg", 90.0, "cam arc to 12:00 (Rakhra 2009: cam between 12 and 3 o'clock)"},
      {"cam_begin_deg", -30.0, "cam arc from 4:00"},
      {"cam_height_mm", 2.0, "Gosvig 2007 threshold (2 mm outside the head radius)"},
      {"cam_height_mm", 4.0, "a larger cam"},
      {"cam_radius_mm", 6.0, "sharper cam section"},
      {"cam_radius_mm", 15.0, "flatter cam section"},
      {"neck_radius_mm", 12.0, "anterior head-neck offset 13 mm"},
      {"neck_radius_mm", 14.5, "offset 10.5 mm (Eijer 2001 normal ~11.6 mm)"},
      {"neck_shaft_angle_deg", 125.0, "CCD 125 (normal 125-135)"},
      {"neck_shaft_angle_deg", 135.0, "CCD 135"},
      {"femoral_anteversion_deg", 5.0, "low femoral version (normal 10-20)"},
      {"femoral_anteversion_deg", 20.0, "high femoral version"},
      {"acetabular_anteversion_deg", 10.0, "low acetabular version (normal 15-20)"},
      {"acetabular_anteversion_deg", 25.0, "high acetabular version"},
      {"hemisphere_ce_deg", 15.0, "socket a hemisphere at CE 15"},
      {"hemisphere_ce_deg", 25.0, "socket a hemisphere at CE 25"},
      {"ce_rim_mode", 1.0, "CE by tilting a hemisphere (lateral only; earlier model)"},
      {"labrum_height_mm", 5.0, "labrum 5 mm"},
      {"labrum_height_mm", 9.0, "labrum 9 mm"},
      {"labrum_base_mm", 4.7, "Seldes 2001 lower bound"},
      {"labrum_base_mm", 6.4, "Seldes 2001 upper bound"},
  };
}

SensitivityResult run_hip_sensitivity(const SensitivityOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<SensitivityVariant> variants =
      options.variants.empty() ? default_sensitivity_variants() : options.variants;
  if (!options.only_parameters.empty()) {
    std::vector<SensitivityVariant> kept;
    for (const std::string& name : options.only_parameters) {
      const auto before = kept.size();
      for (const auto& v : variants) {
        if (v.field == name) kept.push_back(v);
      }
      if (kept.size() == before) {
        std::string known;
        for (const auto& v : variants) {
          if (known.find(v.field) == std::string::npos) known += (known.empty() ? "" : ", ") + v.field;
        }
        throw_error("study sensitivity: no variants of parameter '", name, "' (known: ", known, ")");
      }
    }
    variants = std::move(kept);
  }
  const Motion motion = standing_to_sitting(options.sub_motions);
  SensitivityResult result;
  result.motion_angle_deg = motion.steps.back().angle_deg;
  result.edge_mm = options.edge_mm;

  std::vector<std::pair<std::string, SensitivityVariant>> jobs;
  jobs.push_back({"(defaults)", {"(defaults)", 0.0, "shipped defaults"}});
  for (const auto& v : variants) jobs.push_back({v.field, v});
  ProgressBar progress("hip sensitivity: " + std::to_string(jobs.size() * options.hips.size()) + " hips",
                       jobs.size() * options.hips.size(), options.progress);
  for (const auto& [field, variant] : jobs) {
    for (const auto& hip_spec : options.hips) {
      SensitivityRow row;
      row.field = field;
      row.note = variant.note;
      row.hip = hip_spec.label;
      row.ce_deg = hip_spec.ce_deg;
      row.alpha_deg = hip_spec.alpha_deg;
      try {
        geometry::HipParameters p;
        p.ce_deg = hip_spec.ce_deg;
        p.alpha_deg = hip_spec.alpha_deg;
        p.edge_mm = options.edge_mm;
        if (field != "(defaults)") {
          row.is_default = field_value(p, field) == variant.value;
          p = with(p, field, variant.value);
          row.value = variant.value;
        } else {
          row.is_default = true;
        }
        const geometry::HipModel model = geometry::generate_hip(p).model;
        row.measured_ce_deg = model.measured_ce_deg;
        row.measured_alpha_deg = model.measured_alpha_notzli_deg;
        const LoadedHip hip = loaded_hip_from_model(model, field);
        PenetrationOptions penetration;
        penetration.threads = options.threads;
        StageLog log;
        const PenetrationRun run = compute_penetration(hip, motion, penetration, log);
        row.max_curvilinear_mm = run.max_curvilinear_mm();
        row.max_radial_mm = run.max_radial_mm();
        // The striking region begins where the run's does: at R plus the tolerance it applied.
        const Eigen::Vector3d axis = (hip.frame * motion.steps.front().axis).normalized();
        row.first_contact_deg = first_striking_contact_deg(
            model.tissue("femur_bone"), model.tissue("labrum"), model.hjc_mm, axis,
            hip.articular_radius_mm + run.contact_tolerance_mm, options.threads);
      } catch (const Error& e) {
        row.error = e.what();
      }
      result.rows.push_back(row);
      progress.advance();
    }
  }
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace hipfai::studies
