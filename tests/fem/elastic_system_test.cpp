// fem::ElasticSystem: dofs, cell stiffness, internal forces, von Mises stress and the placing of
// bodies bonded to a rotated rigid body, on the small layer of layer_fixture.h.
#include "fem/elastic_system.h"
#include "core/error.h"
#include "fem/motion_solver.h"
#include "layer_fixture.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hipfai::fem {
namespace {

using testing::layer_model;
using testing::layer_system;

// The displacement u(x) = grad . x + shift at every dof.
dealii::Vector<double> linear_field(const ElasticSystem& system, const dealii::Tensor<2, 3>& grad,
                                    const dealii::Tensor<1, 3>& shift = {}) {
  dealii::Vector<double> u(system.dof_handler().n_dofs());
  std::vector<dealii::types::global_dof_index> dofs(system.fe().n_dofs_per_cell());
  for (const auto& cell : system.dof_handler().active_cell_iterators()) {
    cell->get_dof_indices(dofs);
    for (unsigned int i = 0; i < dofs.size(); ++i) {
      const dealii::Point<3>& x = system.support_points()[dofs[i]];
      u[dofs[i]] = (grad * x + shift)[system.component_of(i)];
    }
  }
  return u;
}

TEST(FemElasticSystem, CountsTheDofsOfQ2) {
  const auto system = layer_system(layer_model(0.0), 2);
  // 5 x 5 x 5 support points of Q2 on 2 x 2 x 2 cells, three components each.
  EXPECT_EQ(system->dof_handler().n_dofs(), 3u * 5 * 5 * 5);
  EXPECT_EQ(system->support_points().size(), system->dof_handler().n_dofs());
  EXPECT_EQ(system->cell_matrix(0).m(), system->fe().n_dofs_per_cell());
}

TEST(FemElasticSystem, RigidMotionsCarryNoInternalForce) {
  const auto system = layer_system(layer_model(0.0), 2);
  dealii::Tensor<2, 3> skew;  // infinitesimal rotation
  skew[0][1] = 0.01;
  skew[1][0] = -0.01;
  const dealii::Vector<double> u =
      linear_field(*system, skew, dealii::Tensor<1, 3>({0.2, -0.1, 0.3}));
  const auto forces = system->internal_forces({&u});
  ASSERT_EQ(forces.size(), 1u);
  for (const double f : forces[0]) EXPECT_NEAR(f, 0.0, 1e-10);
}

TEST(FemElasticSystem, UniaxialStrainGivesTheAnalyticVonMises) {
  const ContactModel model = layer_model(0.0);
  const auto system = layer_system(model, 2);
  dealii::Tensor<2, 3> grad;
  grad[2][2] = -0.01;  // 1 % compression along z, no lateral strain
  const VonMisesField field = system->von_mises(linear_field(*system, grad), model);
  // Stress: sigma_zz = (lambda + 2 mu) eps, sigma_xx = sigma_yy = lambda eps; von Mises = 2 mu
  // |eps|.
  const double expected = 2.0 * model.bodies[0].material.shear_modulus_mpa() * 0.01;
  ASSERT_EQ(field.samples.size(), 1u);
  ASSERT_EQ(field.samples[0].size(), 8u * 27);  // 8 cells, 3^3 Gauss points
  double volume = 0.0;
  for (const FieldSample& sample : field.samples[0]) {
    EXPECT_NEAR(sample.value, expected, 1e-9 * expected);
    volume += sample.weight;
  }
  EXPECT_NEAR(volume, testing::kLayerWidth * testing::kLayerWidth * testing::kLayerThickness, 1e-9);
  for (const float cell_max : field.cell_max) EXPECT_NEAR(cell_max, expected, 1e-5 * expected);
}

TEST(FemElasticSystem, InternalForcesOfSeveralStatesInOnePass) {
  const auto system = layer_system(layer_model(0.0), 2);
  dealii::Tensor<2, 3> grad;
  grad[0][0] = 0.02;
  const dealii::Vector<double> u = linear_field(*system, grad);
  dealii::Vector<double> twice = u;
  twice *= 2.0;
  std::vector<Linearization> states(2);
  states[0].displacement = u;
  states[1].displacement = twice;
  system->add_internal_forces(states);
  double largest = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    EXPECT_NEAR(states[1].internal_force[i], 2.0 * states[0].internal_force[i], 1e-12);
    largest = std::max(largest, std::abs(states[0].internal_force[i]));
  }
  EXPECT_GT(largest, 0.0);  // a stretched layer pulls on its boundary nodes
}

TEST(FemElasticSystem, BondedBodiesFollowTheirRigidBodysRotation) {
  ContactModel model = layer_model(0.0);
  model.bodies[0].bonded_rigid_body = 1;
  model.rigid_bodies[1].rotation = rotation_about_axis(dealii::Tensor<1, 3>({0, 0, 1}), M_PI / 2);
  model.rigid_bodies[1].rotation_center_mm = dealii::Point<3>(0, 0, 0);
  const auto system = layer_system(model, 1);
  // The layer's corner (W, 0, 0) turns to (0, W, 0).
  bool found = false;
  for (const dealii::Point<3>& vertex : system->triangulation().get_vertices()) {
    found = found || vertex.distance(dealii::Point<3>(0, testing::kLayerWidth, 0)) < 1e-12;
  }
  EXPECT_TRUE(found);
}

TEST(FemElasticSystem, RejectsCellsOfNoBody) {
  ContactModel model = layer_model(0.0);
  model.bodies[0].material_id = 7;
  ensure_mpi_initialized();
  ElasticSystem system(MPI_COMM_WORLD, 2, 2);
  testing::mesh_layer(system.triangulation(), 1);
  EXPECT_THROW(system.setup(model), Error);
}

}  // namespace
}  // namespace hipfai::fem
