// fem::ContactModel and check_references: the model's internal references; what a
// ContactProblem fixes at construction.
#include "fem/contact_model.h"
#include "core/error.h"
#include "fem/contact_problem.h"
#include "layer_fixture.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace hipfai::fem {
namespace {

using testing::layer_model;

TEST(FemContactModel, AcceptsAConsistentModel) {
  EXPECT_NO_THROW(check_references(layer_model(0.0)));
  EXPECT_NO_THROW(check_references(ContactModel{}));
}

TEST(FemContactModel, RejectsReferencesToMissingRigidBodies) {
  ContactModel body = layer_model(0.0);
  body.bodies[0].bonded_rigid_body = 2;
  EXPECT_THROW(check_references(body), Error);
  ContactModel bonded = layer_model(0.0);
  bonded.bonded_boundaries[0].rigid_body = 5;
  EXPECT_THROW(check_references(bonded), Error);
  ContactModel pair = layer_model(0.0);
  pair.contact_pairs[0].master_rigid_body = 2;
  EXPECT_THROW(check_references(pair), Error);
}

TEST(FemContactModel, RejectsARigidMasterWithoutSurface) {
  ContactModel model = layer_model(0.0);
  model.contact_pairs[0].master_rigid_body = 0;  // the bone: bonded only, no surface
  EXPECT_THROW(check_references(model), Error);
}

TEST(FemContactModel, RejectsAZeroFreeDirectionOfALoadControlledBody) {
  ContactModel model = layer_model(0.0);
  model.rigid_bodies[1].free_directions = {dealii::Tensor<1, 3>()};
  EXPECT_NO_THROW(check_references(model));  // not load controlled: not used
  model.rigid_bodies[1].load_controlled = true;
  EXPECT_THROW(check_references(model), Error);
}

// The substructured solver's mesh is set up for it at construction (on several ranks, rank 0's
// alone): switching to or from it between runs is an error, not a silently wrong mesh.
TEST(FemContactProblem, RejectsSwitchingToOrFromTheSubstructuredSolver) {
  for (const auto& [built, switched] : {std::pair{LinearSolver::kSubstructured, LinearSolver::kDirect},
                                       std::pair{LinearSolver::kCgAmg, LinearSolver::kSubstructured}}) {
    ContactOptions options;
    options.linear_solver = built;
    ContactProblem problem(MPI_COMM_SELF, options);
    problem.options().linear_solver = switched;
    EXPECT_THROW(problem.run(), Error);
  }
}

// A body in two pieces, one bonded to the bone and one held only by its contact (walls leave it
// free to move vertically), has a singular stiffness as a whole: the substructured solver names
// the piece instead of factorising it. With both pieces bonded it solves. (The body-level check
// alone saw the bonded piece and let the singular factorisation through.)
TEST(FemContactProblem, SubstructuredSolverRefusesAPieceHeldOnlyByContact) {
  using dealii::Point;
  for (const bool second_bonded : {false, true}) {
    ContactOptions options;
    options.linear_solver = LinearSolver::kSubstructured;
    ContactProblem problem(MPI_COMM_SELF, options);
    dealii::Triangulation<3> left, right;
    dealii::GridGenerator::subdivided_hyper_rectangle(left, {2, 2, 2}, Point<3>(0, 0, 0),
                                                      Point<3>(testing::kLayerWidth, testing::kLayerWidth, testing::kLayerThickness));
    const double gap = 2.0, x0 = testing::kLayerWidth + gap;
    dealii::GridGenerator::subdivided_hyper_rectangle(right, {2, 2, 2}, Point<3>(x0, 0, 0),
                                                      Point<3>(x0 + testing::kLayerWidth, testing::kLayerWidth, testing::kLayerThickness));
    dealii::GridGenerator::merge_triangulations(left, right, problem.triangulation());
    constexpr dealii::types::boundary_id kFreeBottom = 9;
    for (const auto& face : problem.triangulation().active_face_iterators()) {
      if (!face->at_boundary()) continue;
      const Point<3> c = face->center();
      const bool on_right = c[0] > testing::kLayerWidth + 0.5 * gap;
      if (c[2] < 1e-9)
        face->set_boundary_id(on_right && !second_bonded ? kFreeBottom : testing::kLayerBottom);
      else if (c[2] > testing::kLayerThickness - 1e-9)
        face->set_boundary_id(testing::kLayerTop);
      else if (std::abs(c[0]) < 1e-9 || std::abs(c[0] - testing::kLayerWidth) < 1e-9 || std::abs(c[0] - x0) < 1e-9 ||
               std::abs(c[0] - x0 - testing::kLayerWidth) < 1e-9)
        face->set_boundary_id(testing::kLayerWallX);
      else
        face->set_boundary_id(testing::kLayerWallY);
    }
    problem.model() = layer_model(0.0);
    problem.model().rigid_bodies[1].translation_mm = dealii::Tensor<1, 3>({0, 0, -0.01});  // the plate pressed in
    if (second_bonded) {
      const ContactResult result = problem.run();
      EXPECT_EQ(result.status, ContactStatus::kConverged);
      continue;
    }
    try {
      problem.run();
      FAIL() << "expected an error";
    } catch (const Error& error) {
      const std::string what = error.what();
      EXPECT_NE(what.find("a piece of 'cartilage' (125 of its 250 nodes, one of 2 pieces) is held only by its contacts"),
                std::string::npos)
          << what;
    }
  }
}

}  // namespace
}  // namespace hipfai::fem
