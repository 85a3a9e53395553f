#include "studies/pipeline/scene_runner.h"

#include "anatomy/frame_file.h"
#include "studies/pipeline/assessment.h"
#include "studies/pipeline/assessment_report.h"

#include "contact/radial_mapping.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/version.h"
#include "geometry/mesh_io.h"
#include "studies/results/results_file.h"

#ifdef HIPFAI_WITH_FEM
#include "fem/contact_problem.h"
#include "studies/pipeline/hip_fe_run.h"
#endif

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace hipfai::studies {

namespace {

// One row per motion step: the pose, the penetration columns when penetration ran (`run` not
// null), the FE columns when the FE ran.
void write_steps_csv(const std::filesystem::path& path, const Motion& motion, const PenetrationRun* run,
                     const SceneFeResult& fe) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "step,flexion_deg,adduction_deg,internal_rotation_deg,angle_deg";
    if (run) {
      out << ",max_curvilinear_mm,max_radial_mm,curvilinear_vertices,radial_vertices,curvilinear_ms,radial_ms";
    }
    if (fe.ran) {
      out << ",fe_status";
      for (const SceneFeColumn& column : fe.columns) out << ',' << fe_measure_name(column.measure);
    }
    out << '\n';
    out << std::setprecision(10);
    for (std::size_t k = 0; k < motion.steps.size(); ++k) {
      const auto& pose = motion.steps[k].pose;
      out << (k + 1) << ',' << pose.flexion_deg << ',' << pose.adduction_deg << ','
          << pose.internal_rotation_deg << ',' << motion.steps[k].angle_deg;
      if (run) {
        const auto& s = run->steps[k];
        out << ',' << s.curvilinear_max_mm() << ',' << s.radial_max_mm() << ',' << s.curvilinear_vertices << ','
            << s.radial_vertices << ',' << s.curvilinear_ms << ',' << s.radial_ms;
      }
      if (fe.ran) {
        out << ',' << fe.status[k];
        for (const SceneFeColumn& column : fe.columns) out << ',' << column.values[k];
      }
      out << '\n';
    }
  });
}

// The units attribute of an FE column in results.h5: MPa, and how the peak was taken when it is
// not the plain largest value.
const char* units_of(const FeMeasure& measure) {
  const auto* von_mises = std::get_if<VonMisesMeasure>(&measure);
  const auto* pressure = std::get_if<PressureStat>(&measure);
  if ((von_mises && von_mises->stat == VonMisesStat::kBall) || (pressure && *pressure == PressureStat::kBall)) {
    return "MPa (averaged over a ball about the peak)";
  }
  if (von_mises && von_mises->stat == VonMisesStat::kP95) return "MPa (95th percentile over the tissue)";
  return "MPa";
}

#ifdef HIPFAI_WITH_FEM
// Runs (or reuses) the hip FE over the motion and picks the columns the outputs ask for.
SceneFeResult run_fe(const Scene& scene, const Motion& motion, const LoadedHip& hip,
                     const SceneRunOptions& options, StageLog& log) {
  HipFeRunOptions run;
  run.model_dir = hip.dir.string();
  run.motion = fe_motion_of(scene, motion);
  run.level = scene.fe.level;
  run.body_weight_n = scene.fe.body_weight_n;
  run.progress = options.progress;
  run.label = "scene '" + scene.name + "' FE";
  const CachedHipFe cached = run_hip_fe_cached(run, options.cache_dir);
  if (cached.reused) {
    log.hit(StageKind::kFiniteElement);
  } else {
    log.ran(StageKind::kFiniteElement);
  }
  const HipFeTable& table = cached.table;
  if (table.steps.size() != motion.steps.size()) {
    throw_error((cached.entry / "fe.csv").string(), ": ", table.steps.size(), " steps, the motion has ",
                motion.steps.size());
  }

  SceneFeResult fe;
  fe.ran = true;
  fe.reused = cached.reused;
  fe.entry = cached.entry;
  fe.level = scene.fe.level;
  fe.seconds = cached.seconds;
  fe.load = fe_load_description(scene, motion);
  for (const FeStepRecord& step : table.steps) {
    const bool known = step.status >= 0 && step.status <= static_cast<int>(fem::ContactStatus::kNonFinite);
    fe.status_code.push_back(step.status);
    fe.status.push_back(known ? fem::to_string(static_cast<fem::ContactStatus>(step.status)) : "unknown");
    fe.not_converged += !step.converged();
    fe.step_seconds.push_back(step.wall_time_s);
  }
  // One column per measure, each a value per step.
  const auto add_column = [&](const FeMeasure& measure, const auto& value_of) {
    SceneFeColumn column{measure, {}};
    for (const FeStepRecord& step : table.steps) column.values.push_back(value_of(step));
    fe.columns.push_back(std::move(column));
  };
  if (scene.outputs.count(Output::kVonMises)) {
    // The tissues the model has, in the table's order.
    for (const FeTissue tissue : table.tissues) {
      for (const VonMisesStat stat : kVonMisesStats) {
        add_column(VonMisesMeasure{stat, tissue},
                   [&](const FeStepRecord& step) { return step.von_mises(stat, tissue); });
      }
    }
  }
  if (scene.outputs.count(Output::kContactPressure)) {
    for (const PressureStat stat : kPressureStats) {
      add_column(stat, [&](const FeStepRecord& step) { return step.pressure(stat); });
    }
  }
  return fe;
}
#endif

}  // namespace

Motion motion_of(const Scene& scene) {
  switch (scene.motion.kind) {
    case MotionSpec::Kind::kStandingToSitting:
      return standing_to_sitting(scene.motion.sub_motions);
    case MotionSpec::Kind::kMedical:
      return medical_rotation(scene.motion.medical, scene.motion.max_deg, scene.motion.steps);
    case MotionSpec::Kind::kCsv:
      return read_motion_csv(scene.motion.csv);
  }
  return {};
}

Motion fe_motion_of(const Scene& scene, const Motion& motion) {
  Motion fe_motion = motion;
  if (scene.motion.kind == MotionSpec::Kind::kStandingToSitting) {
    SittingDownLoadOptions load;
    load.body_weight_n = scene.fe.body_weight_n;
    attach_sitting_down_load(fe_motion, load);
  }
  return fe_motion;
}

const std::vector<double>& SceneFeResult::column(const FeMeasure& measure) const {
  for (const SceneFeColumn& column : columns) {
    if (column.measure == measure) return column.values;
  }
  throw_error("scene FE results: no column '", fe_measure_name(measure), "'");
}

namespace {

PenetrationOptions penetration_options(const Scene& scene, const SceneRunOptions& options) {
  PenetrationOptions penetration;
  penetration.curvilinear = scene.outputs.count(Output::kCurvilinearDepth) != 0;
  penetration.radial = scene.outputs.count(Output::kRadialDepth) != 0;
  penetration.rom = scene.outputs.count(Output::kRom) != 0;
  penetration.swap_roles = scene.options.swap_roles;
  penetration.mapping = scene.options.mapping;
  penetration.table_size = scene.options.table_size;
  penetration.threads = options.threads;
  penetration.cache_dir = options.cache_dir;
  return penetration;
}

// --vtp-step's 1-based steps (0: the last) as 0-based indices of the motion.
std::vector<std::size_t> vtp_step_indices(const std::vector<int>& steps, const Motion& motion) {
  std::vector<std::size_t> indices;
  for (int step : steps) {
    const int resolved = step == 0 ? static_cast<int>(motion.steps.size()) : step;
    if (resolved < 1 || resolved > static_cast<int>(motion.steps.size())) {
      throw_error("--vtp-step ", step, ": the motion has ", motion.steps.size(), " steps");
    }
    indices.push_back(static_cast<std::size_t>(resolved - 1));
  }
  return indices;
}

// One VTP per tissue with that step's depths, the tissue in its neutral pose.
void write_depth_vtps(const LoadedHip& hip, std::size_t step, const DepthFields& fields,
                      const std::filesystem::path& out_dir) {
  std::map<std::string, geometry::TriMesh> coloured;
  for (const auto& [key, values] : fields) {
    const std::string tissue = key.substr(0, key.find('/'));
    auto [it, inserted] = coloured.try_emplace(tissue, hip.tissues.at(tissue));
    it->second.vertex_fields[key.substr(key.find('/') + 1)] = values;
  }
  for (const auto& [tissue, mesh] : coloured) {
    std::ostringstream name;
    name << tissue << "_step" << std::setw(3) << std::setfill('0') << (step + 1) << ".vtp";
    geometry::write_mesh(mesh, out_dir / name.str());
  }
}

// The bones with the hip's own frame (model.json: the hip frame, HJC and neck axis), the scene's
// motion as the user motion.
AssessmentResult run_assessment(const Motion& motion, const LoadedHip& hip, const SceneRunOptions& options,
                                StageLog& log) {
  AssessmentRequest request;
  request.femur = &hip.tissues.at("femur_bone");
  request.pelvis = &hip.tissues.at("acetabular_bone");
  request.femur_name = "femur_bone";
  request.pelvis_name = "acetabular_bone";
  request.frame = anatomy::read_frame_file(hip.dir / "model.json");
  request.motion = motion;
  request.threads = options.threads;
  AssessmentResult assessment = assess_hip(request);
  log.ran(StageKind::kAssessment);
  if (options.write_files) {
    write_assessment(assessment, {(hip.dir / "femur_bone").string(), (hip.dir / "acetabular_bone").string(),
                                  (hip.dir / "model.json").string(), motion.name},
                     options.out_dir / "assessment");
  }
  return assessment;
}

// The poses and, when penetration ran, the per-step maximum depths, query times, maximum depth
// fields and ranges of motion.
void write_penetration_datasets(ResultsFile& file, const Motion& motion, const PenetrationRun& run,
                                bool penetration_ran, const PenetrationOptions& penetration) {
  std::vector<double> poses, angles, curvilinear, radial, curvilinear_ms, radial_ms;
  for (std::size_t k = 0; k < motion.steps.size(); ++k) {
    const auto& pose = motion.steps[k].pose;
    poses.insert(poses.end(), {pose.flexion_deg, pose.adduction_deg, pose.internal_rotation_deg});
    angles.push_back(motion.steps[k].angle_deg);
    if (!penetration_ran) continue;
    curvilinear.push_back(run.steps[k].curvilinear_max_mm());
    radial.push_back(run.steps[k].radial_max_mm());
    curvilinear_ms.push_back(run.steps[k].curvilinear_ms);
    radial_ms.push_back(run.steps[k].radial_ms);
  }
  file.write("/motion/pose_deg", poses, 3, "deg (flexion, adduction, internal rotation)");
  file.write("/motion/angle_deg", angles, 1, "deg");
  if (penetration.curvilinear) {
    file.write("/curvilinear/max_depth_mm", curvilinear, 1, "mm");
    file.write("/curvilinear/query_ms", curvilinear_ms, 1, "ms");
  }
  if (penetration.radial) {
    file.write("/radial/max_depth_mm", radial, 1, "mm");
    file.write("/radial/query_ms", radial_ms, 1, "ms");
  }
  for (const auto& [key, values] : run.max_fields) {
    file.write("/fields/" + key, values, 1, "mm (maximum over the motion)");
  }
  if (penetration.rom) {
    std::vector<double> axes, ranges;
    for (std::size_t a = 0; a < run.rom.size(); ++a) {
      axes.insert(axes.end(), {run.rom_axes[a].x(), run.rom_axes[a].y(), run.rom_axes[a].z()});
      ranges.insert(ranges.end(), {run.rom[a].anticlockwise_deg, run.rom[a].clockwise_deg});
    }
    file.write("/rom/axis", axes, 3, "unit vector, model coordinates");
    file.write("/rom/range_deg", ranges, 2, "deg (anticlockwise, clockwise)");
  }
}

void write_fe_datasets(ResultsFile& file, const SceneFeResult& fe, const Scene& scene) {
  file.create_group("/fe");
  file.set_attribute("/fe", "level", std::string(to_string(fe.level)));
  file.set_attribute("/fe", "load", fe.load);
  file.set_attribute("/fe", "body_weight_n", scene.fe.body_weight_n);
  file.set_attribute("/fe", "cache_entry", fe.entry.string());
  file.set_attribute("/fe", "steps_not_converged", static_cast<double>(fe.not_converged));
  const std::vector<std::int64_t> codes(fe.status_code.begin(), fe.status_code.end());
  file.write_integers("/fe/status", codes, 1,
                      "fem::ContactStatus: 0 converged, 1 active set not converged, 2 linear solver "
                      "failed, 3 no contact, 4 non-finite");
  file.write_strings("/fe/status_name", fe.status);
  for (const SceneFeColumn& column : fe.columns) {
    file.write("/fe/" + fe_measure_name(column.measure), column.values, 1, units_of(column.measure));
  }
  file.write("/fe/step_time_s", fe.step_seconds, 1, "s (solve time per step when computed)");
}

void write_results_h5(const Scene& scene, const Motion& motion, const SceneRunSummary& summary,
                      bool penetration_ran, const PenetrationOptions& penetration, const std::filesystem::path& path) {
  const SceneFeResult& fe = summary.fe;
  const LoadedHip& hip = summary.hip;
  ResultsFile file(path);
  file.set_attribute("/", "scene_file", scene.file.string());
  file.set_attribute("/", "scene_name", scene.name);
  file.set_attribute("/", "code_version", std::string(kVersion) + " " + kGitSha);
  file.set_attribute("/", "units", fe.ran ? "length mm, angle deg, time ms, stress MPa, force N"
                                          : "length mm, angle deg, time ms");
  file.set_attribute("/", "hip_id", hip.id);
  for (const auto& [tissue, hash] : hip.mesh_hash) file.set_attribute("/", "mesh_hash_" + tissue, hash);
  write_penetration_datasets(file, motion, summary.run, penetration_ran, penetration);
  if (fe.ran) write_fe_datasets(file, fe, scene);
  file.commit();
}

void write_assessment_line(std::ostream& text, const AssessmentResult& assessment, bool wrote_files) {
  const auto& m = assessment.before.measures;
  text << "  assessment: " << anatomy::morphology_name(m.morphology) << ", lateral CE " << m.lateral_ce.ce_deg
       << " deg, alpha " << m.alpha.alpha_deg << " deg";
  if (assessment.before.rom.fadir_internal_rotation.limit) {
    text << ", FADIR internal rotation " << assessment.before.rom.fadir_internal_rotation.limit->angle_deg << " deg";
  }
  if (assessment.motion_depths) {
    text << ", bone-to-bone over the motion: curvilinear " << assessment.motion_depths->max_curvilinear_mm()
         << " mm, radial " << assessment.motion_depths->max_radial_mm() << " mm";
  }
  text << (wrote_files ? " (assessment/)" : "") << '\n';
}

void write_fe_lines(std::ostream& text, const SceneFeResult& fe, const Scene& scene) {
  text << "  FE level " << to_string(fe.level) << " (" << fe.load << "): " << fe.not_converged << " of "
       << fe.status.size() << " steps not converged, " << std::setprecision(1) << fe.seconds << " s"
       << (fe.reused ? " (from the cache " : " (computed, cached in ") << fe.entry.string() << ")\n"
       << std::setprecision(3);
  auto peak = [](const std::vector<double>& values) {
    double p = 0.0;
    for (double v : values) p = std::isfinite(v) ? std::max(p, v) : p;
    return p;
  };
  bool first = true;
  for (const SceneFeColumn& column : fe.columns) {
    const auto* von_mises = std::get_if<VonMisesMeasure>(&column.measure);
    if (!von_mises || von_mises->stat != VonMisesStat::kMax) continue;
    text << (first ? "  peak von Mises (MPa): " : ", ") << to_string(*von_mises->tissue) << ' '
         << peak(column.values);
    first = false;
  }
  if (!first) text << '\n';
  if (scene.outputs.count(Output::kContactPressure)) {
    text << "  peak contact pressure " << peak(fe.column(PressureStat::kMax)) << " MPa\n";
  }
}

std::string summary_text(const Scene& scene, const Motion& motion, const SceneRunSummary& summary,
                         const PenetrationOptions& penetration, const std::optional<AssessmentResult>& assessment,
                         const SceneRunOptions& options) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(3) << "scene '" << scene.name << "', hip " << summary.hip.id << ", "
       << motion.steps.size() << " steps\n";
  if (penetration.curvilinear) {
    text << "  max curvilinear depth " << summary.run.max_curvilinear_mm() << " mm (pre-processing "
         << summary.run.curvilinear_preprocessing_ms << " ms)\n";
  }
  if (penetration.radial) {
    text << "  max radial depth      " << summary.run.max_radial_mm() << " mm (pre-processing "
         << summary.run.radial_preprocessing_ms << " ms)\n";
  }
  for (std::size_t a = 0; a < summary.run.rom.size(); ++a) {
    text << "  ROM about axis " << (a + 1) << ": anticlockwise " << summary.run.rom[a].anticlockwise_deg
         << " deg, clockwise " << summary.run.rom[a].clockwise_deg << " deg\n";
  }
  if (assessment) write_assessment_line(text, *assessment, options.write_files);
  if (summary.fe.ran) write_fe_lines(text, summary.fe, scene);
  text << "  stages executed:";
  for (const auto& [kind, count] : summary.log.executed) text << ' ' << stage_kind_name(kind) << " x" << count;
  if (!summary.log.reused.empty()) {
    text << "; from cache:";
    for (const auto& [kind, count] : summary.log.reused) text << ' ' << stage_kind_name(kind) << " x" << count;
  }
  text << '\n';
  if (options.write_files) text << "  wrote " << (options.out_dir / "results.h5").string() << '\n';
  return text.str();
}

}  // namespace

SceneRunSummary run_scene(const Scene& scene, const Motion& motion, const SceneRunOptions& options) {
#ifndef HIPFAI_WITH_FEM
  if (needs_fe(scene)) {
    throw_error(scene.file.string(), ": outputs von_mises/contact_pressure need the FE module, and this "
                "hipfai was built without it (configure with -DHIPFAI_WITH_FEM=ON)");
  }
#endif
  SceneRunSummary summary;
  summary.hip = acquire_hip(scene, scene.tissues, options.cache_dir, summary.log);
  const PenetrationOptions penetration = penetration_options(scene, options);
  const std::vector<std::size_t> vtp_steps = vtp_step_indices(options.vtp_steps, motion);
  const LoadedHip& hip = summary.hip;
  auto observer = [&](std::size_t step, const DepthFields& fields) {
    if (!options.write_files) return;
    if (std::find(vtp_steps.begin(), vtp_steps.end(), step) == vtp_steps.end()) return;
    write_depth_vtps(hip, step, fields, options.out_dir);
  };
  if (options.write_files) std::filesystem::create_directories(options.out_dir);
  // Penetration stages only for penetration outputs: an FE-only scene builds no table.
  const bool penetration_ran = needs_penetration(scene);
  if (penetration_ran) summary.run = compute_penetration(hip, motion, penetration, summary.log, observer);
  if (needs_fe(scene)) {
#ifdef HIPFAI_WITH_FEM
    summary.fe = run_fe(scene, motion, hip, options, summary.log);
#endif
  }
  std::optional<AssessmentResult> assessment;
  if (scene.outputs.count(Output::kAssessment)) assessment = run_assessment(motion, hip, options, summary.log);
  if (options.write_files) {
    write_results_h5(scene, motion, summary, penetration_ran, penetration, options.out_dir / "results.h5");
    write_steps_csv(options.out_dir / "steps.csv", motion, penetration_ran ? &summary.run : nullptr, summary.fe);
  }
  summary.text = summary_text(scene, motion, summary, penetration, assessment, options);
  return summary;
}

}  // namespace hipfai::studies
