#include "studies/scene_runner.h"

#include "contact/radial_mapping.h"
#include "core/error.h"
#include "core/version.h"
#include "geometry/mesh_io.h"
#include "studies/results_file.h"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace hipfai::studies {

namespace {

contact::RadialMapping mapping_of(const std::string& name) {
  if (name == "spherical") return contact::RadialMapping::kSpherical;
  if (name == "cartesian") return contact::RadialMapping::kCartesian;
  return contact::RadialMapping::kCube;
}

void write_steps_csv(const std::filesystem::path& path, const Motion& motion, const PenetrationRun& run) {
  const std::filesystem::path partial = path.string() + ".partial";
  {
    std::ofstream out(partial);
    out << "step,flexion_deg,adduction_deg,internal_rotation_deg,angle_deg,max_curvilinear_mm,"
           "max_radial_mm,curvilinear_vertices,radial_vertices,curvilinear_ms,radial_ms\n";
    out << std::setprecision(10);
    for (std::size_t k = 0; k < run.steps.size(); ++k) {
      const auto& pose = motion.steps[k].pose;
      const auto& s = run.steps[k];
      out << (k + 1) << ',' << pose.flexion_deg << ',' << pose.adduction_deg << ','
          << pose.internal_rotation_deg << ',' << motion.steps[k].angle_deg << ','
          << s.curvilinear_max_mm() << ',' << s.radial_max_mm() << ',' << s.curvilinear_vertices << ','
          << s.radial_vertices << ',' << s.curvilinear_ms << ',' << s.radial_ms << '\n';
    }
    if (!out) throw_error(path.string(), ": write failed");
  }
  std::filesystem::rename(partial, path);
}

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

SceneRunSummary run_scene(const Scene& scene, const Motion& motion, const SceneRunOptions& options) {
  if (scene.outputs.count(Output::kVonMises) || scene.outputs.count(Output::kContactPressure)) {
    throw_error(scene.file.string(), ": outputs von_mises/contact_pressure need the FE study "
                "(hipfai fem); this runner computes penetration depths and ROM");
  }
  SceneRunSummary summary;
  summary.hip = acquire_hip(scene, scene.tissues, options.cache_dir, summary.log);

  PenetrationOptions penetration;
  penetration.curvilinear = scene.outputs.count(Output::kCurvilinearDepth) != 0;
  penetration.radial = scene.outputs.count(Output::kRadialDepth) != 0;
  penetration.rom = scene.outputs.count(Output::kRom) != 0;
  penetration.swap_roles = scene.options.swap_roles;
  penetration.mapping = mapping_of(scene.options.mapping);
  penetration.table_size = scene.options.table_size;
  penetration.threads = options.threads;
  penetration.cache_dir = options.cache_dir;

  std::vector<std::size_t> vtp_steps;
  for (int step : options.vtp_steps) {
    const int resolved = step == 0 ? static_cast<int>(motion.steps.size()) : step;
    if (resolved < 1 || resolved > static_cast<int>(motion.steps.size())) {
      throw_error("--vtp-step ", step, ": the motion has ", motion.steps.size(), " steps");
    }
    vtp_steps.push_back(static_cast<std::size_t>(resolved - 1));
  }
  const LoadedHip& hip = summary.hip;
  auto observer = [&](std::size_t step, const DepthFields& fields) {
    if (!options.write_files) return;
    if (std::find(vtp_steps.begin(), vtp_steps.end(), step) == vtp_steps.end()) return;
    // One VTP per tissue with that step's depths, the tissue in its neutral pose.
    std::map<std::string, geometry::TriMesh> coloured;
    for (const auto& [key, values] : fields) {
      const std::string tissue = key.substr(0, key.find('/'));
      auto [it, inserted] = coloured.try_emplace(tissue, hip.tissues.at(tissue));
      it->second.vertex_fields[key.substr(key.find('/') + 1)] = values;
    }
    for (const auto& [tissue, mesh] : coloured) {
      std::ostringstream name;
      name << tissue << "_step" << std::setw(3) << std::setfill('0') << (step + 1) << ".vtp";
      geometry::write_mesh(mesh, options.out_dir / name.str());
    }
  };
  if (options.write_files) std::filesystem::create_directories(options.out_dir);
  summary.run = compute_penetration(hip, motion, penetration, summary.log, observer);

  if (options.write_files) {
    ResultsFile file(options.out_dir / "results.h5");
    file.set_attribute("/", "scene_file", scene.file.string());
    file.set_attribute("/", "scene_name", scene.name);
    file.set_attribute("/", "code_version", std::string(kVersion) + " " + kGitSha);
    file.set_attribute("/", "units", "length mm, angle deg, time ms");
    file.set_attribute("/", "hip_id", hip.id);
    for (const auto& [tissue, hash] : hip.mesh_hash) file.set_attribute("/", "mesh_hash_" + tissue, hash);
    std::vector<double> poses, angles, curvilinear, radial, curvilinear_ms, radial_ms;
    for (std::size_t k = 0; k < motion.steps.size(); ++k) {
      const auto& pose = motion.steps[k].pose;
      poses.insert(poses.end(), {pose.flexion_deg, pose.adduction_deg, pose.internal_rotation_deg});
      angles.push_back(motion.steps[k].angle_deg);
      curvilinear.push_back(summary.run.steps[k].curvilinear_max_mm());
      radial.push_back(summary.run.steps[k].radial_max_mm());
      curvilinear_ms.push_back(summary.run.steps[k].curvilinear_ms);
      radial_ms.push_back(summary.run.steps[k].radial_ms);
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
    for (const auto& [key, values] : summary.run.max_fields) {
      file.write("/fields/" + key, values, 1, "mm (maximum over the motion)");
    }
    if (penetration.rom) {
      std::vector<double> axes, ranges;
      for (std::size_t a = 0; a < summary.run.rom.size(); ++a) {
        axes.insert(axes.end(), {summary.run.rom_axes[a].x(), summary.run.rom_axes[a].y(),
                                 summary.run.rom_axes[a].z()});
        ranges.insert(ranges.end(), {summary.run.rom[a].anticlockwise_deg, summary.run.rom[a].clockwise_deg});
      }
      file.write("/rom/axis", axes, 3, "unit vector, model coordinates");
      file.write("/rom/range_deg", ranges, 2, "deg (anticlockwise, clockwise)");
    }
    file.commit();
    write_steps_csv(options.out_dir / "steps.csv", motion, summary.run);
  }

  std::ostringstream text;
  text << std::fixed << std::setprecision(3) << "scene '" << scene.name << "', hip " << hip.id << ", "
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
  text << "  stages executed:";
  for (const auto& [kind, count] : summary.log.executed) text << ' ' << stage_kind_name(kind) << " x" << count;
  if (!summary.log.reused.empty()) {
    text << "; from cache:";
    for (const auto& [kind, count] : summary.log.reused) text << ' ' << stage_kind_name(kind) << " x" << count;
  }
  text << '\n';
  if (options.write_files) text << "  wrote " << (options.out_dir / "results.h5").string() << '\n';
  summary.text = text.str();
  return summary;
}

}  // namespace hipfai::studies
