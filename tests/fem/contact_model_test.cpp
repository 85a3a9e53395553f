// fem::ContactModel and check_references: the model's internal references; what a
// ContactProblem fixes at construction.
#include "fem/contact_model.h"
#include "core/error.h"
#include "fem/contact_problem.h"
#include "layer_fixture.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace hipfai::fem
