#include "fem/elastic_system.h"

#include "core/error.h"
#include "fem/thread_chunks.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hipfai::fem {

using dealii::types::global_dof_index;

namespace {

geometry::Vec3 point_to_vec3(const dealii::Point<3>& point) { return {point[0], point[1], point[2]}; }

}  // namespace

ElasticSystem::ElasticSystem(MPI_Comm communicator, unsigned int fe_degree, unsigned int mapping_degree)
    : comm_(communicator),
      triangulation_(communicator, dealii::Triangulation<3>::none, false,
                     dealii::parallel::shared::Triangulation<3>::partition_auto),
      fe_(dealii::FE_Q<3>(fe_degree), 3),
      mapping_(mapping_degree),
      dof_handler_(triangulation_) {
  for (unsigned int i = 0; i < fe_.n_dofs_per_cell(); ++i) {
    const auto [component, base_index] = fe_.system_to_component_index(i);
    component_of_.push_back(component);
    base_of_.push_back(base_index);
  }
  for (unsigned int f = 0; f < dealii::GeometryInfo<3>::faces_per_cell; ++f) {
    for (unsigned int i = 0; i < fe_.n_dofs_per_cell(); ++i)
      support_on_face_[f].push_back(fe_.has_support_on_face(i, f));
  }
  const unsigned int n_base = fe_.base_element(0).n_dofs_per_cell();
  system_index_.resize(n_base);
  for (unsigned int b = 0; b < n_base; ++b) {
    for (unsigned int c = 0; c < 3; ++c) system_index_[b][c] = fe_.component_to_system_index(c, b);
  }
}

namespace {

// GridTools::diameter's measure: the largest distance between two boundary vertices (the same
// pairwise scan and arithmetic, so the same number), of any placement of the vertices.
double boundary_diameter(const std::vector<dealii::Point<3>>& vertices,
                         const std::vector<bool>& on_boundary) {
  std::vector<dealii::Point<3>> boundary;
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (on_boundary[i]) boundary.push_back(vertices[i]);
  double max_distance_sqr = 0.0;
  for (std::size_t i = 0; i < boundary.size(); ++i) {
    for (std::size_t j = i + 1; j < boundary.size(); ++j)
      max_distance_sqr = std::max(max_distance_sqr, (boundary[i] - boundary[j]).norm_square());
  }
  return std::sqrt(max_distance_sqr);
}

}  // namespace

const std::vector<bool>& ElasticSystem::boundary_vertices() const {
  if (boundary_vertices_.size() != triangulation_.n_vertices()) {
    boundary_vertices_.assign(triangulation_.n_vertices(), false);
    for (const auto& cell : triangulation_.active_cell_iterators()) {
      for (const unsigned int face : cell->face_indices()) {
        if (!cell->face(face)->at_boundary()) continue;
        for (unsigned int i = 0; i < cell->face(face)->n_vertices(); ++i)
          boundary_vertices_[cell->face(face)->vertex_index(i)] = true;
      }
    }
  }
  return boundary_vertices_;
}

std::size_t ElasticSystem::threads() const {
  return threads_ > 0 ? threads_ : threads_per_rank(comm_);
}

double ElasticSystem::diameter() const {
  if (diameter_ < 0.0) diameter_ = boundary_diameter(triangulation_.get_vertices(), boundary_vertices());
  return diameter_;
}

double ElasticSystem::diameter_if_placed(const ContactModel& model) const {
  if (reference_vertices_.empty()) return diameter();
  return boundary_diameter(placed_vertices(model), boundary_vertices());
}

std::vector<dealii::Point<3>> ElasticSystem::placed_vertices(const ContactModel& model) const {
  std::vector<dealii::Point<3>> placed = reference_vertices_;
  std::vector<bool> done(reference_vertices_.size(), false);
  for (const auto& cell : triangulation_.cell_iterators()) {
    const int rigid = rigid_body_of_material(model, cell->material_id());
    for (const unsigned int v : cell->vertex_indices()) {
      const unsigned int index = cell->vertex_index(v);
      if (done[index]) continue;  // bodies that share a vertex: the first one places it
      done[index] = true;
      if (rigid < 0) continue;
      const RigidBody& body = model.rigid_bodies[rigid];
      const dealii::Point<3>& x = reference_vertices_[index];
      placed[index] = body.rotation_center_mm + body.rotation * (x - body.rotation_center_mm);
    }
  }
  return placed;
}

void ElasticSystem::place_bodies(const ContactModel& model) {
  diameter_ = -1.0;
  if (reference_vertices_.empty()) reference_vertices_ = triangulation_.get_vertices();
  const std::vector<dealii::Point<3>> placed = placed_vertices(model);
  for (const auto& cell : triangulation_.cell_iterators()) {
    for (const unsigned int v : cell->vertex_indices()) cell->vertex(v) = placed[cell->vertex_index(v)];
  }
}

void ElasticSystem::setup(const ContactModel& model) {
  diameter_ = -1.0;  // the mesh may have been changed since it was placed
  boundary_vertices_.clear();
  lame_by_material_.clear();
  for (const Body& body : model.bodies) {
    lame_by_material_[body.material_id] = {body.material.lame_lambda_mpa(),
                                           body.material.shear_modulus_mpa()};
  }
  for (const auto& cell : triangulation_.active_cell_iterators()) {
    if (!lame_by_material_.count(cell->material_id())) {
      throw_error("fem model: cell with material id ", static_cast<int>(cell->material_id()),
                  " belongs to no body");
    }
  }
  dof_handler_.distribute_dofs(fe_);
  owned_dofs_ = dof_handler_.locally_owned_dofs();
  all_dofs_ = dealii::complete_index_set(dof_handler_.n_dofs());

  // Support point of every dof, from every cell (the shared triangulation has them all).
  support_points_.assign(dof_handler_.n_dofs(), dealii::Point<3>());
  dealii::FEValues<3> fe_values(mapping_, fe_, dealii::Quadrature<3>(fe_.get_unit_support_points()),
                                dealii::update_quadrature_points);
  std::vector<global_dof_index> dofs(fe_.n_dofs_per_cell());
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fe_values.reinit(cell);
    cell->get_dof_indices(dofs);
    for (unsigned int i = 0; i < dofs.size(); ++i)
      support_points_[dofs[i]] = fe_values.quadrature_point(i);
  }
}

void ElasticSystem::cell_stiffness(const dealii::DoFHandler<3>::active_cell_iterator& cell,
                                   dealii::FEValues<3>& fe_values,
                                   dealii::FullMatrix<double>& matrix) const {
  fe_values.reinit(cell);
  const auto [lambda, mu] = lame_by_material_.at(cell->material_id());
  const unsigned int n = fe_.n_dofs_per_cell();
  const dealii::FEValuesExtractors::Vector displacement(0);
  std::vector<dealii::SymmetricTensor<2, 3>> strain(n);
  std::vector<double> divergence(n);
  matrix = 0;
  for (unsigned int q = 0; q < fe_values.n_quadrature_points; ++q) {
    for (unsigned int i = 0; i < n; ++i) {
      strain[i] = fe_values[displacement].symmetric_gradient(i, q);
      divergence[i] = dealii::trace(strain[i]);
    }
    const double weight = fe_values.JxW(q);
    for (unsigned int i = 0; i < n; ++i) {
      for (unsigned int j = i; j < n; ++j) {
        const double value =
            (lambda * divergence[i] * divergence[j] + 2.0 * mu * (strain[i] * strain[j])) * weight;
        matrix(i, j) += value;
        if (j != i) matrix(j, i) += value;
      }
    }
  }
}

void ElasticSystem::compute_cell_matrices(bool every_cell) {
  const std::size_t n_cells = triangulation_.n_active_cells();
  if (cell_matrices_.size() != n_cells) {
    cell_matrices_.assign(n_cells, dealii::FullMatrix<double>());
    cell_matrix_vertices_.assign(n_cells, {});
    cell_matrix_lame_.assign(n_cells, {std::numeric_limits<double>::quiet_NaN(), 0.0});
  }
  std::vector<dealii::DoFHandler<3>::active_cell_iterator> cells;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!every_cell && !cell->is_locally_owned()) continue;
    const std::size_t index = cell->active_cell_index();
    std::array<dealii::Point<3>, 8> vertices;
    for (unsigned int v = 0; v < 8; ++v) vertices[v] = cell->vertex(v);
    const std::pair<double, double> lame = lame_by_material_.at(cell->material_id());
    if (cell_matrices_[index].m() == fe_.n_dofs_per_cell() &&
        vertices == cell_matrix_vertices_[index] && lame == cell_matrix_lame_[index]) {
      continue;  // unmoved since the last run
    }
    cell_matrix_vertices_[index] = vertices;
    cell_matrix_lame_[index] = lame;
    cells.push_back(cell);
  }
  auto compute = [&](std::size_t first, std::size_t last) {
    dealii::FEValues<3> fe_values(mapping_, fe_, dealii::QGauss<3>(fe_.degree + 1),
                                  dealii::update_gradients | dealii::update_JxW_values);
    for (std::size_t k = first; k < last; ++k) {
      dealii::FullMatrix<double>& matrix = cell_matrices_[cells[k]->active_cell_index()];
      matrix.reinit(fe_.n_dofs_per_cell(), fe_.n_dofs_per_cell());
      cell_stiffness(cells[k], fe_values, matrix);
    }
  };
  run_in_chunks(cells.size(), threads(), compute);
}

std::size_t ElasticSystem::dof_layout_key() const {
  std::size_t key = 1469598103934665603ull;
  const auto mix = [&key](std::size_t value) {
    key ^= value;
    key *= 1099511628211ull;
  };
  mix(dof_handler_.n_dofs());
  std::vector<global_dof_index> dofs(fe_.n_dofs_per_cell());
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    cell->get_dof_indices(dofs);
    mix(cell->material_id());
    for (const global_dof_index dof : dofs) mix(dof);
  }
  return key;
}

std::vector<std::vector<double>> ElasticSystem::internal_forces(
    const std::vector<const dealii::Vector<double>*>& displacements) const {
  // One pass over the cells for all states: each cell matrix is applied to every state's local
  // displacement.
  const std::size_t states = displacements.size();
  const std::size_t n_dofs = dof_handler_.n_dofs();
  std::vector<double> forces(states * n_dofs, 0.0);
  const unsigned int n = fe_.n_dofs_per_cell();
  dealii::Vector<double> local_u(n), local_f(n);
  std::vector<global_dof_index> dofs(n);
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    const dealii::FullMatrix<double>& matrix = cell_matrices_[cell->active_cell_index()];
    cell->get_dof_indices(dofs);
    for (std::size_t k = 0; k < states; ++k) {
      for (unsigned int i = 0; i < n; ++i) local_u[i] = (*displacements[k])[dofs[i]];
      matrix.vmult(local_f, local_u);
      double* force = forces.data() + k * n_dofs;
      for (unsigned int i = 0; i < n; ++i) force[dofs[i]] += local_f[i];
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, forces.data(), static_cast<int>(forces.size()), MPI_DOUBLE, MPI_SUM,
                comm_);
  std::vector<std::vector<double>> result(states);
  for (std::size_t k = 0; k < states; ++k) {
    result[k].assign(forces.begin() + k * n_dofs, forces.begin() + (k + 1) * n_dofs);
  }
  return result;
}

void ElasticSystem::add_internal_forces(std::vector<Linearization>& states) const {
  std::vector<const dealii::Vector<double>*> displacements;
  for (const Linearization& state : states) displacements.push_back(&state.displacement);
  std::vector<std::vector<double>> forces = internal_forces(displacements);
  for (std::size_t k = 0; k < states.size(); ++k) states[k].internal_force = std::move(forces[k]);
}

VonMisesField ElasticSystem::von_mises(const dealii::Vector<double>& displacement,
                                       const ContactModel& model) const {
  // Every rank holds the whole solution: evaluate all cells, no communication needed.
  std::map<dealii::types::material_id, std::size_t> body_of_material;
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    body_of_material[model.bodies[b].material_id] = b;
  VonMisesField field;
  field.samples.resize(model.bodies.size());
  field.cell_max.reinit(triangulation_.n_active_cells());
  // Cells in chunks over the threads, each cell's samples into its own slot, gathered in cell
  // order afterwards: the same field whatever the number of threads.
  std::vector<dealii::DoFHandler<3>::active_cell_iterator> cells;
  for (const auto& cell : dof_handler_.active_cell_iterators()) cells.push_back(cell);
  std::vector<std::vector<FieldSample>> cell_samples(cells.size());
  run_in_chunks(cells.size(), threads(), [&](std::size_t first, std::size_t last) {
    dealii::FEValues<3> fe_values(
        mapping_, fe_, dealii::QGauss<3>(fe_.degree + 1),
        dealii::update_gradients | dealii::update_quadrature_points | dealii::update_JxW_values);
    const dealii::FEValuesExtractors::Vector extractor(0);
    std::vector<dealii::SymmetricTensor<2, 3>> strains(fe_values.n_quadrature_points);
    for (std::size_t c = first; c < last; ++c) {
      const auto& cell = cells[c];
      fe_values.reinit(cell);
      fe_values[extractor].get_function_symmetric_gradients(displacement, strains);
      const auto [lambda, mu] = lame_by_material_.at(cell->material_id());
      std::vector<FieldSample>& out = cell_samples[c];
      float& cell_max = field.cell_max[cell->active_cell_index()];
      for (unsigned int q = 0; q < strains.size(); ++q) {
        const dealii::SymmetricTensor<2, 3>& strain = strains[q];
        const dealii::SymmetricTensor<2, 3> stress =
            lambda * dealii::trace(strain) * dealii::unit_symmetric_tensor<3>() + 2.0 * mu * strain;
        const dealii::SymmetricTensor<2, 3> deviator = dealii::deviator(stress);
        const double value = std::sqrt(1.5 * (deviator * deviator));
        out.push_back({point_to_vec3(fe_values.quadrature_point(q)), value, fe_values.JxW(q)});
        cell_max = std::max(cell_max, static_cast<float>(value));
      }
    }
  });
  for (std::size_t c = 0; c < cells.size(); ++c) {
    std::vector<FieldSample>& out = field.samples[body_of_material.at(cells[c]->material_id())];
    out.insert(out.end(), cell_samples[c].begin(), cell_samples[c].end());
  }
  return field;
}

dealii::Tensor<1, 3> ElasticSystem::point_value(const dealii::Vector<double>& displacement,
                                                const dealii::Point<3>& point) const {
  dealii::Vector<double> value(3);
  dealii::VectorTools::point_value(mapping_, dof_handler_, displacement, point, value);
  dealii::Tensor<1, 3> result;
  for (unsigned int d = 0; d < 3; ++d) result[d] = value[d];
  return result;
}

}  // namespace hipfai::fem
