// Writes the seed corpora of the harnesses into <out>/<harness>/: for the mesh readers a
// tetrahedron with a vertex field in every variant the project's writers make (STL/PLY ascii and
// binary, OBJ, VTP ascii and binary, MSH); for the other readers files made by the project's own
// writers (model.json, motion CSV, estimator model, results file) and its example data (the
// scenes of meshes/scenes/, meshes/real-hips/LHDL_CT/hip.json); for the readers of `hipfai assess`
// (OpenSim motions, user frame files) small files in each layout they accept, and the model.json.
#include "fuzz_tetrahedron.h"
#include "contact/radial_table_io.h"
#include "geometry/hip_model.h"
#include "geometry/mesh_io_msh.h"
#include "geometry/mesh_io_obj.h"
#include "geometry/mesh_io_ply.h"
#include "geometry/mesh_io_stl.h"
#include "geometry/mesh_io_vtp.h"
#include "studies/estimator_model_file.h"
#include "studies/pipeline/motion.h"
#include "studies/results/results_file.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>

namespace {

namespace fs = std::filesystem;
using namespace hipfai;

void put(const fs::path& file, const std::string& bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << bytes;
}

void copy_into(const fs::path& from, const fs::path& dir) {
  fs::create_directories(dir);
  fs::copy_file(from, dir / from.filename(), fs::copy_options::overwrite_existing);
}

void write_mesh_seeds(const fs::path& out) {
  using namespace geometry::mesh_io;
  const geometry::TriMesh mesh = fuzz::tetrahedron();
  put(out / "stl" / "ascii.stl", write_stl("seed", mesh, true));
  put(out / "stl" / "binary.stl", write_stl("seed", mesh, false));
  put(out / "ply" / "ascii.ply", write_ply("seed", mesh, true));
  put(out / "ply" / "binary.ply", write_ply("seed", mesh, false));
  put(out / "obj" / "mesh.obj", write_obj(mesh));
  put(out / "vtp" / "ascii.vtp", write_vtp(mesh, true));
  put(out / "vtp" / "binary.vtp", write_vtp(mesh, false));
  put(out / "msh" / "mesh.msh", write_msh(mesh));
}

// model.json of a model whose five tissues are the tetrahedron (the file names the model_json
// harness's folder has).
void write_model_json_seed(const fs::path& out, const fs::path& work) {
  geometry::HipModel model;
  model.hjc_mm = geometry::Vec3(1, 2, 3);
  model.measured_ce_deg = 21.5;
  model.alpha_profile = {{0.0, 40.0}, {15.0, 42.5}};
  for (const char* tissue : geometry::kHipTissueNames) model.tissues[tissue] = fuzz::tetrahedron();
  geometry::write_hip_model(model, work / "model");
  copy_into(work / "model" / "model.json", out / "model_json");
}

void write_motion_seeds(const fs::path& out) {
  studies::Motion loaded = studies::standing_to_sitting(4);
  studies::attach_sitting_down_load(loaded, {.body_weight_n = 700.0});
  fs::create_directories(out / "motion");
  studies::write_motion_csv(loaded, out / "motion" / "sitting_with_force.csv");
  studies::write_motion_csv(studies::medical_rotation("flexion", 90.0, 3),
                            out / "motion" / "flexion.csv");
}

// OpenSim motion files in the layouts the reader accepts: a version-1 .mot in degrees, a states
// file in radians with OpenSim 4 state paths (left hip), a SIMM-style header without a version.
void write_opensim_motion_seeds(const fs::path& out) {
  put(out / "opensim_motion" / "degrees.mot",
      "walk_ik\nversion=1\nnRows=2\nnColumns=5\ninDegrees=yes\nendheader\n"
      "time\thip_flexion_r\thip_adduction_r\thip_rotation_r\tknee_angle_r\n"
      "0.00\t10.5\t-2.25\t4.0\t-20\n0.01\t12\t-3\t5.5\t-22\n");
  put(out / "opensim_motion" / "states.mot",
      "states\nversion=1\nnRows=2\nnColumns=4\ninDegrees=no\nendheader\n"
      "time\t/jointset/hip_l/hip_flexion_l/value\t/jointset/hip_l/hip_adduction_l/value\t"
      "/jointset/hip_l/hip_rotation_l/value\n0.5\t1.05\t0.2\t-0.1\n0.75\t+0.5\t-0.25\t0\n");
  put(out / "opensim_motion" / "simm.mot",
      "First trial\t\t\nnRows=2\t\t\nnColumns=4\t\t\n\t\t\n# SIMM Motion File Header:\t\t\n"
      "name first trial\ndatacolumns 4\ndatarows 2\nrange 0.400000 0.417000\nendheader\r\n"
      "time\thip_flexion_r\thip_adduction_r\thip_rotation_r\r\n"
      "0.4\t19.67986891\t-2.81547267\t-6.54743948\r\n0.417\t20.1704694\t-3.0099434\t-7.02786216\r\n");
}

// User frame files: axes (both frames), landmarks (both bones), and the model.json of the
// model_json seed (the hip-model shape).
void write_frame_file_seeds(const fs::path& out) {
  put(out / "frame_file" / "axes.json",
      R"({"side": "right", "hjc_mm": [1, 2, 3], "frames": {)"
      R"("pelvis": {"origin_mm": [1, 2, 3], "right": [1, 0, 0], "anterior": [0, 1, 0], "superior": [0, 0, 1]},)"
      R"("femur": {"origin_mm": [1, 2, 3], "right": [0, 1, 0], "anterior": [-1, 0, 0], "superior": [0, 0, 2]}}})");
  put(out / "frame_file" / "landmarks.json",
      R"({"side": "right", "pelvis_landmarks": {"asis_right_mm": [115, 0, 0], "asis_left_mm": [-115, 0, 0],)"
      R"("pubic_tubercle_right_mm": [25, 0, -90], "pubic_tubercle_left_mm": [-25, 0, -90]},)"
      R"("femur_landmarks": {"head_centre_mm": [90, 0, -60], "medial_epicondyle_mm": [50, 0, -495],)"
      R"("lateral_epicondyle_mm": [130, 0, -485]}})");
  copy_into(out / "model_json" / "model.json", out / "frame_file");
}

// A model trained on four hips with a 1 x 2 grid of one tissue (2 features) and 3 steps.
void write_estimator_seed(const fs::path& out) {
  studies::EstimatorModel model;
  model.grid = studies::parse_feature_grid("1x2 femur_bone");
  model.measure = "pressure_max_mpa";
  model.angle_deg = {10.0, 20.0, 30.0};
  model.code_version = "fuzz seed";
  Eigen::MatrixXd features(4, 2), values(4, 3);
  features << 1.0, 2.0, 2.0, 2.5, 3.0, 4.5, 4.0, 4.0;
  values << 1.0, 2.0, 3.0, 1.5, 2.5, 3.5, 2.0, 3.0, 4.5, 2.5, 3.5, 5.0;
  for (Eigen::Index i = 0; i < features.rows(); ++i) {
    studies::TrainingHip hip;
    hip.name = "hip" + std::to_string(i);
    hip.hash = "hash" + std::to_string(i);
    hip.ce_deg = 20.0 + static_cast<double>(i);
    hip.alpha_deg = 40.0;
    hip.edge_mm = 2.0;
    hip.features = features.row(i).transpose();
    for (Eigen::Index j = 0; j < values.cols(); ++j) hip.values.push_back(values(i, j));
    model.hips.push_back(hip);
  }
  stats::EstimatorSettings settings;
  settings.pca.components = 2;
  settings.nearest = 2;
  settings.knn_k = 2;
  model.estimator = stats::train_estimator(features, values, settings);
  studies::write_estimator_model(model, out / "estimator_model" / "model.h5");
}

// The datasets and attributes the results_h5 harness reads, in every kind the writer makes.
void write_results_seed(const fs::path& out) {
  studies::ResultsFile file(out / "results_h5" / "results.h5");
  file.set_attribute("/", "code_version", "fuzz seed");
  file.set_attribute("/", "body_weight_n", 700.0);
  file.create_group("/steps");
  file.write("/steps/rotation", {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, -1, 0, 0, 0, 0, 1}, 9, "1");
  file.write("/steps/angle_deg", {0.0, 90.0}, 1, "deg");
  file.write_integers("/steps/index", {1, 2}, 1, "1");
  file.write_strings("/steps/names", {"first", "second"});
  file.write("/total", {3.5}, 1, "N");
  file.set_attribute("/steps/rotation", "units", "1");
  file.commit();
}

// The first lines of a file, whole lines only (the stored results are long; a seed needs their form).
std::string head_lines(const fs::path& file, int lines) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  std::string text, line;
  for (int k = 0; k < lines && std::getline(in, line); ++k) text += line + '\n';
  return text;
}

void write_text(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
}

// The validation study's stored results (docs/validation-results): steps.csv alone, and steps.csv
// and timings.csv joined by a form feed (fuzz_validation_csv.cpp).
void write_validation_seeds(const fs::path& out, const fs::path& source) {
  const fs::path results = source / "docs" / "validation-results";
  const std::string steps = head_lines(results / "steps.csv", 6);
  write_text(out / "validation_csv" / "steps_only.csv", steps);
  write_text(out / "validation_csv" / "steps_and_timings.csv", steps + '\f' + head_lines(results / "timings.csv", 3));
}

// An FE run's per-step table in the layout write_hip_fe_csv writes (studies/pipeline/hip_fe_run.cpp): two
// bodies, two steps, every column kind (numbers, a surface name, an empty cell).
void write_fe_csv_seed(const fs::path& out) {
  std::string header = "step,status,ranks,dofs,active_set_iterations,max_pressure_mpa,mean_pressure_mpa,"
                       "contact_area_mm2,max_penetration_mm,tx_mm,ty_mm,tz_mm";
  for (const char* kind : {"max_von_mises_mpa", "p95_von_mises_mpa"}) {
    for (const char* body : {"femoral cartilage", "labrum"}) header += std::string(",") + kind + " " + body;
  }
  header += ",wall_time_s,sub_steps,cutbacks,linear_solves,peak_radius_mm,ball_peak_pressure_mpa,"
            "ball_peak_von_mises_mpa femoral cartilage,ball_peak_von_mises_mpa labrum,max_pressure_surface\n";
  const std::string rows =
      "1,0,1,48015,3,1.25,0.5,120.5,0.01,0,0,-1e-3,1.9,1.1,0.8,0.4,5.5,1,0,2,1,1.2,1.5,0.9,labrum\n"
      "2,1,1,48015,12,nan,,0,0,0,0,0,inf,1e300,0.8,0.4,6,2,1,9,1,-0,,nan,femoral_cartilage\n";
  write_text(out / "fe_csv" / "fe.csv", header + rows);
}

// A radial table as the cache stores it: a spherical grid of 2 x 2 cells, three triangles (one in
// two cells, one always a candidate).
void write_radial_table_seed(const fs::path& out) {
  contact::RadialTable table;
  table.grid.mapping = contact::RadialMapping::kSpherical;
  table.grid.faces = 1;
  table.grid.dimension = 2;
  table.centre = contact::Vec3(1.0, -2.0, 0.5);
  table.num_triangles = 3;
  table.cells = {{0}, {0, 1}, {}, {}};
  table.triangle_cells = {{0, 1}, {1}, {}};
  table.always_candidates = {2};
  table.is_always = {0, 0, 1};
  contact::save_radial_table(table, out / "radial_table" / "table.bin");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: make_fuzz_seeds OUT_DIR SOURCE_DIR\n";
    return 2;
  }
  const fs::path out = argv[1], source = argv[2];
  try {
    write_mesh_seeds(out);
    write_model_json_seed(out, out / "work");
    fs::remove_all(out / "work");
    write_motion_seeds(out);
    write_opensim_motion_seeds(out);
    write_frame_file_seeds(out);
    write_estimator_seed(out);
    write_results_seed(out);
    write_validation_seeds(out, source);
    write_fe_csv_seed(out);
    write_radial_table_seed(out);
    for (const auto& entry : fs::directory_iterator(source / "meshes" / "scenes")) {
      copy_into(entry.path(), out / "scene");
    }
    copy_into(source / "meshes" / "real-hips" / "LHDL_CT" / "hip.json", out / "hip_json");
    // Files on which HDF5 itself reads past its buffers: under the sanitizers they crash HDF5, and
    // the readers must refuse them (studies/results/hdf5_child.h) rather than go down with it.
    for (const auto& entry : fs::directory_iterator(source / "tests" / "data" / "hdf5-crashes")) {
      copy_into(entry.path(), out / "results_h5");
      copy_into(entry.path(), out / "estimator_model");
    }
  } catch (const std::exception& error) {
    std::cerr << "make_fuzz_seeds: " << error.what() << '\n';
    return 1;
  }
  return 0;
}
