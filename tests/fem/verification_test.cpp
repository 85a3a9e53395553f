// Verification of the FE contact model against closed forms computed here, independently of the
// library's own reference values (fem/verification_cases.cpp).
#include "fem/verification_cases.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <string>

namespace hipfai::fem {
namespace {

double constrained_modulus(double youngs, double poisson) {
  return youngs * (1.0 - poisson) / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
}

// Two layers in series under a rigid plate: p = d / (h1 / M1 + h2 / M2).
double stacked_layers_pressure(const std::map<std::string, double>& in) {
  const double compliance =
      in.at("upper_thickness_mm") /
          constrained_modulus(in.at("upper_youngs_modulus_mpa"), in.at("upper_poisson_ratio")) +
      in.at("lower_thickness_mm") /
          constrained_modulus(in.at("lower_youngs_modulus_mpa"), in.at("lower_poisson_ratio"));
  return in.at("indentation_mm") / compliance;
}

VerificationResult run_case(const std::string& name, unsigned int degree = 2,
                            LinearSolver solver = LinearSolver::kCgAmg) {
  VerificationOptions options;
  options.fe_degree = degree;
  options.linear_solver = solver;
  return run_verification_case(name, options, MPI_COMM_WORLD);
}

TEST(FemVerification, UniaxialLayerPressureIsMdOverH) {
  const VerificationResult result = run_case("uniaxial_layer");
  ASSERT_EQ(result.solve.status, ContactStatus::kConverged);
  const auto& in = result.inputs;
  const double expected = constrained_modulus(in.at("youngs_modulus_mpa"), in.at("poisson_ratio")) *
                          in.at("indentation_mm") / in.at("thickness_mm");
  ASSERT_FALSE(result.solve.nodes.empty());
  // The exact field is linear in z, inside the Q2 space: only the CG tolerance (1e-12 relative
  // residual) separates the nodal pressures from M d / h, far below 1e-6.
  for (const ContactNode& node : result.solve.nodes) {
    EXPECT_TRUE(node.active);
    EXPECT_NEAR(node.pressure_mpa, expected, 1e-6 * expected);
  }
  // Total force = p * area: the node areas tile the top face.
  const double area = in.at("width_mm") * in.at("width_mm");
  EXPECT_NEAR(-result.solve.pair_force_n[0][2], expected * area, 1e-6 * expected * area);
  // Residual penetration well under 1 % of the thickness (it is at solver round-off here).
  EXPECT_LT(result.solve.peaks.max_penetration_mm, 1e-2 * in.at("thickness_mm"));
}

TEST(FemVerification, LoadControlledPlateBalancesTheForce) {
  const VerificationResult result = run_case("uniaxial_load_control");
  ASSERT_EQ(result.solve.status, ContactStatus::kConverged);
  const auto& in = result.inputs;
  const double force = in.at("force_n");
  // The translation solves an exactly affine balance: resultant = force to solver tolerance.
  EXPECT_NEAR(-result.solve.pair_force_n[0][2], force, 1e-6 * force);
  const double area = in.at("width_mm") * in.at("width_mm");
  const double modulus = constrained_modulus(in.at("youngs_modulus_mpa"), in.at("poisson_ratio"));
  const double expected_translation = force * in.at("thickness_mm") / (modulus * area);
  EXPECT_NEAR(-result.solve.rigid_translation_mm[1][2], expected_translation,
              1e-6 * expected_translation);
}

TEST(FemVerification, StackedLayersOnNonMatchingMeshes) {
  const VerificationResult result = run_case("stacked_layers");
  ASSERT_EQ(result.solve.status, ContactStatus::kConverged);
  const auto& in = result.inputs;
  const double expected = stacked_layers_pressure(in);
  unsigned interface_nodes = 0;
  // The exact field is piecewise linear and the interface displacement uniform, both inside the
  // Q2 spaces. Segment-based mortar integrals are exact on these flat faces (Gauss rule exact
  // for the degree-8 integrand on every clipped piece), so the discrete solution is the exact
  // one up to the CG tolerance (1e-12 relative residual): 1e-6 per node, the accuracy required
  // (the earlier composite-quadrature mortar gave 9e-4, node-to-surface 3e-2).
  double worst = 0.0;
  for (const ContactNode& node : result.solve.nodes) {
    EXPECT_NEAR(node.pressure_mpa, expected, 1e-6 * expected) << "pair " << node.pair;
    worst = std::max(worst, std::abs(node.pressure_mpa - expected) / expected);
    interface_nodes += node.pair == 1;
  }
  std::cout << "stacked_layers: worst nodal relative pressure error " << worst << "\n";
  // Resultants over the area (on the upper layer: down from the plate, up from the lower layer).
  const double area = in.at("width_mm") * in.at("width_mm");
  EXPECT_NEAR(-result.solve.pair_force_n[0][2] / area, expected, 1e-6 * expected);
  EXPECT_NEAR(result.solve.pair_force_n[1][2] / area, expected, 1e-6 * expected);
  EXPECT_GT(interface_nodes, 0u);
}

// Contact pressure between two spherical shells from u = A r + B / r^2, eliminating shell by
// shell: u(b) of each shell as an affine function of the contact pressure p.
double lame_pressure(double a, double b, double c, double d, double youngs, double poisson) {
  const double bulk3 = youngs / (1 - 2 * poisson);          // 3K
  const double shear4 = 2 * youngs / (1 + poisson);         // 4 mu
  // Shell [r0, r1] with u(r0) = u0 and sigma_rr(r1) = -p: returns u(r1) = alpha + beta p.
  const auto end_displacement = [&](double r0, double r1, double u0, double& alpha, double& beta) {
    // [r0, 1/r0^2; 3K, -4mu/r1^3] [A; B] = [u0; -p]
    const double det = r0 * (-shear4 / (r1 * r1 * r1)) - bulk3 / (r0 * r0);
    const double a_u0 = (-shear4 / (r1 * r1 * r1)) / det, a_p = -(1 / (r0 * r0)) * -1 / det;
    const double b_u0 = -bulk3 / det, b_p = r0 * -1 / det;
    alpha = (a_u0 * r1 + b_u0 / (r1 * r1)) * u0;
    beta = a_p * r1 + b_p / (r1 * r1);
  };
  double alpha_inner, beta_inner, alpha_outer, beta_outer;
  end_displacement(a, b, d, alpha_inner, beta_inner);
  end_displacement(c, b, 0.0, alpha_outer, beta_outer);  // outer shell, integrated inwards
  return (alpha_outer - alpha_inner) / (beta_inner - beta_outer);
}

TEST(FemVerification, SphericalShellsMatchLame) {
  const VerificationResult result = run_case("spherical_shells");
  ASSERT_EQ(result.solve.status, ContactStatus::kConverged);
  const auto& in = result.inputs;
  const double expected =
      lame_pressure(in.at("core_radius_mm"), in.at("contact_radius_mm"), in.at("cup_radius_mm"),
                    in.at("core_expansion_mm"), in.at("youngs_modulus_mpa"), in.at("poisson_ratio"));
  ASSERT_GT(expected, 0.0);
  double sum = 0, worst = 0;
  unsigned count = 0;
  for (const ContactNode& node : result.solve.nodes) {
    EXPECT_TRUE(node.active);
    // Curved, non-matching Q2 surfaces (faceting of the geometry, segment polygons following
    // curved master edges to second order): nodal pressures measured within 0.8 % on this mesh,
    // bound 1.5 %; the mean measured 0.2 %, bound 0.5 %.
    EXPECT_NEAR(node.pressure_mpa, expected, 0.015 * expected);
    worst = std::max(worst, std::abs(node.pressure_mpa - expected) / expected);
    sum += node.pressure_mpa;
    ++count;
  }
  std::cout << "spherical_shells: worst nodal relative error " << worst << ", mean "
            << std::abs(sum / count - expected) / expected << "\n";
  EXPECT_NEAR(sum / count, expected, 0.005 * expected);
  EXPECT_LT(result.solve.peaks.max_penetration_mm, 1e-2 * 2.0);
}

TEST(FemVerification, HertzSphereOnBlockSlow) {
  const VerificationResult result = run_case("hertz");
  ASSERT_EQ(result.solve.status, ContactStatus::kConverged);
  const auto& in = result.inputs;
  const double modulus = in.at("youngs_modulus_mpa") /
                         (1 - in.at("poisson_ratio") * in.at("poisson_ratio"));
  const double force = in.at("force_n");
  const double radius = std::cbrt(3 * force * in.at("sphere_radius_mm") / (4 * modulus));
  const double peak = 3 * force / (2 * M_PI * radius * radius);
  EXPECT_NEAR(-result.solve.pair_force_n[0][2], force / 4, 1e-6 * force / 4);
  for (const VerificationQuantity& q : result.quantities) {
    // 5 %: the accuracy the task asks of the finest mesh.
    if (q.name == "peak pressure") {
      EXPECT_NEAR(q.computed, peak, 0.05 * peak);
    }
    if (q.name == "contact radius (fit)") {
      EXPECT_NEAR(q.computed, radius, 0.05 * radius);
    }
  }
}


// The direct solver's reduction P^T K P (built row by row on one rank, by PETSc's triple product
// on several) against the same closed forms: the exact solutions lie in the Q2 spaces, so only
// round-off separates the nodal pressures from them. Stacked layers put a deformable mortar
// master into P (29 weights per slave row), the load-controlled plate the free translation.
// The substructured solver (each body factorised once, the contact condensed onto the active
// constraints and the free translations) solves the same discrete problem as the monolithic
// direct solve: on the cases with a closed form whose bodies are all bonded (symmetry walls, a
// prescribed indentation, load control, concentric shells with a deformable master) the same
// active set, nodal pressures and gaps, and the same closed-form quantities. (Hertz is left to
// the slow suite's direct and CG runs.)
TEST(FemVerification, SubstructuredSolverEqualsTheDirectOne) {
  for (const std::string name : {"uniaxial_layer", "uniaxial_load_control", "spherical_shells"}) {
    SCOPED_TRACE(name);
    const VerificationResult direct = run_case(name, 2, LinearSolver::kDirect);
    const VerificationResult condensed = run_case(name, 2, LinearSolver::kSubstructured);
    ASSERT_EQ(direct.solve.status, ContactStatus::kConverged);
    ASSERT_EQ(condensed.solve.status, ContactStatus::kConverged);
    EXPECT_TRUE(condensed.passed());
    ASSERT_EQ(condensed.solve.nodes.size(), direct.solve.nodes.size());
    ASSERT_FALSE(direct.solve.nodes.empty());
    const double scale = direct.solve.peaks.max_pressure_mpa;
    for (std::size_t n = 0; n < direct.solve.nodes.size(); ++n) {
      ASSERT_EQ(condensed.solve.nodes[n].active, direct.solve.nodes[n].active) << "node " << n;
      EXPECT_NEAR(condensed.solve.nodes[n].pressure_mpa, direct.solve.nodes[n].pressure_mpa, 1e-9 * scale);
      EXPECT_NEAR(condensed.solve.nodes[n].gap_mm, direct.solve.nodes[n].gap_mm, 1e-12);
    }
    ASSERT_EQ(condensed.quantities.size(), direct.quantities.size());
    for (std::size_t q = 0; q < direct.quantities.size(); ++q) {
      EXPECT_NEAR(condensed.quantities[q].computed, direct.quantities[q].computed,
                  1e-9 * std::abs(direct.quantities[q].computed))
          << direct.quantities[q].name;
    }
    for (std::size_t b = 0; b < direct.solve.rigid_translation_mm.size(); ++b) {
      EXPECT_LT((condensed.solve.rigid_translation_mm[b] - direct.solve.rigid_translation_mm[b]).norm(),
                1e-12 + 1e-9 * direct.solve.rigid_translation_mm[b].norm());
    }
  }
}

// A body held only by its contacts (the upper layer of the stacked case floats between the
// plate and the lower layer, walls leaving it free to move vertically) has no factorisable
// stiffness of its own: the substructured solver says so instead of solving a singular system.
TEST(FemVerification, SubstructuredSolverRefusesABodyHeldOnlyByContact) {
  try {
    run_case("stacked_layers", 2, LinearSolver::kSubstructured);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("'cartilage' is held only by its contacts"), std::string::npos)
        << error.what();
  }
}

TEST(FemVerification, DirectSolverReproducesTheClosedForms) {
  {
    const VerificationResult result = run_case("uniaxial_layer", 2, LinearSolver::kDirect);
    ASSERT_EQ(result.solve.status, ContactStatus::kConverged);
    const auto& in = result.inputs;
    const double expected = constrained_modulus(in.at("youngs_modulus_mpa"), in.at("poisson_ratio")) *
                            in.at("indentation_mm") / in.at("thickness_mm");
    ASSERT_FALSE(result.solve.nodes.empty());
    for (const ContactNode& node : result.solve.nodes) EXPECT_NEAR(node.pressure_mpa, expected, 1e-9 * expected);
  }
  {
    const VerificationResult result = run_case("stacked_layers", 2, LinearSolver::kDirect);
    ASSERT_EQ(result.solve.status, ContactStatus::kConverged);
    const auto& in = result.inputs;
    const double expected = stacked_layers_pressure(in);
    unsigned interface_nodes = 0;
    for (const ContactNode& node : result.solve.nodes) {
      EXPECT_NEAR(node.pressure_mpa, expected, 1e-9 * expected) << "pair " << node.pair;
      interface_nodes += node.pair == 1;
    }
    EXPECT_GT(interface_nodes, 0u);
  }
  {
    const VerificationResult result = run_case("uniaxial_load_control", 2, LinearSolver::kDirect);
    ASSERT_EQ(result.solve.status, ContactStatus::kConverged);
    const auto& in = result.inputs;
    const double force = in.at("force_n");
    EXPECT_NEAR(-result.solve.pair_force_n[0][2], force, 1e-9 * force);
  }
}

}  // namespace
}  // namespace hipfai::fem
