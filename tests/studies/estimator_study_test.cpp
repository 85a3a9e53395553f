#include "studies/estimator_study.h"

#include "core/error.h"
#include "geometry/hip_model.h"
#include "geometry/primitive_meshes.h"
#include "studies/estimator_model_file.h"
#include "studies/pipeline/motion.h"
#include "studies/results/results_file.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <hdf5.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <string>

namespace hipfai::studies {
namespace {

namespace fs = std::filesystem;

fs::path estimator_scratch(const std::string& name) {
  const fs::path dir = fs::path(HIPFAI_BINARY_DIR) / "test-scratch" / ("estimator-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A "hip" of four concentric spheres about the HJC (octaspheres, level 4: chord sagitta well under
// 0.1 mm at these radii), the femur's radius `r`; CE = r so the FE rows can be matched to it.
geometry::HipModel sphere_hip(double r) {
  geometry::HipModel model;
  model.parameters.ce_deg = r;
  model.parameters.alpha_deg = 50;
  model.parameters.edge_mm = 2;
  const geometry::Vec3 o = geometry::Vec3::Zero();
  model.tissues["femur_bone"] = geometry::make_octasphere(o, r, 4);
  model.tissues["femoral_cartilage"] = geometry::make_octasphere(o, r + 2, 4);
  model.tissues["acetabular_cartilage"] = geometry::make_octasphere(o, r + 4, 4);
  model.tissues["labrum"] = geometry::make_octasphere(o, r + 6, 4);
  return model;
}

// Writes hips with femur radius 20..26 mm and a steps.csv whose "pressure" is a known function of
// that radius: (1 + 0.1 step) (r - 15) MPa over 4 steps.
void write_sphere_study(const fs::path& dir, const std::vector<double>& radii, int steps, double angle_step) {
  std::ofstream csv(dir / "fe" / "steps.csv");
  csv << "ce_deg,alpha_deg,step,angle_deg,pressure_max_mpa\n";
  for (const double r : radii) {
    geometry::write_hip_model(sphere_hip(r), dir / "hips" / ("hip-" + std::to_string(static_cast<int>(r))));
    for (int s = 1; s <= steps; ++s) {
      csv << r << ",50," << s << ',' << angle_step * s << ',' << (1 + 0.1 * s) * (r - 15) << '\n';
    }
  }
}

// Validation of the sphere study written by write_sphere_study into `dir`, results in dir/out.
EstimatorValidateOptions sphere_validate_options(const fs::path& dir, int max_e_prime) {
  EstimatorValidateOptions options;
  options.train.fe = {dir / "fe"};
  options.train.hips = dir / "hips";
  options.train.progress = false;
  options.out_dir = dir / "out";
  options.max_e_prime = max_e_prime;
  return options;
}

TEST(PressureFeatures, SpheresGiveTheirRadiusEverywhere) {
  const geometry::HipModel hip = sphere_hip(25);
  const FeatureGrid grid;
  const HipFeatures features = extract_hip_features(hip, grid);
  ASSERT_EQ(features.values.size(), 1944);
  EXPECT_EQ(features.misses, 0);
  for (int t = 0; t < 4; ++t) {
    for (int k = 0; k < 486; ++k) {
      // Inside the octasphere: at most the radius, and no nearer than its chord sagitta allows.
      const double r = 25.0 + 2.0 * t;
      EXPECT_LE(features.values(t * 486 + k), r + 1e-9);
      EXPECT_GT(features.values(t * 486 + k), r - 0.15);
    }
  }
}

TEST(PressureFeatures, FarthestCrossingAndMissesOnAnOffCentreBox) {
  geometry::HipModel hip = sphere_hip(25);
  // A box from x = 10 to 30 around the +X axis: rays towards -X miss it (R = 0); the ray along
  // +X-ish directions leaves it at its far face x = 30 (not the near face x = 10).
  hip.tissues["labrum"] = geometry::make_box({10, -5, -5}, {30, 5, 5}, 2);
  FeatureGrid grid;
  grid.polar_steps = 1;       // the single polar cell's centre is the equator
  grid.azimuth_steps = 4;     // azimuth 45, 135, 225, 315 deg
  grid.tissues = {"labrum"};
  EXPECT_EQ(extract_hip_features(hip, grid).misses, 4);  // 45 deg off the axis: outside the box
  grid.azimuth_steps = 1;     // azimuth 180 deg: -X, a miss
  EXPECT_EQ(extract_hip_features(hip, grid).values(0), 0.0);
  grid.azimuth_steps = 2;     // azimuth 90 and 270 deg: misses
  EXPECT_EQ(extract_hip_features(hip, grid).misses, 2);
  grid.azimuth_steps = 36;    // azimuth 5 deg: through the box, leaving at x = 30
  const HipFeatures features = extract_hip_features(hip, grid);
  EXPECT_NEAR(features.values(0), 30.0 / std::cos(5.0 * M_PI / 180.0), 1e-9);
  hip.tissues.erase("labrum");
  EXPECT_THROW(extract_hip_features(hip, grid), Error);
}

TEST(EstimatorStudy, ImpingingHipsAreThoseWithPenetrationInTheCaseSteps) {
  // The sphere study with the penetration depths of `study validate`: hips of radius >= 25 mm
  // "impinge" from step 3 of 4 (curvilinear depth for 25, radial for 26), the others never. Case 1
  // (steps 1-2) has no impinging hip; case 2 (steps 1-4) has those two.
  const fs::path dir = estimator_scratch("impinging");
  fs::create_directories(dir / "fe");
  write_sphere_study(dir, {20, 21, 22, 23, 24, 25, 26}, 4, 10.0);
  {
    std::ifstream in(dir / "fe" / "steps.csv");
    std::ostringstream with_depths;
    std::string line;
    std::getline(in, line);
    with_depths << line << ",max_curvilinear_mm,max_radial_mm\n";
    while (std::getline(in, line)) {
      const double r = std::stod(line.substr(0, line.find(',')));
      const int step = std::stoi(line.substr(line.find(",50,") + 4));
      const bool late = step >= 3;
      with_depths << line << ',' << (late && r == 25 ? 1.5 : 0.0) << ',' << (late && r == 26 ? 0.7 : 0.0) << '\n';
    }
    std::ofstream(dir / "fe" / "steps.csv") << with_depths.str();
  }
  EstimatorValidateOptions options = sphere_validate_options(dir, 2);
  const auto summary = validate_estimator(options);
  EXPECT_EQ(summary.impinging[0], 0);
  EXPECT_EQ(summary.impinging[1], 2);
  std::ifstream loo(dir / "out" / "loo.csv");
  std::string line;
  std::getline(loo, line);
  int rows = 0;
  while (std::getline(loo, line)) {
    ++rows;
    const std::size_t first_comma = line.find(',');
    const bool case2 = line.substr(first_comma + 1, 2) == "2,";
    const bool impinging_hip = line.rfind("ce25", 0) == 0 || line.rfind("ce26", 0) == 0;
    EXPECT_EQ(line.back(), case2 && impinging_hip ? '1' : '0') << line;
  }
  EXPECT_GT(rows, 0);
  const std::string report = [&] {
    std::ifstream in(dir / "out" / "report.md");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  EXPECT_NE(report.find("## Where it fails: hips that impinge"), std::string::npos);

  // A depth that is not a number >= 0 is refused with the line.
  std::ofstream(dir / "fe" / "steps.csv", std::ios::app) << "20,50,5,50,1,-1,0\n";
  EXPECT_THROW(validate_estimator(options), Error);
}

TEST(EstimatorStudy, LeaveOneOutOnSphereHipsAndModelFile) {
  const fs::path dir = estimator_scratch("spheres");
  fs::create_directories(dir / "fe");
  write_sphere_study(dir, {20, 21, 22, 23, 24, 25, 26}, 4, 10.0);
  EstimatorValidateOptions options = sphere_validate_options(dir, 3);
  const auto summary = validate_estimator(options);
  EXPECT_EQ(summary.hips[0], 7);
  // Pressure is linear in every feature: ridge finds it on the interior hips (radius 21-25).
  EXPECT_LT(summary.interior_error[0][2], 1.0);
  // The thesis' method answers with a neighbour's value: radius +-1 mm of (r - 15) >= 6 mm is at
  // most 1/6 = 17 %; a wrong neighbour choice (2 mm off) would exceed it on most hips.
  EXPECT_LT(summary.interior_error[0][0], 17.0);
  for (const char* file : {"loo.csv", "estimates.csv", "hips.csv", "report.md", "model.h5", "fig73_case1.svg"}) {
    EXPECT_TRUE(fs::exists(dir / "out" / file)) << file;
  }
  std::ifstream loo(dir / "out" / "loo.csv");
  std::string header;
  std::getline(loo, header);
  EXPECT_EQ(header, "hip,case,e_prime,method,mean_abs_error_percent,bordering,impinging");
  // A table without penetration depths: the impinging column stays empty.
  std::string row;
  std::getline(loo, row);
  EXPECT_EQ(row.back(), ',') << row;
  EXPECT_EQ(summary.impinging[0] + summary.impinging[1], 0);
  // coverage.csv: one row per case and method with intervals (no depths: no depth_nn rows), each
  // share the count over the steps counted.
  std::ifstream coverage(dir / "out" / "coverage.csv");
  std::getline(coverage, header);
  EXPECT_EQ(header,
            "case,method,e_prime,steps,undefined_steps,covered,coverage,large_error_steps,large_error_flagged,flag_recall");
  int coverage_rows = 0;
  for (std::string line; std::getline(coverage, line); ++coverage_rows) {
    std::vector<std::string> cells;
    std::stringstream cells_in(line);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 10u) << line;
    EXPECT_NE(cells[1], "depth_nn");
    const double steps = std::stod(cells[3]), covered = std::stod(cells[5]);
    EXPECT_EQ(steps + std::stod(cells[4]), 7 * (cells[0] == "1" ? 2 : 4)) << line;  // 7 hips x the case's steps
    if (steps > 0) {
      EXPECT_NEAR(std::stod(cells[6]), covered / steps, 1e-9) << line;
    }
  }
  EXPECT_EQ(coverage_rows, 6);

  // Round trip: a reloaded model predicts bit-identically.
  EstimatorTrainOptions train = options.train;
  const EstimatorModel model = train_estimator_model(train);
  write_estimator_model(model, dir / "model.h5");
  const EstimatorModel reloaded = read_estimator_model(dir / "model.h5");
  EXPECT_EQ(reloaded.grid.describe(), model.grid.describe());
  EXPECT_EQ(reloaded.hips.size(), 7u);
  EXPECT_EQ(reloaded.hips[3].hash, model.hips[3].hash);
  geometry::write_hip_model(sphere_hip(23.5), dir / "target");
  for (const auto method : stats::kEstimatorMethods) {
    if (stats::needs_depths(method)) continue;  // this table has no depths (DepthNn... below)
    const auto a = predict_hip(model, dir / "target", method, 3).result;
    const auto b = predict_hip(reloaded, dir / "target", method, 3).result;
    ASSERT_EQ(a.steps.size(), 4u);
    for (std::size_t j = 0; j < 4; ++j) {
      EXPECT_EQ(a.steps[j].estimate, b.steps[j].estimate);
      EXPECT_EQ(a.steps[j].low, b.steps[j].low);
      EXPECT_EQ(a.steps[j].high, b.steps[j].high);
    }
    EXPECT_EQ(a.bordering, b.bordering);
  }
  // A hip far outside the training radii is flagged.
  geometry::write_hip_model(sphere_hip(35), dir / "far");
  EXPECT_TRUE(predict_hip(model, dir / "far", stats::EstimatorMethod::kPcaNn, 3).result.bordering);
  EXPECT_FALSE(predict_hip(model, dir / "target", stats::EstimatorMethod::kPcaNn, 3).result.bordering);
}

// One-line error whose text contains `needle`.
void expect_error(const std::function<void()>& call, const std::string& needle) {
  try {
    call();
    ADD_FAILURE() << "no error; expected one containing '" << needle << "'";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(needle), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

// Training options on a sphere study of radii 20, 22, 24, 26 mm written into estimator_scratch(name).
EstimatorTrainOptions four_sphere_training(const std::string& name, int steps) {
  const fs::path dir = estimator_scratch(name);
  fs::create_directories(dir / "fe");
  write_sphere_study(dir, {20, 22, 24, 26}, steps, 10.0);
  EstimatorTrainOptions train;
  train.fe = {dir / "fe"};
  train.hips = dir / "hips";
  train.progress = false;
  return train;
}

TEST(EstimatorStudy, RejectsBadModelFilesAndMismatchedRetraining) {
  EstimatorTrainOptions train = four_sphere_training("reject", 3);
  const fs::path dir = train.hips.parent_path();
  const EstimatorModel model = train_estimator_model(train);
  write_estimator_model(model, dir / "model.h5");

  expect_error([&] { read_estimator_model(dir / "missing.h5"); }, "no such model file");
  std::ofstream(dir / "garbage.h5") << "not hdf5 at all\n";
  expect_error([&] { read_estimator_model(dir / "garbage.h5"); }, "not a hipfai estimator model");
  {
    ResultsFile foreign(dir / "foreign.h5");
    foreign.set_attribute("/", "format", "something-else");
    foreign.commit();
  }
  expect_error([&] { read_estimator_model(dir / "foreign.h5"); }, "not a hipfai estimator model");
  {
    // Truncated copy: HDF5 cannot open it.
    std::ifstream in(dir / "model.h5", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir / "truncated.h5", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  EXPECT_THROW(read_estimator_model(dir / "truncated.h5"), Error);
  {
    // A model whose PCA does not match its grid.
    ResultsFile bad(dir / "inconsistent.h5");
    bad.set_attribute("/", "format", "hipfai-pressure-estimator");
    bad.set_attribute("/", "feature_grid", "2x2 femur_bone");
    bad.write("/pca/total_variance", {1.0}, 1, "1");
    bad.commit();
  }
  expect_error([&] { read_estimator_model(dir / "inconsistent.h5"); }, "corrupt estimator model");

  // Retraining: more FE results with another motion are refused; so is another grid.
  fs::create_directories(dir / "fe2");
  {
    std::ofstream csv(dir / "fe2" / "steps.csv");
    csv << "ce_deg,alpha_deg,step,angle_deg,pressure_max_mpa\n";
    for (int s = 1; s <= 5; ++s) csv << "21,50," << s << ',' << 7.0 * s << ",1.5\n";
  }
  geometry::write_hip_model(sphere_hip(21), dir / "hips" / "hip-21");
  EstimatorTrainOptions more;
  more.base_model = dir / "model.h5";
  more.fe = {dir / "fe2"};
  more.hips = dir / "hips";
  more.progress = false;
  expect_error([&] { train_estimator_model(more); }, "motion differs");
  more.fe.clear();
  more.grid.polar_steps = 9;
  more.grid_given = true;
  expect_error([&] { train_estimator_model(more); }, "feature grid");
  // Same motion: a new hip gives a new model with one more hip.
  {
    std::ofstream csv(dir / "fe2" / "steps.csv");
    csv << "ce_deg,alpha_deg,step,angle_deg,pressure_max_mpa\n";
    for (int s = 1; s <= 3; ++s) csv << "21,50," << s << ',' << 10.0 * s << ',' << (1 + 0.1 * s) * 6 << '\n';
  }
  more.fe = {dir / "fe2"};
  more.grid = FeatureGrid{};
  more.grid_given = false;
  EXPECT_EQ(train_estimator_model(more).hips.size(), 5u);
}

// The real CT hip (bones only, hip.json): a model of all four tissues refuses it, naming what is
// missing; a model of the femur alone predicts it in the bones' approximate frame and flags it
// bordering (a CT femur, shaft and all, is nothing like the training spheres).
TEST(EstimatorStudy, RealBonesOnlyHip) {
  EstimatorTrainOptions train = four_sphere_training("real", 2);
  const fs::path ct = fs::path(HIPFAI_SOURCE_DIR) / "meshes/real-hips/LHDL_CT";
  const EstimatorModel all_tissues = train_estimator_model(train);
  expect_error([&] { predict_hip(all_tissues, ct, stats::EstimatorMethod::kPcaNn, 2); },
               "no femoral_cartilage, acetabular_cartilage, labrum (it has femur_bone, pelvis_bone)");
  train.grid.tissues = {"femur_bone"};
  train.grid_given = true;
  const EstimatorModel femur_only = train_estimator_model(train);
  const HipPrediction prediction = predict_hip(femur_only, ct, stats::EstimatorMethod::kPcaNn, 1);
  EXPECT_TRUE(prediction.approximate_frame);
  EXPECT_TRUE(prediction.result.bordering);
  EXPECT_EQ(prediction.result.steps.size(), 2u);
}

// depth_nn end to end: an FE table of standing-to-sitting (4 sub-motions) with penetration depths
// (hips of radius 25 and 26 mm impinge from step 3, their pressure doubled there), a model that
// keeps the depths through its file, and a prediction that computes the target's own depths.
TEST(EstimatorStudy, DepthNnComputesTheTargetsPenetrationAndKeepsTheDepthsInTheModelFile) {
  // The sphere study with depths, at the given step angles, written into `dir`.
  const auto write_study = [](const fs::path& dir, const std::vector<double>& angles) {
    fs::create_directories(dir / "fe");
    std::ofstream csv(dir / "fe" / "steps.csv");
    csv << std::setprecision(17) << "ce_deg,alpha_deg,step,angle_deg,max_curvilinear_mm,max_radial_mm,pressure_max_mpa\n";
    for (const double r : {20.0, 21.0, 22.0, 23.0, 24.0, 25.0, 26.0}) {
      geometry::write_hip_model(sphere_hip(r), dir / "hips" / ("hip-" + std::to_string(static_cast<int>(r))));
      for (int s = 1; s <= static_cast<int>(angles.size()); ++s) {
        const bool impinging = r >= 25 && s >= 3;
        csv << r << ",50," << s << ',' << angles[static_cast<std::size_t>(s - 1)] << ',' << (impinging ? 0.5 * s : 0.0)
            << ',' << (impinging ? 0.2 : 0.0) << ',' << (1 + 0.1 * s) * (r - 15) * (impinging ? 2.0 : 1.0) << '\n';
      }
    }
  };
  const fs::path dir = estimator_scratch("depth-nn");
  std::vector<double> angles;
  for (const MotionStep& step : standing_to_sitting(4).steps) angles.push_back(step.angle_deg);
  write_study(dir, angles);
  EstimatorTrainOptions train;
  train.fe = {dir / "fe"};
  train.hips = dir / "hips";
  train.progress = false;
  const EstimatorModel model = train_estimator_model(train);
  ASSERT_TRUE(model.estimator.depths.known());
  EXPECT_EQ(model.estimator.depths.curvilinear_mm(5, 3), 2.0);  // radius 25, step 4
  write_estimator_model(model, dir / "model.h5");
  const EstimatorModel reloaded = read_estimator_model(dir / "model.h5");
  ASSERT_TRUE(reloaded.estimator.depths.known());
  EXPECT_EQ(reloaded.estimator.depths.curvilinear_mm, model.estimator.depths.curvilinear_mm);
  EXPECT_EQ(reloaded.estimator.depths.radial_mm, model.estimator.depths.radial_mm);

  // A target whose labrum is a small ball beside the joint (concentric closed spheres would put the
  // femur inside the labrum from the start, which compute_penetration refuses): nothing penetrates
  // over the motion, the depths computed for it are 0 at every step, and depth_nn gives the
  // nearest hips' level times the contact-free profile (1 + 0.1 s) / 1.1.
  geometry::HipModel target = sphere_hip(22.5);
  target.tissues["labrum"] = geometry::make_octasphere(geometry::Vec3(32.5, 0, 0), 3.0, 3);
  target.tissues["acetabular_cartilage"] = geometry::make_octasphere(geometry::Vec3(-32.5, 0, 0), 3.0, 3);
  geometry::write_hip_model(target, dir / "target");
  const HipPrediction a = predict_hip(model, dir / "target", stats::EstimatorMethod::kDepthNn, 3);
  const HipPrediction b = predict_hip(reloaded, dir / "target", stats::EstimatorMethod::kDepthNn, 3);
  ASSERT_TRUE(a.depths.known());
  EXPECT_EQ(a.depths.curvilinear_mm.cols(), 4);
  EXPECT_EQ(a.depths.curvilinear_mm.maxCoeff(), 0.0);
  EXPECT_EQ(a.depths.radial_mm.maxCoeff(), 0.0);
  ASSERT_EQ(a.result.steps.size(), 4u);
  for (std::size_t j = 0; j < 4; ++j) {
    EXPECT_NEAR(a.result.steps[j].estimate / a.result.steps[0].estimate, (1.1 + 0.1 * static_cast<double>(j)) / 1.1, 1e-12);
    EXPECT_EQ(a.result.steps[j].estimate, b.result.steps[j].estimate);
    EXPECT_EQ(a.result.steps[j].low, b.result.steps[j].low);
    EXPECT_EQ(a.result.steps[j].high, b.result.steps[j].high);
  }

  // The leave-one-out has depth_nn rows, and on the impinging hips it beats the plain kNN, which
  // copies non-impinging neighbours' curves (radius 25's 4 nearest: 23, 24, 26, 22).
  EstimatorValidateOptions options = sphere_validate_options(dir, 2);
  const auto summary = validate_estimator(options);
  EXPECT_TRUE(std::isfinite(summary.mean_error[1][3]));
  EXPECT_LT(summary.mean_error[1][3], summary.mean_error[1][1]);

  // A model without depths refuses depth_nn (its file says so too).
  const EstimatorTrainOptions plain = four_sphere_training("depth-nn-plain", 3);
  const EstimatorModel plain_model = train_estimator_model(plain);
  EXPECT_FALSE(plain_model.estimator.depths.known());
  expect_error([&] { predict_hip(plain_model, dir / "target", stats::EstimatorMethod::kDepthNn, 1); },
               "depth_nn needs the training hips' penetration depths");
  write_estimator_model(plain_model, dir / "plain.h5");
  EXPECT_FALSE(read_estimator_model(dir / "plain.h5").estimator.depths.known());
  // Another motion: predict does not know its axis and refuses depth_nn.
  const fs::path other = estimator_scratch("depth-nn-other");
  write_study(other, {10, 20, 30, 40});
  train.fe = {other / "fe"};
  train.hips = other / "hips";
  const EstimatorModel other_model = train_estimator_model(train);
  EXPECT_TRUE(other_model.estimator.depths.known());
  expect_error([&] { predict_hip(other_model, dir / "target", stats::EstimatorMethod::kDepthNn, 1); },
               "is not standing-to-sitting");
}

}  // namespace
}  // namespace hipfai::studies

#ifdef HIPFAI_WITH_FEM
namespace hipfai::studies {
namespace {

// A scripts/fem-sweep folder as the script leaves it: summary.csv, per model the `fem run --csv`
// table and the HDF5 with each step's rotation (here about Z by `angles_deg`, and once about an
// oblique axis: the angle of a rotation does not depend on its axis).
void write_sweep_model(const fs::path& dir, const std::string& model, const std::vector<double>& angles_deg,
                       double pressure_scale, const Eigen::Vector3d& axis) {
  std::ofstream csv(dir / (model + ".csv"));
  // The columns the table's reader needs (studies/results/hip_fe_table.h), no tissue's von Mises.
  csv << "step,status,dofs,max_pressure_mpa,ball_peak_pressure_mpa,mean_pressure_mpa,wall_time_s\n";
  std::vector<double> rotation;
  for (std::size_t k = 0; k < angles_deg.size(); ++k) {
    csv << k + 1 << ",0,1200," << pressure_scale * (k + 1) << ',' << 0.5 * pressure_scale * (k + 1) << ",0.1,0.5\n";
    const Eigen::Matrix3d r = Eigen::AngleAxisd(angles_deg[k] * M_PI / 180.0, axis.normalized()).toRotationMatrix();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) rotation.push_back(r(i, j));
    }
  }
  // n x 3 x 3, as fem/fem_results.cpp writes it.
  const hid_t file = H5Fcreate((dir / (model + ".h5")).c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t group = H5Gcreate2(file, "steps", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const hsize_t dims[3] = {angles_deg.size(), 3, 3};
  const hid_t space = H5Screate_simple(3, dims, nullptr);
  const hid_t set = H5Dcreate2(group, "rotation", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rotation.data()), 0);
  H5Dclose(set);
  H5Sclose(space);
  H5Gclose(group);
  H5Fclose(file);
}

TEST(EstimatorStudy, ReadsAFemSweepFolder) {
  const fs::path dir = estimator_scratch("fem-sweep");
  {
    std::ofstream summary(dir / "summary.csv");
    summary << "model,exit_status,steps,converged\nce10_alpha50,0,3,3\nce20_alpha60,0,3,3\nce30_alpha70,1,0,0\n";
  }
  write_sweep_model(dir, "ce10_alpha50", {10, 20, 30}, 1.0, Eigen::Vector3d::UnitZ());
  write_sweep_model(dir, "ce20_alpha60", {10, 20, 30}, 2.0, Eigen::Vector3d(1, 2, 3));
  // ce30_alpha70 stopped before its table: skipped.
  // read_dataset of an n x 3 x 3 set: rows n, cols 9 (it used to write past a 2-extent array).
  std::size_t rows = 0, cols = 0;
  EXPECT_EQ(read_dataset(dir / "ce10_alpha50.h5", "/steps/rotation", &rows, &cols).size(), 27u);
  EXPECT_EQ(rows, 3u);
  EXPECT_EQ(cols, 9u);
  const FeSweep sweep = read_fe_sweep(dir, "pressure_max_mpa");
  ASSERT_EQ(sweep.hips.size(), 2u);
  ASSERT_EQ(sweep.angle_deg.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(sweep.angle_deg[static_cast<std::size_t>(k)], 10.0 * (k + 1), 1e-9);
  EXPECT_EQ(sweep.hips[1].ce_deg, 20.0);
  EXPECT_EQ(sweep.hips[1].alpha_deg, 60.0);
  EXPECT_TRUE(std::isnan(sweep.hips[1].edge_mm));
  EXPECT_DOUBLE_EQ(sweep.hips[1].values[2], 6.0);
  EXPECT_DOUBLE_EQ(read_fe_sweep(dir, "pressure_ball_mpa").hips[0].values[1], 1.0);
  EXPECT_THROW(read_fe_sweep(dir, "pressure_p99_mpa"), Error);

  // Another motion in one model, and a name CE/alpha cannot be read from, are errors.
  write_sweep_model(dir, "ce20_alpha60", {10, 20, 35}, 2.0, Eigen::Vector3d::UnitZ());
  EXPECT_THROW(read_fe_sweep(dir, "pressure_max_mpa"), Error);
  write_sweep_model(dir, "ce20_alpha60", {10, 20, 30}, 2.0, Eigen::Vector3d::UnitZ());
  {
    std::ofstream summary(dir / "summary.csv", std::ios::app);
    summary << "left_hip,0,3,3\n";
  }
  write_sweep_model(dir, "left_hip", {10, 20, 30}, 1.0, Eigen::Vector3d::UnitZ());
  EXPECT_THROW(read_fe_sweep(dir, "pressure_max_mpa"), Error);
}


}  // namespace
}  // namespace hipfai::studies
#endif
