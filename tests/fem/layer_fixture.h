// A small model shared by the unit tests of the contact problem's stages: a layer (W x W x T mm,
// Q2) bonded to bone below, frictionless side walls, a rigid plane just above its top, and
// helpers to build it into an ElasticSystem or a ContactProblem.
#pragma once

#include "fem/contact_constraints.h"
#include "fem/contact_model.h"
#include "fem/contact_problem.h"
#include "fem/elastic_system.h"
#include "fem/mortar_coupling.h"

#include <deal.II/grid/grid_generator.h>

#include <memory>

namespace hipfai::fem::testing {

constexpr double kLayerWidth = 4.0, kLayerThickness = 2.0;  // mm
constexpr dealii::types::boundary_id kLayerBottom = 0, kLayerTop = 1, kLayerWallX = 2,
                                     kLayerWallY = 3;

// The layer's mesh in `tria`, boundary ids set.
inline void mesh_layer(dealii::Triangulation<3>& tria, unsigned int cells_across) {
  dealii::GridGenerator::subdivided_hyper_rectangle(
      tria, {cells_across, cells_across, 2}, dealii::Point<3>(0, 0, 0),
      dealii::Point<3>(kLayerWidth, kLayerWidth, kLayerThickness));
  for (const auto& face : tria.active_face_iterators()) {
    if (!face->at_boundary()) continue;
    const dealii::Point<3> c = face->center();
    if (c[2] < 1e-9)
      face->set_boundary_id(kLayerBottom);
    else if (c[2] > kLayerThickness - 1e-9)
      face->set_boundary_id(kLayerTop);
    else if (c[0] < 1e-9 || c[0] > kLayerWidth - 1e-9)
      face->set_boundary_id(kLayerWallX);
    else
      face->set_boundary_id(kLayerWallY);
  }
}

// Bone (rigid body 0, bonded below) and a plate (rigid body 1) whose surface is the plane
// `gap_mm` above the layer's top, pressing down.
inline ContactModel layer_model(double gap_mm) {
  ContactModel model;
  model.bodies = {{"cartilage", 0, {12.0, 0.45}, -1}};
  RigidBody bone{"bone", nullptr, {}, false, {}, {}, dealii::unit_symmetric_tensor<3>(), {}};
  RigidBody plate{"plate",
                  std::make_shared<RigidPlane>(dealii::Point<3>(0, 0, kLayerThickness + gap_mm),
                                               dealii::Tensor<1, 3>({0, 0, -1})),
                  {},
                  false,
                  {},
                  {},
                  dealii::unit_symmetric_tensor<3>(),
                  {}};
  model.rigid_bodies = {bone, plate};
  model.bonded_boundaries = {{kLayerBottom, 0, {}}};
  model.symmetry_boundaries = {{kLayerWallX, 0}, {kLayerWallY, 1}};
  model.contact_pairs = {{kLayerTop, 1, 0}};
  return model;
}

// An ElasticSystem of the layer (Q2, mapping Q2), set up for `model`, cell matrices computed.
inline std::unique_ptr<ElasticSystem> layer_system(const ContactModel& model,
                                                   unsigned int cells_across) {
  ensure_mpi_initialized();
  auto system = std::make_unique<ElasticSystem>(MPI_COMM_WORLD, 2, 2);
  mesh_layer(system->triangulation(), cells_across);
  system->place_bodies(model);
  system->setup(model);
  system->compute_cell_matrices();
  return system;
}

// The layer with its plate `gap_mm` above: system, fixed dofs and contact nodes.
struct LayerContact {
  ContactModel model;
  std::unique_ptr<ElasticSystem> system;
  ContactConstraints constraints;
  std::vector<SlaveNode> nodes;

  LayerContact(double gap_mm, unsigned int cells_across)
      : model(layer_model(gap_mm)), system(layer_system(model, cells_across)) {
    constraints.collect_fixed_dofs(*system, model);
    nodes = collect_slave_nodes(*system, model, constraints.fixed_dofs());
  }
};

}  // namespace hipfai::fem::testing
