// fem::write_contact_vtu: the fields of a contact solve in one .vtu file, on the small layer.
#include "fem/contact_output.h"
#include "layer_fixture.h"

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

}  // namespace
}  // namespace hipfai::fem
