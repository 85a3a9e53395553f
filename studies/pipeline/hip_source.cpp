#include "studies/pipeline/hip_source.h"

#include "anatomy/frame_file.h"
#include "core/atomic_file.h"
#include "core/cache_entry.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/literature.h"
#include "core/source_hashes.h"
#include "geometry/hip_generator.h"
#include "geometry/hip_model.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_io_common.h"
#include "studies/pipeline/soft_tissue_model.h"

#include <Eigen/Geometry>

#include <cmath>
#include <sstream>

namespace hipfai::studies {

namespace {

geometry::HipParameters parameters_of(const ParametricHip& hip) {
  geometry::HipParameters parameters = hip.base.value_or(geometry::HipParameters{});
  parameters.ce_deg = hip.ce_deg;
  parameters.alpha_deg = hip.alpha_deg;
  parameters.edge_mm = hip.edge_mm;
  return parameters;
}

}  // namespace

namespace {

std::vector<double> steps_deg(double first, double last) {
  std::vector<double> values;
  for (double value = first; value <= last + 1e-9; value += literature::kStudyStepDeg) values.push_back(value);
  return values;
}

}  // namespace

std::vector<double> study_ce_deg() { return steps_deg(literature::kStudyCeMinDeg, literature::kStudyCeMaxDeg); }

std::vector<double> study_alpha_deg() {
  return steps_deg(literature::kStudyAlphaMinDeg, literature::kStudyAlphaMaxDeg);
}

std::vector<std::pair<double, double>> study_grid_angles() {
  std::vector<std::pair<double, double>> grid;
  for (const double ce : study_ce_deg()) {
    for (const double alpha : study_alpha_deg()) grid.emplace_back(ce, alpha);
  }
  return grid;
}

std::string parametric_hip_id(double ce_deg, double alpha_deg) {
  std::ostringstream id;
  id << "ce" << ce_deg << "_alpha" << alpha_deg;
  return id.str();
}

LoadedHip loaded_hip_from_model(const geometry::HipModel& model, const std::string& id,
                                const std::set<std::string>& tissues) {
  LoadedHip hip;
  hip.id = id;
  hip.hjc_mm = model.hjc_mm;
  hip.frame.col(0) = model.axes.flexion_axis;
  hip.frame.col(1) = model.axes.adduction_axis;
  hip.frame.col(2) = model.axes.internal_rotation_axis;
  hip.ce_deg = model.parameters.ce_deg;
  hip.alpha_deg = model.parameters.alpha_deg;
  hip.articular_radius_mm = model.parameters.articular_radius_mm;
  for (const auto& [name, mesh] : model.tissues) {
    if (!tissues.empty() && tissues.count(name) == 0) continue;
    hip.tissues[name] = mesh;
    hip.mesh_hash[name] = geometry::mesh_hash(mesh);
  }
  return hip;
}

std::filesystem::path generated_hip_dir(const ParametricHip& hip, const std::filesystem::path& cache_dir) {
  Hasher key;
  key.add(geometry::hip_parameters_to_json(parameters_of(hip))).add(kHipSourceHash);
  return cache_dir / ("hip-" + parametric_hip_id(hip.ce_deg, hip.alpha_deg) + "-" + key.hex());
}

LoadedHip acquire_hip(const Scene& scene, const std::set<std::string>& tissues,
                      const std::filesystem::path& cache_dir, StageLog& log) {
  LoadedHip hip;
  if (scene.parametric) {
    hip.id = parametric_hip_id(scene.parametric->ce_deg, scene.parametric->alpha_deg);
    hip.dir = generated_hip_dir(*scene.parametric, cache_dir);
    // Written beside the final folder and renamed, so an interrupted run leaves no half model;
    // made once when several jobs sharing the cache ask for it together (core/cache_entry.h).
    const EntrySource source = make_cache_entry(
        hip.dir, [](const std::filesystem::path& dir) { return std::filesystem::exists(dir / "model.json"); },
        [&](AtomicDirectory& staging) {
          const auto generated = geometry::generate_hip(parameters_of(*scene.parametric));
          geometry::write_hip_model(generated.model, staging.partial_path(), "ply");
        });
    if (source == EntrySource::kMade) {
      log.ran(StageKind::kGenerateHip);
    } else {
      log.hit(StageKind::kGenerateHip);
    }
  } else if (scene.bones) {
    // The bones dressed once (studies/pipeline/soft_tissue_model.h), kept in the cache by the content of
    // the files and choices that make the folder.
    const SceneBones& bones = *scene.bones;
    Hasher key;
    key.add(std::string_view("dressed-bones-v1")).add(std::string_view(kHipSourceHash));
    for (const std::filesystem::path& file : {bones.femur, bones.pelvis, bones.frame}) {
      key.add(file.empty() ? std::string() : geometry::mesh_io::read_file_bytes(file));
    }
    key.add(std::string_view(bones.side ? anatomy::side_name(*bones.side) : "found"));
    hip.id = bones.femur.stem().string();
    hip.dir = cache_dir / ("dressed-" + hip.id + "-" + key.hex());
    if (std::filesystem::exists(hip.dir / "model.json")) {
      log.hit(StageKind::kDressBones);
    } else {
      const geometry::TriMesh femur = geometry::read_mesh(bones.femur);
      const geometry::TriMesh pelvis = geometry::read_mesh(bones.pelvis);
      SoftTissueModelRequest request;
      request.assessment.femur = &femur;
      request.assessment.pelvis = &pelvis;
      request.assessment.femur_name = bones.femur.string();
      request.assessment.pelvis_name = bones.pelvis.string();
      request.assessment.side = bones.side;
      if (!bones.frame.empty()) request.assessment.frame = anatomy::read_frame_file(bones.frame);
      std::filesystem::create_directories(cache_dir);
      write_soft_tissue_model(build_soft_tissue_model(request), bones.femur.string(), bones.pelvis.string(), hip.dir);
      log.ran(StageKind::kDressBones);
    }
  } else {
    hip.dir = scene.model_dir;
    hip.id = scene.model_dir.filename().string();
    log.ran(StageKind::kLocateHip);
  }
  const geometry::HipModel model = geometry::load_hip_model(hip.dir, tissues);
  LoadedHip loaded = loaded_hip_from_model(model, hip.id, tissues);
  loaded.dir = hip.dir;
  for (std::size_t k = 0; k < loaded.tissues.size(); ++k) log.ran(StageKind::kLoadTissue);
  hip = std::move(loaded);
  return hip;
}

void put_femur_at_neutral(LoadedHip& hip, geometry::FemoralNeutral neutral) {
  if (neutral == geometry::FemoralNeutral::kShaftAxis) return;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(literature::kAnatomicMechanicalAngleDeg * geometry::kDegToRad, hip.frame.col(1).normalized())
          .toRotationMatrix();
  for (const char* tissue : {"femur_bone", "femoral_cartilage"}) {
    const auto mesh = hip.tissues.find(tissue);
    if (mesh == hip.tissues.end()) continue;
    for (geometry::Vec3& v : mesh->second.vertices) v = hip.hjc_mm + rotation * (v - hip.hjc_mm);
    hip.mesh_hash[tissue] += "+mechanical-neutral";
  }
}

}  // namespace hipfai::studies
