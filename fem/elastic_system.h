// hipfai — the linear elastic system of the deformable bodies: finite element, mapping, degrees
// of freedom, cell stiffness matrices, internal forces and stresses.
//
// All deformable bodies share one parallel::shared::Triangulation (every rank keeps the whole
// mesh) with an FESystem of three equal FE_Q elements. Bodies bonded to a rigid body are rotated
// rigidly with it before each run (place_bodies), so a large rotation costs no strain in the
// small-strain model. The stiffness of every cell is computed once per run and cached across
// runs for cells that have not moved: assembly and internal forces only apply these matrices.
// Units: mm, N, MPa.
#pragma once

#include "fem/contact_model.h"
#include "fem/peak_measures.h"

#include <deal.II/base/index_set.h>
#include <deal.II/base/point.h>
#include <deal.II/distributed/shared_tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <mpi.h>

#include <array>
#include <map>
#include <utility>
#include <vector>

namespace hipfai::fem {

// A displacement with the internal forces it causes (both replicated on every rank).
struct Linearization {
  dealii::Vector<double> displacement;  // constraints distributed
  std::vector<double> internal_force;   // f_i = integral of sigma(u) : eps(phi_i)
};

// Von Mises stress at every Gauss point, per body.
struct VonMisesField {
  // Per body (index into ContactModel::bodies): value (MPa), position (mm, the run's pose,
  // undeformed) and JxW (mm^3) of each Gauss point, cells in order.
  std::vector<std::vector<FieldSample>> samples;
  dealii::Vector<float> cell_max;  // largest over each active cell's Gauss points (MPa)
};

class ElasticSystem {
 public:
  // The cells are partitioned over the communicator's ranks (every rank holds the whole mesh).
  // The substructured solver, which solves on rank 0 alone (fem/rank_team.h), gives its system
  // MPI_COMM_SELF: its dofs are numbered, and every loop over them sums, as on one rank.
  ElasticSystem(MPI_Comm communicator, unsigned int fe_degree, unsigned int mapping_degree);

  // Moves the mesh to the model's pose: the cells of a body bonded to a rigid body rotated with
  // it from the reference vertices (saved on the first call, so rotations do not accumulate).
  void place_bodies(const ContactModel& model);
  // The triangulation's diameter in its current placement (GridTools::diameter's measure, a
  // pairwise scan of the boundary vertices), computed once per set-up: the contact stages of a
  // run ask for it several times.
  double diameter() const;
  // The same number for the placement place_bodies(model) would make, without moving the mesh
  // (bit for bit what diameter() gives after it); the current one before the first placement.
  double diameter_if_placed(const ContactModel& model) const;
  // Lame constants per material, dofs and their support points. Throws hipfai::Error for a cell
  // whose material id belongs to no body.
  void setup(const ContactModel& model);
  // Stiffness of every locally owned cell (every cell with every_cell: a rank that factorises
  // whole bodies) that moved (or changed material) since the last call.
  void compute_cell_matrices(bool every_cell = false);

  // A fingerprint of the dof layout: the dof indices and material of every cell, in cell order
  // (FNV-1a). Equal keys: the same dofs on the same cells, so per-layout data can be kept.
  std::size_t dof_layout_key() const;

  // Internal forces K u of each displacement, in one pass over the cells.
  std::vector<std::vector<double>> internal_forces(
      const std::vector<const dealii::Vector<double>*>& displacements) const;
  // Fills each state's internal_force from its displacement.
  void add_internal_forces(std::vector<Linearization>& states) const;
  // Von Mises stress of the displacement at every Gauss point, per body of the model.
  VonMisesField von_mises(const dealii::Vector<double>& displacement,
                          const ContactModel& model) const;
  // Displacement at a point of the run's configuration.
  dealii::Tensor<1, 3> point_value(const dealii::Vector<double>& displacement,
                                   const dealii::Point<3>& point) const;

  MPI_Comm communicator() const { return comm_; }
  // Threads of this rank's FE stages (cell matrices, von Mises, the contact search, the condensed
  // contact problem): threads_per_rank(communicator) (fem/thread_chunks.h) unless set_threads
  // gave another count. The substructured solver on several ranks gives its leading rank the
  // machine's threads and its helpers one (fem/contact_problem.cpp). 0 restores the default.
  std::size_t threads() const;
  void set_threads(std::size_t n_threads) { threads_ = n_threads; }
  dealii::parallel::shared::Triangulation<3>& triangulation() { return triangulation_; }
  const dealii::parallel::shared::Triangulation<3>& triangulation() const { return triangulation_; }
  const dealii::FESystem<3>& fe() const { return fe_; }
  const dealii::MappingQ<3>& mapping() const { return mapping_; }
  const dealii::DoFHandler<3>& dof_handler() const { return dof_handler_; }
  const dealii::IndexSet& owned_dofs() const { return owned_dofs_; }
  const dealii::IndexSet& all_dofs() const { return all_dofs_; }
  const std::vector<dealii::Point<3>>& support_points() const { return support_points_; }
  // Stiffness of a locally owned cell (by active cell index), after compute_cell_matrices.
  const dealii::FullMatrix<double>& cell_matrix(unsigned int active_cell_index) const {
    return cell_matrices_[active_cell_index];
  }

  // Tabulated per cell dof (deal.II answers these through several virtual layers per call; the
  // contact search asks them millions of times).
  unsigned int component_of(unsigned int i) const { return component_of_[i]; }
  unsigned int base_of(unsigned int i) const { return base_of_[i]; }
  bool support_on_face(unsigned int face_no, unsigned int i) const {
    return support_on_face_[face_no][i];
  }
  unsigned int system_index(unsigned int base_index, unsigned int component) const {
    return system_index_[base_index][component];
  }

 private:
  void cell_stiffness(const dealii::DoFHandler<3>::active_cell_iterator& cell,
                      dealii::FEValues<3>& fe_values, dealii::FullMatrix<double>& matrix) const;
  // Every vertex where place_bodies(model) puts it (from the reference vertices).
  std::vector<dealii::Point<3>> placed_vertices(const ContactModel& model) const;
  // Per vertex: on a boundary face (marked once per triangulation).
  const std::vector<bool>& boundary_vertices() const;

  MPI_Comm comm_;
  std::size_t threads_ = 0;  // 0: threads_per_rank(comm_)
  dealii::parallel::shared::Triangulation<3> triangulation_;
  dealii::FESystem<3> fe_;
  dealii::MappingQ<3> mapping_;
  dealii::DoFHandler<3> dof_handler_;
  std::vector<unsigned int> component_of_, base_of_;  // per cell dof
  std::array<std::vector<bool>, dealii::GeometryInfo<3>::faces_per_cell> support_on_face_;
  std::vector<std::array<unsigned int, 3>> system_index_;  // [base index][component]
  std::map<dealii::types::material_id, std::pair<double, double>>
      lame_by_material_;  // (lambda, mu)
  dealii::IndexSet owned_dofs_, all_dofs_;
  std::vector<dealii::Point<3>> support_points_;  // of every dof
  std::vector<dealii::Point<3>> reference_vertices_;
  mutable double diameter_ = -1.0;  // of the current placement, < 0 until asked
  mutable std::vector<bool> boundary_vertices_;
  // Stiffness of every locally owned cell (by active cell index) in the configuration of this
  // run, with the vertices and Lame constants each was computed with: a cell whose vertices have
  // not moved since (the tissues of the fixed bodies) keeps its matrix in the next run — the
  // mapping's other support points follow from the vertices and the triangulation's manifolds,
  // which do not change.
  std::vector<dealii::FullMatrix<double>> cell_matrices_;
  std::vector<std::array<dealii::Point<3>, 8>> cell_matrix_vertices_;
  std::vector<std::pair<double, double>> cell_matrix_lame_;
};

}  // namespace hipfai::fem
