// fem::write_contact_vtu: the fields of a contact solve in one .vtu file, on the small layer.
#include "fem/contact_output.h"
#include "layer_fixture.h"
#include "core/error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace hipfai::fem {
namespace {

using dealii::Point;

TEST(FemContactOutput, WritesTheFieldsToVtu) {
  const ContactModel model = testing::layer_model(0.0);
  const auto system = testing::layer_system(model, 1);
  SlaveNode node;
  node.position = Point<3>(0, 0, 2);
  const std::vector<SlaveNode> nodes = {node};
  ContactFields fields{{1.5}, {-0.01}, {true}};
  const dealii::Vector<double> displacement(system->dof_handler().n_dofs());
  dealii::Vector<float> von_mises(system->triangulation().n_active_cells());
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "hipfai_fem_contact_output.vtu";
  write_contact_vtu(file.string(), *system, displacement, von_mises, nodes, fields);
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  for (const char* name : {"displacement_mm", "material_id", "von_mises_cell_max_mpa",
                           "contact_pressure_mpa", "contact_gap_mm", "contact_active"}) {
    EXPECT_NE(text.str().find(name), std::string::npos) << name;
  }
  std::filesystem::remove(file);
}

// A node that is the slave of two pairs (the hip model's articular nodes face the femoral
// cartilage and, where it is absent, the femur's bone) shows its whole pressure, the nearer gap
// and active if either pair holds it; the second pair, inactive, must not wipe out the first.
TEST(FemContactOutput, ANodeInTwoPairsShowsTheSumOfItsPressures) {
  SlaveNode cartilage_pair;
  cartilage_pair.pair = 0;
  cartilage_pair.dofs = {3, 4, 5};
  SlaveNode bone_pair = cartilage_pair;
  bone_pair.pair = 1;
  SlaveNode alone;
  alone.dofs = {6, 7, 8};
  const std::vector<SlaveNode> nodes = {cartilage_pair, bone_pair, alone};
  const ContactFields fields{{1.25, 0.0, 0.0}, {-0.002, 0.8, 0.3}, {true, false, false}};
  const dealii::Vector<double> values = contact_dof_fields(9, nodes, fields);
  EXPECT_DOUBLE_EQ(values[3], 1.25);   // pressure: 1.25 + 0
  EXPECT_DOUBLE_EQ(values[4], -0.002); // the nearer gap
  EXPECT_DOUBLE_EQ(values[5], 1.0);    // active in the cartilage pair
  EXPECT_DOUBLE_EQ(values[6], 0.0);
  EXPECT_DOUBLE_EQ(values[7], 0.3);
  EXPECT_DOUBLE_EQ(values[8], 0.0);
  for (const unsigned int dof : {0u, 1u, 2u}) EXPECT_DOUBLE_EQ(values[dof], 0.0);
  // Both pairs active (a node pressed by cartilage and bone): the pressures add.
  const ContactFields both{{1.0, 0.5, 0.0}, {-0.001, -0.003, 0.3}, {true, true, false}};
  const dealii::Vector<double> summed = contact_dof_fields(9, nodes, both);
  EXPECT_DOUBLE_EQ(summed[3], 1.5);
  EXPECT_DOUBLE_EQ(summed[4], -0.003);
  // No solve yet: zeros; fields that do not match the nodes, or a dof out of range: an error.
  const dealii::Vector<double> none = contact_dof_fields(9, nodes, ContactFields());
  EXPECT_DOUBLE_EQ(none.l2_norm(), 0.0);
  EXPECT_THROW(contact_dof_fields(9, nodes, ContactFields{{1.0}, {0.0}, {true}}), Error);
  EXPECT_THROW(contact_dof_fields(8, nodes, fields), Error);
}

}  // namespace
}  // namespace hipfai::fem
