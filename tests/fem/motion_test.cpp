// Rigid-body kinematics of the FE contact model on concentric spherical shells with the hip's
// dimensions (full spheres, no symmetry planes): a prescribed rotation of the core about the
// centre must not change the contact pressure (a spherical joint), and a load on the freely
// translating core must be balanced by the contact resultant at every step.
#include "fem/fem_results.h"
#include "fem/motion_solver.h"
#include "fem/verification_cases.h"


#include <deal.II/base/multithread_info.h>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

namespace hipfai::fem {
namespace {

using dealii::Point;
using dealii::Tensor;

constexpr double kCoreRadius = 23.0, kContactRadius = 25.0, kCupRadius = 27.0;  // mm
constexpr double kExpansion = 0.02;  // mm, radial, keeps the whole interface closed

ElasticMaterial cartilage() { return {12.0, 0.45}; }  // E = 12 MPa, nu = 0.45 (core/literature.h)

// Lame: contact pressure between the shells, core expanded by d, cup fixed; both shells of the
// same material. u = A r + B / r^2, sigma_rr = 3K A - 4 mu B / r^3; unknowns A1 B1 A2 B2 p.
double lame_pressure() {
  const ElasticMaterial m = cartilage();
  const double k3 = m.youngs_modulus_mpa / (1 - 2 * m.poisson_ratio);
  const double g4 = 2 * m.youngs_modulus_mpa / (1 + m.poisson_ratio);
  const double a = kCoreRadius, b = kContactRadius, c = kCupRadius;
  // Inner shell: u(a) = d, sigma(b) = -p  ->  A1, B1 linear in (d, p); same for the outer shell
  // with u(c) = 0; then u1(b) = u2(b) fixes p. Solve the 2x2 systems by Cramer's rule.
  const auto shell = [&](double r0, double u0, double p, double& A, double& B) {
    const double m11 = r0, m12 = 1 / (r0 * r0), m21 = k3, m22 = -g4 / (b * b * b);
    const double det = m11 * m22 - m12 * m21;
    A = (u0 * m22 - m12 * -p) / det;
    B = (m11 * -p - m21 * u0) / det;
  };
  const auto mismatch = [&](double p) {
    double A1, B1, A2, B2;
    shell(a, kExpansion, p, A1, B1);
    shell(c, 0.0, p, A2, B2);
    return (A1 * b + B1 / (b * b)) - (A2 * b + B2 / (b * b));
  };
  // The mismatch is affine in p.
  const double m0 = mismatch(0.0), m1 = mismatch(1.0);
  return -m0 / (m1 - m0);
}

// The verification case's two bonded cartilage shells with a non-matching contact interface
// (fem/verification_cases.h), the inner shell's core pushed out by kExpansion.
void build_shells(ContactProblem& problem) { build_concentric_shells(problem, kExpansion); }

ContactOptions shell_options() {
  ContactOptions options;
  options.mapping_degree = 4;  // r = 25 mm faceting would otherwise rival the 0.02 mm load
  return options;
}

struct PressureSummary {
  double min = 1e300, max = 0, mean = 0;
};
PressureSummary summarize(const ContactResult& result) {
  PressureSummary s;
  for (const ContactNode& node : result.nodes) {
    s.min = std::min(s.min, node.pressure_mpa);
    s.max = std::max(s.max, node.pressure_mpa);
    s.mean += node.pressure_mpa / result.nodes.size();
  }
  return s;
}

TEST(FemMotion, RotationOfASphericalJointLeavesThePressureUnchanged) {
  ContactProblem problem(MPI_COMM_WORLD, shell_options());
  build_shells(problem);
  const double expected = lame_pressure();
  const ContactResult neutral = problem.run();
  ASSERT_EQ(neutral.status, ContactStatus::kConverged);
  const PressureSummary before = summarize(neutral);
  // Mesh of 2 mm shells with 2-4 Q2 cells through the thickness on a full sphere: the mean is
  // measured within 0.5 % of Lame, nodes within 1.5 %; bounds 1 % and 3 %.
  EXPECT_NEAR(before.mean, expected, 0.01 * expected);
  EXPECT_NEAR(before.max, expected, 0.03 * expected);
  EXPECT_NEAR(before.min, expected, 0.03 * expected);
  // A uniform pressure: a ball's area-weighted mean lies between the nodes' min and max, so the
  // ball-averaged peak has the same bound (1 mm balls, the default, hold several nodes here).
  EXPECT_NEAR(neutral.peaks.ball_peak_pressure_mpa, expected, 0.03 * expected);
  EXPECT_LE(neutral.peaks.ball_peak_pressure_mpa, neutral.peaks.max_pressure_mpa);
  EXPECT_EQ(neutral.peaks.peak_average_radius_mm, 1.0);

  // 90 degrees about z maps both cube-sphere meshes onto themselves: the rotated discrete
  // problem is the neutral one with its nodes permuted, up to the segment quadrature of the
  // curved faces, whose (non-polynomial) integrands are sampled at points that depend on each
  // face's parametrization, which the rotation permutes: measured 1.3e-6 relative, bound 1e-5.
  problem.model().rigid_bodies[0].rotation = rotation_about_axis(Tensor<1, 3>({0, 0, 1}), M_PI / 2);
  const ContactResult quarter_turn = problem.run();
  ASSERT_EQ(quarter_turn.status, ContactStatus::kConverged);
  const PressureSummary turned = summarize(quarter_turn);
  EXPECT_NEAR(turned.mean, before.mean, 1e-5 * expected);
  EXPECT_NEAR(turned.max, before.max, 1e-5 * expected);
  EXPECT_NEAR(turned.min, before.min, 1e-5 * expected);

  // An oblique rotation makes the interface mesh pair different, not the physics: Lame within
  // the same discretization bounds (the small-strain model would give a rotation of the bonded
  // boundary applied as a displacement a spurious strain of order the angle; rotating the
  // configuration avoids it).
  problem.model().rigid_bodies[0].rotation = rotation_about_axis(Tensor<1, 3>({1, 2, 3}), 0.7);
  const ContactResult oblique = problem.run();
  ASSERT_EQ(oblique.status, ContactStatus::kConverged);
  const PressureSummary rotated = summarize(oblique);
  std::cout << "shells: Lame " << expected << " MPa; neutral mean " << before.mean << " ["
            << before.min << ", " << before.max << "]; 90 deg mean " << turned.mean
            << "; oblique mean " << rotated.mean << " [" << rotated.min << ", " << rotated.max
            << "]\n";
  EXPECT_NEAR(rotated.mean, expected, 0.01 * expected);
  EXPECT_NEAR(rotated.max, expected, 0.03 * expected);
  EXPECT_NEAR(rotated.min, expected, 0.03 * expected);
}

TEST(FemMotion, LoadedCoreRelocatesAndTheContactResultantBalancesTheLoad) {
  ContactProblem problem(MPI_COMM_WORLD, shell_options());
  build_shells(problem);
  const Tensor<1, 3> axis({1, 2, 3});
  std::vector<MotionStep> steps;
  for (int k = 0; k < 3; ++k) {
    // Up to 80 N, well below what would open the 0.23 MPa interface (~ p pi R^2 = 450 N).
    steps.push_back({rotation_about_axis(axis, 0.3 * k), Tensor<1, 3>({40.0, -30.0, 60.0 - 20.0 * k})});
  }
  MotionOptions options;
  options.moving_body = 0;
  const std::string file = (std::filesystem::path(HIPFAI_BINARY_DIR) / "fem_motion_test.h5").string();
  FemResultsWriter writer(file, {"femoral cartilage", "acetabular cartilage"}, 0);
  const std::vector<ContactResult> results = run_motion(
      problem, steps, options,
      [&](std::size_t k, const ContactResult& result) { writer.append(steps[k], result); });
  ASSERT_EQ(results.size(), steps.size());
  for (std::size_t k = 0; k < steps.size(); ++k) {
    ASSERT_EQ(results[k].status, ContactStatus::kConverged) << "step " << k;
    const Tensor<1, 3> force = steps[k].force_n;
    // The contact force on the inner shell balances the load the core puts on it; the
    // translation solves an exactly affine balance, so this holds to the CG tolerance: 1e-6.
    const Tensor<1, 3> residual = results[k].pair_force_n[0] + force;
    EXPECT_LT(residual.norm(), 1e-6 * force.norm()) << "step " << k;
    // The head relocates along the load (the shells' stiffness is isotropic up to the mesh).
    const Tensor<1, 3> t = results[k].rigid_translation_mm[0];
    EXPECT_GT(t * force, 0.95 * t.norm() * force.norm()) << "step " << k;
    std::cout << "step " << k << ": translation " << t << " mm, resultant residual "
              << residual.norm() / force.norm() << ", " << results[k].statistics.active_set_iterations
              << " active-set iterations, " << results[k].statistics.wall_time_s << " s\n";
  }

  // The HDF5 file holds every step, read back independently with the C API.
  const hid_t h5 = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(h5, 0);
  const auto read = [&](const char* name, std::vector<double>& values, std::string& unit) {
    const hid_t dataset = H5Dopen2(h5, name, H5P_DEFAULT);
    const hid_t space = H5Dget_space(dataset);
    values.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    const hid_t attribute = H5Aopen(dataset, "unit", H5P_DEFAULT);
    const hid_t type = H5Aget_type(attribute);
    unit.assign(H5Tget_size(type), '\0');
    H5Aread(attribute, type, unit.data());
    unit = unit.c_str();
    H5Tclose(type);
    H5Aclose(attribute);
    H5Sclose(space);
    H5Dclose(dataset);
  };
  std::vector<double> resultant, translation, status, von_mises, sub_steps, cutbacks, ball_von_mises,
      ball_pressure, ball_pressure_position;
  std::string unit;
  read("/steps/sub_steps", sub_steps, unit);
  EXPECT_EQ(unit, "1");
  read("/steps/cutbacks", cutbacks, unit);
  read("/steps/contact_resultant_n", resultant, unit);
  EXPECT_EQ(unit, "N");
  read("/steps/femur_translation_mm", translation, unit);
  EXPECT_EQ(unit, "mm");
  read("/steps/status", status, unit);
  read("/steps/max_von_mises_mpa", von_mises, unit);
  EXPECT_EQ(unit, "MPa");
  read("/steps/ball_peak_von_mises_mpa", ball_von_mises, unit);
  EXPECT_EQ(unit, "MPa");
  read("/steps/ball_peak_pressure_mpa", ball_pressure, unit);
  EXPECT_EQ(unit, "MPa");
  read("/steps/ball_peak_pressure_position_mm", ball_pressure_position, unit);
  EXPECT_EQ(unit, "mm");
  H5Fclose(h5);
  ASSERT_EQ(resultant.size(), 3 * steps.size());
  ASSERT_EQ(von_mises.size(), 2 * steps.size());
  for (std::size_t k = 0; k < steps.size(); ++k) {
    EXPECT_EQ(status[k], 0.0);
    EXPECT_EQ(sub_steps[k], static_cast<double>(results[k].statistics.sub_steps));
    EXPECT_EQ(cutbacks[k], static_cast<double>(results[k].statistics.cutbacks));
    for (unsigned d = 0; d < 3; ++d) {
      // Stored as computed: exact copies of the in-memory doubles.
      EXPECT_EQ(resultant[3 * k + d], results[k].pair_force_n[0][d]);
      EXPECT_EQ(translation[3 * k + d], results[k].rigid_translation_mm[0][d]);
    }
    EXPECT_GT(von_mises[2 * k], 0.0);
    for (unsigned b = 0; b < 2; ++b) {
      EXPECT_EQ(ball_von_mises[2 * k + b], results[k].peaks.ball_peak_von_mises_mpa[b]);
      // A weighted mean of the Gauss-point values cannot exceed their maximum.
      EXPECT_GT(ball_von_mises[2 * k + b], 0.0);
      EXPECT_LE(ball_von_mises[2 * k + b], von_mises[2 * k + b]);
    }
    EXPECT_EQ(ball_pressure[k], results[k].peaks.ball_peak_pressure_mpa);
    EXPECT_GT(ball_pressure[k], 0.0);
    EXPECT_LE(ball_pressure[k], results[k].peaks.max_pressure_mpa);
    for (unsigned d = 0; d < 3; ++d) {
      EXPECT_EQ(ball_pressure_position[3 * k + d], results[k].peaks.ball_peak_pressure_position_mm[d]);
    }
  }
}

// Searched beside the step before, each step's contact must be exactly what the step would have
// searched itself (fem/contact_search_ahead.h), with the same answers bit for bit. The femoral
// shell turns with its bone, so every step's master faces and search radius differ. As the
// master (the hip's pairing: the acetabular side is the slave) the search ahead is used; as the
// slave it moves between the steps, which the search ahead must notice (it read the slave nodes
// in the previous placement), and every later step searches anew. The first step's own search
// runs beside its factorisation, on the mesh as placed for it: used either way.
TEST(FemMotion, SearchAheadGivesTheStepsOfTheMotionSearchedStepByStep) {
  const Tensor<1, 3> axis({1, 2, 3});
  std::vector<MotionStep> steps;
  for (int k = 0; k < 3; ++k)
    steps.push_back({rotation_about_axis(axis, 0.2 * k), Tensor<1, 3>({40.0, -30.0, 60.0})});
  // The mapping at the element's degree: a face is then determined by its support points, so a
  // turned face can be checked and kept (at degree 4 every face is made anew at every step, and
  // a search ahead, whose faces were turned, is never used).
  ContactOptions contact_options;
  contact_options.mapping_degree = 2;
  contact_options.linear_solver = LinearSolver::kSubstructured;
  // The searches ahead need a second thread (a one-core machine searches every step itself).
  const bool two_threads = dealii::MultithreadInfo::n_threads() >= 2;
  for (const bool femoral_slave : {false, true}) {
    std::vector<std::vector<ContactResult>> runs;
    for (const bool ahead : {false, true}) {
      ContactProblem problem(MPI_COMM_WORLD, contact_options);
      build_shells(problem);
      if (!femoral_slave) {
        const ContactPair pair = problem.model().contact_pairs.front();
        problem.model().contact_pairs = {{pair.master_boundary_id, -1, pair.slave_boundary_id}};
      }
      MotionOptions options;
      options.search_ahead = ahead;
      runs.push_back(run_motion(problem, steps, options));
    }
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const ContactResult& stepwise = runs[0][k];
      const ContactResult& ahead = runs[1][k];
      ASSERT_EQ(stepwise.status, ContactStatus::kConverged) << "step " << k;
      ASSERT_EQ(ahead.status, ContactStatus::kConverged) << "step " << k;
      EXPECT_EQ(ahead.statistics.searched_ahead, (k == 0 || !femoral_slave) && two_threads)
          << "step " << k;
      EXPECT_EQ(ahead.statistics.active_set_iterations, stepwise.statistics.active_set_iterations);
      EXPECT_EQ(ahead.rigid_translation_mm[0], stepwise.rigid_translation_mm[0]) << "step " << k;
      EXPECT_EQ(ahead.peaks.max_pressure_mpa, stepwise.peaks.max_pressure_mpa) << "step " << k;
      ASSERT_EQ(ahead.nodes.size(), stepwise.nodes.size());
      for (std::size_t n = 0; n < ahead.nodes.size(); ++n) {
        EXPECT_EQ(ahead.nodes[n].pressure_mpa, stepwise.nodes[n].pressure_mpa) << k << " " << n;
        EXPECT_EQ(ahead.nodes[n].gap_mm, stepwise.nodes[n].gap_mm) << k << " " << n;
      }
    }
  }
}

}  // namespace
}  // namespace hipfai::fem
