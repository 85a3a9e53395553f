// Cutback sub-stepping, VTU output every N steps and the no-NaN guarantee of fem::run_motion, on
// a small model: a cartilage layer (4 x 4 x 2 mm, bonded to bone below, frictionless side walls)
// pressed by a rigid plate that is load controlled along z and tilted about the y axis through
// the centre of the layer's top. Tilting moves the contact to one side of the layer, so the
// active set changes with the rotation. Small (Q2, 32 cells) to solve in a fraction of a second.
#include "core/error.h"
#include "fem/motion_solver.h"

#include <deal.II/grid/grid_generator.h>

#include <deal.II/base/multithread_info.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace hipfai::fem {
namespace {

using dealii::Point;
using dealii::Tensor;

constexpr double kWidth = 4.0, kThickness = 2.0;  // mm, the acetabular cartilage's 2 mm
constexpr dealii::types::boundary_id kBottom = 0, kTop = 1, kWallX = 2, kWallY = 3;
// 5 N on 16 mm^2: 0.3 MPa, ~1.5 % strain when flat: small strain, the plate tilts by up to 2 %.
constexpr double kLoad = 5.0;

void build_layer(ContactProblem& problem, unsigned int cells_across) {
  auto& tria = problem.triangulation();
  dealii::GridGenerator::subdivided_hyper_rectangle(tria, {cells_across, cells_across, 2}, Point<3>(0, 0, 0),
                                                    Point<3>(kWidth, kWidth, kThickness));
  for (const auto& face : tria.active_face_iterators()) {
    if (!face->at_boundary()) continue;
    const Point<3> c = face->center();
    if (c[2] < 1e-9) face->set_boundary_id(kBottom);
    else if (c[2] > kThickness - 1e-9) face->set_boundary_id(kTop);
    else if (c[0] < 1e-9 || c[0] > kWidth - 1e-9) face->set_boundary_id(kWallX);
    else face->set_boundary_id(kWallY);
  }
  problem.model().bodies = {{"cartilage", 0, {12.0, 0.45}, -1}};  // E 12 MPa, nu 0.45 (core/literature.h)
  RigidBody bone{"bone", nullptr, {}, false, {}, {}, dealii::unit_symmetric_tensor<3>(), {}};
  RigidBody plate{"plate", std::make_shared<RigidPlane>(Point<3>(0, 0, kThickness), Tensor<1, 3>({0, 0, -1})),
                  {}, false, {}, {}, dealii::unit_symmetric_tensor<3>(), Point<3>(kWidth / 2, kWidth / 2, kThickness)};
  problem.model().rigid_bodies = {bone, plate};
  problem.model().bonded_boundaries = {{kBottom, 0, {}}};
  problem.model().symmetry_boundaries = {{kWallX, 0}, {kWallY, 1}};
  problem.model().contact_pairs = {{kTop, 1, 0}};
}

// The plate tilted by `tilt_rad` about y, pushing down with kLoad.
MotionStep tilted(double tilt_rad) {
  return {rotation_about_axis(Tensor<1, 3>({0, 1, 0}), tilt_rad), Tensor<1, 3>({0, 0, -kLoad})};
}

MotionOptions plate_motion() {
  MotionOptions options;
  options.moving_body = 1;
  options.free_directions = {Tensor<1, 3>({0, 0, 1})};
  return options;
}

TEST(FemMotionCutback, InterpolatedRotationIsTheShortestArc) {
  // from * R(axis, s phi) is the closed form of the slerp from `from` to from * R(axis, phi).
  const Tensor<2, 3> from = rotation_about_axis(Tensor<1, 3>({0.3, -1, 2}), 1.1);
  const Tensor<1, 3> axis = Tensor<1, 3>({1, 1, -0.5}) / Tensor<1, 3>({1, 1, -0.5}).norm();
  for (const double phi : {1e-3, 0.8, 3.0}) {
    const Tensor<2, 3> to = from * rotation_about_axis(axis, phi);
    for (const double s : {0.0, 0.25, 0.5, 1.0}) {
      const Tensor<2, 3> expected = from * rotation_about_axis(axis, s * phi);
      // Round-off of the quaternion extraction: ~1e-15 per entry; bound 1e-12.
      EXPECT_LT((interpolate_rotation(from, to, s) - expected).norm(), 1e-12) << phi << " " << s;
    }
  }
  // Beyond pi the shortest arc turns the other way: phi = 4 rad is 2 pi - 4 the other way round.
  const Tensor<2, 3> far = from * rotation_about_axis(axis, 4.0);
  EXPECT_LT((interpolate_rotation(from, far, 0.5) - from * rotation_about_axis(axis, 0.5 * (4.0 - 2 * M_PI))).norm(),
            1e-12);
}

TEST(FemMotionCutback, FailedStepIsHalvedAndEndsAtTheDirectSolution) {
  ContactProblem problem(MPI_COMM_WORLD, ContactOptions{});
  build_layer(problem, 4);
  // Step 0 settles the flat plate (default limits). Step 1 tilts it by 0.02 rad at once, which
  // lifts it off part of the layer: from step 0's active set that takes more active-set
  // iterations than the limit of 2 set after step 0, while the smaller tilts of the sub-steps,
  // each started from its predecessor's set, need fewer. So step 1 must be cut back and still
  // converge.
  const std::vector<MotionStep> steps = {tilted(0.0), tilted(0.02)};
  const std::vector<ContactResult> results =
      run_motion(problem, steps, plate_motion(), [&](std::size_t k, const ContactResult&) {
        if (k == 0) problem.options().max_active_set_iterations = 2;
      });
  ASSERT_EQ(results.size(), 2u);
  ASSERT_EQ(results[0].status, ContactStatus::kConverged);
  EXPECT_EQ(results[0].statistics.sub_steps, 1u);
  EXPECT_EQ(results[0].statistics.cutbacks, 0u);
  ASSERT_EQ(results[1].status, ContactStatus::kConverged) << to_string(results[1].status);
  EXPECT_GE(results[1].statistics.cutbacks, 1u);
  EXPECT_GE(results[1].statistics.sub_steps, 2u);
  std::cout << "cutback: step 1 in " << results[1].statistics.sub_steps << " sub-steps, " << results[1].statistics.cutbacks
            << " cutbacks, " << results[1].statistics.active_set_iterations << " active-set iterations\n";

  // The same step solved directly, cold, with the default limits.
  ContactProblem direct(MPI_COMM_WORLD, ContactOptions{});
  build_layer(direct, 4);
  RigidBody& plate = direct.model().rigid_bodies[1];
  plate.load_controlled = true;
  plate.free_directions = {Tensor<1, 3>({0, 0, 1})};
  plate.rotation = steps[1].rotation;
  plate.force_n = steps[1].force_n;
  const ContactResult reference = direct.run();
  ASSERT_EQ(reference.status, ContactStatus::kConverged);
  // Same active set, same linear system: the answers differ by the CG tolerance (1e-12 relative
  // residual) amplified by the conditioning; 1e-6 relative leaves room for that and nothing else.
  const double t = results[1].rigid_translation_mm[1][2], t_ref = reference.rigid_translation_mm[1][2];
  EXPECT_NEAR(t, t_ref, 1e-6 * std::abs(t_ref));
  EXPECT_NEAR(results[1].peaks.max_pressure_mpa, reference.peaks.max_pressure_mpa, 1e-6 * reference.peaks.max_pressure_mpa);
  EXPECT_NEAR(results[1].peaks.contact_area_mm2, reference.peaks.contact_area_mm2, 1e-6 * reference.peaks.contact_area_mm2);
  ASSERT_EQ(results[1].nodes.size(), reference.nodes.size());
  std::size_t active = 0;
  for (std::size_t n = 0; n < reference.nodes.size(); ++n) {
    EXPECT_EQ(results[1].nodes[n].active, reference.nodes[n].active) << "node " << n;
    active += reference.nodes[n].active;
  }
  // The tilt really lifted the plate off part of the layer (else nothing needed cutting back).
  EXPECT_LT(active, reference.nodes.size());
  EXPECT_GT(active, 0u);
  // Force balance along the free direction (1e-6: an exactly affine balance, CG tolerance).
  EXPECT_NEAR(results[1].pair_force_n[0][2], -kLoad, 1e-6 * kLoad);
}

TEST(FemMotionCutback, WritesVtuEveryNStepsAndAParaViewCollection) {
  ContactProblem problem(MPI_COMM_WORLD, ContactOptions{});
  build_layer(problem, 2);
  const std::vector<MotionStep> steps = {tilted(0.0), tilted(0.005), tilted(0.01)};
  const std::filesystem::path directory = std::filesystem::path(HIPFAI_BINARY_DIR) / "fem_vtu_every_test";
  // One rank clears the directory, the others wait, so no rank deletes another's files.
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    std::filesystem::remove_all(directory);
    std::filesystem::create_directories(directory);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  MotionOptions options = plate_motion();
  options.vtu_every = 2;
  options.vtu_prefix = (directory / "layer").string();
  const std::vector<ContactResult> results = run_motion(problem, steps, options);
  for (const ContactResult& result : results) ASSERT_EQ(result.status, ContactStatus::kConverged);
  // Every 2nd step and the last one: steps 2 and 3 (counted from 1), not step 1.
  EXPECT_FALSE(std::filesystem::exists(directory / "layer_1.vtu"));
  ASSERT_TRUE(std::filesystem::exists(directory / "layer_2.vtu"));
  ASSERT_TRUE(std::filesystem::exists(directory / "layer_3.vtu"));
  std::stringstream vtu;
  vtu << std::ifstream(directory / "layer_3.vtu").rdbuf();
  for (const char* field : {"displacement_mm", "material_id", "von_mises_cell_max_mpa", "contact_pressure_mpa",
                            "contact_gap_mm", "contact_active"}) {
    EXPECT_NE(vtu.str().find(std::string("Name=\"") + field + "\""), std::string::npos) << field;
  }
  std::stringstream pvd;
  pvd << std::ifstream(directory / "layer.pvd").rdbuf();
  EXPECT_NE(pvd.str().find("timestep=\"2\" group=\"\" part=\"0\" file=\"layer_2.vtu\""), std::string::npos)
      << pvd.str();
  EXPECT_NE(pvd.str().find("timestep=\"3\" group=\"\" part=\"0\" file=\"layer_3.vtu\""), std::string::npos)
      << pvd.str();
  EXPECT_EQ(pvd.str().find("layer_1.vtu"), std::string::npos);
  MotionOptions no_prefix = plate_motion();
  no_prefix.vtu_every = 1;
  EXPECT_THROW(run_motion(problem, steps, no_prefix), hipfai::Error);
}

TEST(FemMotionCutback, AnUnbalancedLoadFailsWithoutNaN) {
  // A frictionless flat plate cannot hold a sideways load: with the plate free in x, y and z
  // the balance is singular. The step must fail (after its cutbacks) and report finite numbers.
  ContactProblem problem(MPI_COMM_WORLD, ContactOptions{});
  build_layer(problem, 2);
  MotionOptions options;  // free in x, y and z
  options.moving_body = 1;
  options.max_cutback_depth = 1;
  const std::vector<MotionStep> steps = {{dealii::unit_symmetric_tensor<3>(), Tensor<1, 3>({5.0, 0.0, -10.0})}};
  const std::vector<ContactResult> results = run_motion(problem, steps, options);
  ASSERT_EQ(results.size(), 1u);
  EXPECT_NE(results[0].status, ContactStatus::kConverged) << to_string(results[0].status);
  EXPECT_EQ(results[0].statistics.cutbacks, 1u);  // depth 1: one halving, then given up
  const auto finite = [](const Tensor<1, 3>& v) { return std::isfinite(v.norm()); };
  for (const auto& t : results[0].rigid_translation_mm) EXPECT_TRUE(finite(t));
  for (const auto& f : results[0].pair_force_n) EXPECT_TRUE(finite(f));
  for (const ContactNode& node : results[0].nodes) {
    EXPECT_TRUE(std::isfinite(node.pressure_mpa) && std::isfinite(node.gap_mm) && std::isfinite(node.force_n));
  }
  for (const double value : {results[0].peaks.max_pressure_mpa, results[0].peaks.mean_pressure_mpa, results[0].peaks.contact_area_mm2,
                             results[0].peaks.max_penetration_mm}) {
    EXPECT_TRUE(std::isfinite(value));
  }
  for (const double value : results[0].peaks.max_von_mises_mpa) EXPECT_TRUE(std::isfinite(value));
}

// Each step's contact is searched while the step before is solved; a cutback's sub-steps are
// poses the search ahead did not expect, which it must notice. The answers are those of the
// motion searched step by step, bit for bit.
TEST(FemMotionCutback, SearchAheadChangesNoAnswerAcrossACutback) {
  const std::vector<MotionStep> steps = {tilted(0.0), tilted(0.02), tilted(0.025)};
  std::vector<std::vector<ContactResult>> runs;
  for (const bool ahead : {false, true}) {
    ContactProblem problem(MPI_COMM_WORLD, ContactOptions{});
    build_layer(problem, 4);
    MotionOptions options = plate_motion();
    options.search_ahead = ahead;
    runs.push_back(run_motion(problem, steps, options, [&](std::size_t k, const ContactResult&) {
      if (k == 0) problem.options().max_active_set_iterations = 2;  // step 1 is cut back
    }));
  }
  // The searches ahead need a second thread (a one-core machine searches every step itself).
  const bool two_threads = dealii::MultithreadInfo::n_threads() >= 2;
  const std::vector<ContactResult>& stepwise = runs[0];
  const std::vector<ContactResult>& ahead = runs[1];
  ASSERT_EQ(ahead.size(), steps.size());
  EXPECT_GE(ahead[1].statistics.cutbacks, 1u);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    EXPECT_FALSE(stepwise[k].statistics.searched_ahead);
    // Step 0 has nothing before it; the last attempt of step 1 (at its pose, after a converged
    // half step that expected it) and step 2 use the search run beside the run before.
    EXPECT_EQ(ahead[k].statistics.searched_ahead, k > 0 && two_threads) << "step " << k;
    ASSERT_EQ(ahead[k].status, stepwise[k].status) << "step " << k;
    EXPECT_EQ(ahead[k].statistics.sub_steps, stepwise[k].statistics.sub_steps);
    EXPECT_EQ(ahead[k].statistics.active_set_iterations, stepwise[k].statistics.active_set_iterations);
    EXPECT_EQ(ahead[k].rigid_translation_mm[1], stepwise[k].rigid_translation_mm[1]) << "step " << k;
    ASSERT_EQ(ahead[k].nodes.size(), stepwise[k].nodes.size());
    for (std::size_t n = 0; n < ahead[k].nodes.size(); ++n) {
      EXPECT_EQ(ahead[k].nodes[n].pressure_mpa, stepwise[k].nodes[n].pressure_mpa) << k << " " << n;
      EXPECT_EQ(ahead[k].nodes[n].gap_mm, stepwise[k].nodes[n].gap_mm) << k << " " << n;
    }
  }
}

}  // namespace
}  // namespace hipfai::fem
