// Blocks of hexahedra with a vector Q2 DoF handler and a Q2 mapping, for the unit tests of the
// contact geometry (fem/face_patch.h, fem/boundary_projection.h, fem/mortar_segments.h).
#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <vector>

namespace hipfai::fem::testing {

// One block [lower, upper] of n x n x 1 cells; every boundary face whose centre lies on the
// block's top (z = upper z) gets kTopId, on its bottom kBottomId, the rest keep 0.
class Block {
 public:
  static constexpr dealii::types::boundary_id kTopId = 1, kBottomId = 2;

  Block(const dealii::Point<3>& lower, const dealii::Point<3>& upper, unsigned int n)
      : fe_(dealii::FE_Q<3>(2), 3), mapping_(2) {
    dealii::GridGenerator::subdivided_hyper_rectangle(tria_, {n, n, 1}, lower, upper);
    for (const auto& face : tria_.active_face_iterators()) {
      if (!face->at_boundary()) continue;
      if (std::abs(face->center()[2] - upper[2]) < 1e-12) face->set_boundary_id(kTopId);
      if (std::abs(face->center()[2] - lower[2]) < 1e-12) face->set_boundary_id(kBottomId);
    }
    dof_handler_.reinit(tria_);
    dof_handler_.distribute_dofs(fe_);
  }

  const dealii::DoFHandler<3>& dof_handler() const { return dof_handler_; }
  const dealii::MappingQ<3>& mapping() const { return mapping_; }

  // (cell, face number) of every boundary face with `id`.
  std::vector<std::pair<dealii::DoFHandler<3>::active_cell_iterator, unsigned int>> faces(
      dealii::types::boundary_id id) const {
    std::vector<std::pair<dealii::DoFHandler<3>::active_cell_iterator, unsigned int>> out;
    for (const auto& cell : dof_handler_.active_cell_iterators()) {
      for (const unsigned int f : cell->face_indices()) {
        if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == id)
          out.emplace_back(cell, f);
      }
    }
    return out;
  }

 private:
  dealii::Triangulation<3> tria_;
  dealii::FESystem<3> fe_;
  dealii::MappingQ<3> mapping_;
  dealii::DoFHandler<3> dof_handler_;
};

}  // namespace hipfai::fem::testing
