// fem::ContactModel and check_references: the model's internal references.
#include "fem/contact_model.h"
#include "core/error.h"
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

}  // namespace
}  // namespace hipfai::fem
