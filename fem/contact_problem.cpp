#include "fem/contact_problem.h"

#include "core/error.h"
#include "fem/boundary_projection.h"
#include "fem/face_patch.h"
#include "fem/mortar_segments.h"
#include "fem/peak_measures.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/petsc_precondition.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <petscksp.h>
#include <petscmat.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <memory>
#include <optional>
#include <thread>

namespace hipfai::fem {

using dealii::types::global_dof_index;

const char* to_string(ContactStatus status) {
  switch (status) {
    case ContactStatus::kConverged: return "converged";
    case ContactStatus::kActiveSetNotConverged: return "active set not converged";
    case ContactStatus::kLinearSolverFailed: return "linear solver failed";
    case ContactStatus::kNoContact: return "no contact";
    case ContactStatus::kNonFinite: return "non-finite numbers";
  }
  return "unknown";
}

const char* to_string(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::kCgAmg: return "cg_amg";
    case LinearSolver::kDirect: return "direct";
  }
  return "unknown";
}

void ensure_mpi_initialized() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized) return;
  // Held until exit: finalizes PETSc and MPI after every solver object is gone. One thread per
  // rank: the parallelism we want is MPI, not TBB inside each rank.
  static int argc = 1;
  static char name[] = "hipfai";
  static char* args[] = {name, nullptr};
  static char** argv = args;
  static dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
}

namespace {

struct Linearization {
  dealii::Vector<double> displacement;  // replicated on every rank, constraints distributed
  std::vector<double> internal_force;   // replicated: f_i = integral of sigma(u) : eps(phi_i)
};

struct NodeData {
  unsigned int pair = 0;
  std::array<global_dof_index, 3> dofs{};
  unsigned int constrained_component = 0;
  dealii::Point<3> position;
  dealii::Tensor<1, 3> normal;
  double initial_gap = 0.0;  // (x_s - x_m) . n in the reference configuration
  double area = 0.0;
  int rigid_body = -1;
  std::array<std::vector<std::pair<global_dof_index, double>>, 3> master;
};

// Wall time per phase of one run (verbose output: where the time goes).
struct PhaseTimes {
  double setup = 0, contact_search = 0, sparsity = 0, assembly = 0, solver_setup = 0, solves = 0,
         internal_force = 0, stress = 0;
};

// Seconds since the previous call (or construction).
class Lap {
 public:
  double operator()() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

struct BondedDof {
  global_dof_index dof;
  unsigned int component;
  int rigid_body;
  double extra;
};

}  // namespace

namespace {

// Runs work(first, last) over [0, n) in contiguous chunks on threads, sharing the machine's
// cores with the other MPI ranks on it (the calling thread takes the first chunk).
template <class Work>
void run_in_chunks(std::size_t n, MPI_Comm comm, const Work& work) {
  const std::size_t n_threads = std::clamp<std::size_t>(
      std::thread::hardware_concurrency() / dealii::Utilities::MPI::n_mpi_processes(comm), 1, 8);
  const std::size_t chunk = (n + n_threads - 1) / n_threads;
  std::vector<std::thread> workers;
  for (std::size_t t = 1; t < n_threads; ++t) {
    const std::size_t first = std::min(n, t * chunk);
    const std::size_t last = std::min(n, first + chunk);
    if (first < last) workers.emplace_back(work, first, last);
  }
  work(0, std::min(n, chunk));
  for (std::thread& worker : workers) worker.join();
}

// CG with PETSc's smoothed-aggregation AMG (GAMG) given the six rigid-body modes as its near
// null space: the elasticity-aware multigrid that plain scalar BoomerAMG is not (the latter
// coarsens the displacement components independently and needs many more CG iterations on
// thin or nearly incompressible layers). Falls back to BoomerAMG when the dofs are not numbered
// node by node (x, y, z of one support point consecutive), which the rigid modes need.
class ElasticityPreconditioner {
 public:
  ElasticityPreconditioner(const dealii::PETScWrappers::MPI::SparseMatrix& matrix,
                           const std::vector<dealii::Point<3>>& support_points,
                           const dealii::IndexSet& owned, MPI_Comm comm, LinearSolver solver) {
    KSPCreate(comm, &ksp_);
    KSPSetOperators(ksp_, matrix, matrix);
    if (solver == LinearSolver::kDirect) {
      // The condensed matrix is symmetric positive definite: Cholesky (half the fill of LU).
      // Factorised in KSPSetUp, then every right-hand side is two triangular solves.
      direct_ = true;
      KSPSetType(ksp_, KSPPREONLY);
      PC pc;
      KSPGetPC(ksp_, &pc);
      PCSetType(pc, PCCHOLESKY);
      PCFactorSetMatSolverType(pc, MATSOLVERMUMPS);
      KSPSetUp(ksp_);
      return;
    }
    KSPSetType(ksp_, KSPCG);
    KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED);
    PC pc;
    KSPGetPC(ksp_, &pc);
    bool interleaved = owned.n_elements() % 3 == 0;
    std::vector<global_dof_index> owned_list;
    owned.fill_index_vector(owned_list);
    for (std::size_t i = 0; interleaved && i + 2 < owned_list.size(); i += 3) {
      interleaved = owned_list[i] + 1 == owned_list[i + 1] && owned_list[i] + 2 == owned_list[i + 2] &&
                    support_points[owned_list[i]].distance(support_points[owned_list[i + 2]]) == 0.0;
    }
    int all_interleaved = interleaved ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &all_interleaved, 1, MPI_INT, MPI_MIN, comm);
    if (all_interleaved) {
      PCSetType(pc, PCGAMG);
      Vec coordinates;
      VecCreateMPI(comm, static_cast<PetscInt>(owned_list.size()), PETSC_DETERMINE, &coordinates);
      VecSetBlockSize(coordinates, 3);
      PetscScalar* values;
      VecGetArray(coordinates, &values);
      for (std::size_t i = 0; i < owned_list.size(); ++i) values[i] = support_points[owned_list[i]][i % 3];
      VecRestoreArray(coordinates, &values);
      MatNullSpace rigid_modes;
      MatNullSpaceCreateRigidBody(coordinates, &rigid_modes);
      MatSetNearNullSpace(matrix, rigid_modes);
      MatNullSpaceDestroy(&rigid_modes);
      VecDestroy(&coordinates);
      // Aggressive coarsening of the first level keeps the setup cheap; the threshold drops weak
      // couplings (thin layers, graded meshes) before aggregation.
      PCGAMGSetThreshold(pc, nullptr, 0);
      PCGAMGSetNSmooths(pc, 1);
    } else {
      PCSetType(pc, PCHYPRE);
      PCHYPRESetType(pc, "boomeramg");
    }
    KSPSetUp(ksp_);
  }
  ~ElasticityPreconditioner() { KSPDestroy(&ksp_); }
  ElasticityPreconditioner(const ElasticityPreconditioner&) = delete;
  ElasticityPreconditioner& operator=(const ElasticityPreconditioner&) = delete;

  // Iterations, negated when CG did not reach the tolerance.
  int solve(const dealii::PETScWrappers::MPI::Vector& rhs, dealii::PETScWrappers::MPI::Vector& x,
            double relative_tolerance, unsigned int max_iterations) {
    if (!direct_) {
      KSPSetTolerances(ksp_, relative_tolerance, 0.0, PETSC_DEFAULT, static_cast<PetscInt>(max_iterations));
    }
    KSPSolve(ksp_, rhs, x);
    PetscInt iterations = 0;
    KSPGetIterationNumber(ksp_, &iterations);
    KSPConvergedReason reason;
    KSPGetConvergedReason(ksp_, &reason);
    return reason > 0 ? static_cast<int>(iterations) : -static_cast<int>(iterations) - 1;
  }

 private:
  KSP ksp_ = nullptr;
  bool direct_ = false;
};

// MUMPS Cholesky of a symmetric positive definite matrix behind a KSP: factorised once, then
// every right-hand side is two triangular solves.
class CholeskySolve {
 public:
  CholeskySolve(MPI_Comm comm, Mat matrix) {
    KSPCreate(comm, &ksp_);
    KSPSetOperators(ksp_, matrix, matrix);
    KSPSetType(ksp_, KSPPREONLY);
    KSPGetPC(ksp_, &pc_);
    PCSetType(pc_, PCCHOLESKY);
    PCFactorSetMatSolverType(pc_, MATSOLVERMUMPS);
  }
  ~CholeskySolve() { KSPDestroy(&ksp_); }
  CholeskySolve(const CholeskySolve&) = delete;
  CholeskySolve& operator=(const CholeskySolve&) = delete;

  bool factorised() const { return factorised_; }
  void factorise() {
    KSPSetUp(ksp_);
    factorised_ = true;
  }
  // False, with PETSc's reasons on `log`, when the factorisation or the solve failed.
  bool solve(Vec rhs, Vec x, dealii::ConditionalOStream& log) {
    KSPSolve(ksp_, rhs, x);
    KSPConvergedReason reason;
    KSPGetConvergedReason(ksp_, &reason);
    if (reason >= 0) return true;
    PCFailedReason pc_reason;
    PCGetFailedReason(pc_, &pc_reason);
    log << "fem: direct solve failed: KSP reason " << static_cast<int>(reason) << ", PC reason "
        << static_cast<int>(pc_reason) << std::endl;
    return false;
  }
  // k right-hand sides at once (one rank): rhs and x are n x k, column-major. MUMPS runs the
  // forward and backward substitutions on the block, which costs little more than one column:
  // the factor is read once instead of k times. False, with the reason on `log`, when the
  // factorisation or the solve failed.
  bool solve_block(PetscInt n, PetscInt k, double* rhs, double* x, dealii::ConditionalOStream& log) {
    Mat factor = nullptr;
    PCFactorGetMatrix(pc_, &factor);
    MatFactorError error = MAT_FACTOR_NOERROR;
    if (factor) MatFactorGetError(factor, &error);
    if (!factor || error != MAT_FACTOR_NOERROR) {
      log << "fem: direct solve failed: factorisation error " << static_cast<int>(error) << std::endl;
      return false;
    }
    Mat b = nullptr, solution = nullptr;
    MatCreateSeqDense(PETSC_COMM_SELF, n, k, rhs, &b);
    MatCreateSeqDense(PETSC_COMM_SELF, n, k, x, &solution);
    const PetscErrorCode code = MatMatSolve(factor, b, solution);
    MatDestroy(&b);
    MatDestroy(&solution);
    if (code != 0) {
      log << "fem: direct block solve failed: PETSc error " << static_cast<int>(code) << std::endl;
      return false;
    }
    return true;
  }

 private:
  KSP ksp_ = nullptr;
  PC pc_ = nullptr;
  bool factorised_ = false;
};

}  // namespace

class ContactProblem::Impl {
 public:
  Impl(MPI_Comm communicator, ContactOptions options_in)
      : comm(communicator),
        options(std::move(options_in)),
        triangulation(communicator),
        fe(dealii::FE_Q<3>(options.fe_degree), 3),
        mapping(options.mapping_degree),
        dof_handler(triangulation),
        pcout(std::cout, options.verbose && dealii::Utilities::MPI::this_mpi_process(
                                                   communicator) == 0) {
    // deal.II answers these per call through several virtual layers; the contact search asks
    // them millions of times, so they are tabulated once.
    for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i) {
      const auto [component, base_index] = fe.system_to_component_index(i);
      component_of.push_back(component);
      base_of.push_back(base_index);
    }
    for (unsigned int f = 0; f < dealii::GeometryInfo<3>::faces_per_cell; ++f) {
      for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i) support_on_face[f].push_back(fe.has_support_on_face(i, f));
    }
    const unsigned int n_base = fe.base_element(0).n_dofs_per_cell();
    system_index.resize(n_base);
    for (unsigned int b = 0; b < n_base; ++b) {
      for (unsigned int c = 0; c < 3; ++c) system_index[b][c] = fe.component_to_system_index(c, b);
    }
  }

  ContactResult run(ContactProblem& model);
  dealii::Tensor<1, 3> displacement_at(const dealii::Point<3>& point) const;
  void output_results(const std::string& file) const;

  MPI_Comm comm;
  ContactOptions options;
  dealii::parallel::shared::Triangulation<3> triangulation;
  dealii::FESystem<3> fe;
  dealii::MappingQ<3> mapping;
  dealii::DoFHandler<3> dof_handler;
  dealii::ConditionalOStream pcout;
  std::vector<unsigned int> component_of, base_of;  // per cell dof
  std::array<std::vector<bool>, dealii::GeometryInfo<3>::faces_per_cell> support_on_face;
  std::vector<std::array<unsigned int, 3>> system_index;  // [base index][component]

 private:
  void place_bodies(const ContactProblem& model);
  void setup_system(const ContactProblem& model);
  void collect_fixed_dofs(const ContactProblem& model);
  void collect_contact_nodes(const ContactProblem& model);
  dealii::AffineConstraints<double> make_constraints(
      const std::vector<dealii::Tensor<1, 3>>& translations) const;
  void cell_stiffness(const dealii::DoFHandler<3>::active_cell_iterator& cell,
                      dealii::FEValues<3>& fe_values, dealii::FullMatrix<double>& matrix) const;
  void compute_cell_matrices();
  std::vector<Linearization> solve_reduced_direct(
      const std::vector<dealii::AffineConstraints<double>>& constraints);
  std::vector<Linearization> solve_reduced_serial(
      const std::vector<dealii::AffineConstraints<double>>& constraints,
      const std::vector<std::vector<dealii::Tensor<1, 3>>>& translation_sets);
  void build_serial_base(const dealii::AffineConstraints<double>& c0);
  std::vector<Linearization> solve_with_base(const std::vector<dealii::AffineConstraints<double>>& constraints,
                                             Lap& lap);
  void base_rhs(const dealii::AffineConstraints<double>& constraint, dealii::Vector<double>& g,
                dealii::Vector<double>& kg, std::vector<double>& rhs) const;
  // The right-hand sides with the base's factor (factorised on first use), the nonzero ones in
  // one block solve; x[i] answers rhs[i].
  bool base_solve(const std::vector<std::vector<double>>& rhs, std::vector<std::vector<double>>& x, Lap& lap);
  bool solve_low_rank(const std::vector<dealii::AffineConstraints<double>>& constraints,
                      const std::vector<std::vector<dealii::Tensor<1, 3>>>& translation_sets,
                      std::vector<Linearization>& states);
  std::size_t dof_layout_key() const;
  std::vector<Linearization> solve_linear(
      const std::vector<std::vector<dealii::Tensor<1, 3>>>& translation_sets);
  void add_internal_forces(std::vector<Linearization>& states) const;
  std::vector<std::vector<double>> internal_forces(const std::vector<dealii::Vector<double>*>& displacements) const;
  std::vector<dealii::Tensor<1, 3>> transmitted_force(const ContactProblem& model,
                                                      const Linearization& state) const;
  void evaluate_nodes(const Linearization& state,
                      const std::vector<dealii::Tensor<1, 3>>& translations,
                      std::vector<double>& force, std::vector<double>& gap) const;
  void von_mises(const ContactProblem& model, ContactResult& result);
  void initial_active_set(const std::vector<dealii::Tensor<1, 3>>& translations, double gap_tolerance);
  void one_constraint_per_node(std::vector<bool>& set, const std::vector<double>& gap,
                               const std::vector<bool>* current = nullptr) const;
  static bool make_finite(ContactResult& result, dealii::Vector<double>& displacement);

  std::map<dealii::types::material_id, std::pair<double, double>> lame_by_material;
  dealii::IndexSet owned_dofs;
  dealii::IndexSet all_dofs;
  std::vector<dealii::Point<3>> support_points;
  std::vector<bool> fixed_dof;  // hanging, bonded or symmetry: never a contact slave dof
  std::vector<BondedDof> bonded_dofs;
  std::vector<std::pair<global_dof_index, double>> symmetry_dofs;
  dealii::AffineConstraints<double> hanging_constraints;
  std::vector<dealii::Point<3>> reference_vertices;
  std::vector<NodeData> nodes;
  std::vector<bool> active;
  // Active set of the last converged run, keyed by (pair, x-component dof of the slave node).
  std::map<std::pair<unsigned int, global_dof_index>, bool> converged_active;
  dealii::Vector<double> converged_solution;  // displacement of the last converged run
  dealii::Vector<double> solution;
  // Stiffness of every locally owned cell (by active cell index) in the configuration of this
  // run: independent of the active set, so computed once per run and reused by every
  // assembly and internal-force pass. The vertices and Lame constants each was computed with:
  // a cell whose vertices have not moved since (the tissues of the fixed bodies) keeps its
  // matrix in the next run — the mapping's other support points follow from the vertices and
  // the triangulation's manifolds, which do not change.
  std::vector<dealii::FullMatrix<double>> cell_matrices;
  std::vector<std::array<dealii::Point<3>, 8>> cell_matrix_vertices;
  std::vector<std::pair<double, double>> cell_matrix_lame;
  // Unconstrained stiffness K of this run (direct solver only), assembled on first use.
  dealii::PETScWrappers::MPI::SparseMatrix stiffness;
  bool stiffness_assembled = false;
  // One rank: K as a serial CSR matrix, its pattern kept across runs while the dof layout (the
  // dof indices of every cell, fingerprinted by dof_layout_key) stays the same.
  dealii::SparsityPattern serial_pattern;
  dealii::SparseMatrix<double> serial_stiffness;
  std::size_t serial_pattern_key = 0;
  // One rank: the factorised reduced system of the run (see solve_reduced_serial).
  struct SerialBase {
    static constexpr PetscInt kDirichlet = -1, kExpanded = -2;
    struct Term {
      PetscInt column;
      double weight;
    };
    bool valid = false;
    std::vector<bool> active;  // the active set P was built for
    // Column map through P: >= 0 a free dof's reduced index, kDirichlet a dof fixed to its
    // inhomogeneity, <= kExpanded - e the e-th constrained dof whose constraint names free dofs.
    std::vector<PetscInt> mapped;
    std::vector<global_dof_index> free_dofs;
    std::vector<std::size_t> expansion_begin;
    std::vector<Term> expansion;
    std::vector<PetscInt> expansion_last;  // largest column of each expansion
    // Rows scattered into each reduced row: the constrained dofs whose constraint names it.
    std::vector<std::vector<std::pair<global_dof_index, double>>> incoming;
    std::vector<PetscInt> row_start, columns;  // upper triangle of P^T K P (CSR)
    std::vector<double> values;
    Mat matrix = nullptr;
    std::unique_ptr<CholeskySolve> cholesky;
    void reset() {
      cholesky.reset();
      if (matrix) MatDestroy(&matrix);
      matrix = nullptr;
      valid = false;
    }
    SerialBase() = default;
    SerialBase(const SerialBase&) = delete;
    SerialBase& operator=(const SerialBase&) = delete;
    ~SerialBase() { reset(); }
  };
  SerialBase serial_base;
  unsigned int factorisations = 0, low_rank_updates = 0;
  std::vector<std::size_t> k_row_start;
  std::vector<global_dof_index> k_columns;
  std::vector<double> k_values;
  // Of the last run, for write_vtu: per node of `nodes`, and per active cell.
  std::vector<double> node_pressure, node_gap;
  dealii::Vector<float> cell_von_mises;
  unsigned int linear_solves = 0;
  unsigned int linear_iterations = 0;
  bool linear_failure = false;
  PhaseTimes times;
};

void ContactProblem::Impl::setup_system(const ContactProblem& model) {
  lame_by_material.clear();
  for (const Body& body : model.bodies) {
    lame_by_material[body.material_id] = {body.material.lame_lambda_mpa(),
                                          body.material.shear_modulus_mpa()};
  }
  for (const auto& cell : triangulation.active_cell_iterators()) {
    if (!lame_by_material.count(cell->material_id())) {
      throw_error("fem model: cell with material id ", static_cast<int>(cell->material_id()),
                  " belongs to no body");
    }
  }
  dof_handler.distribute_dofs(fe);
  owned_dofs = dof_handler.locally_owned_dofs();
  all_dofs = dealii::complete_index_set(dof_handler.n_dofs());

  // Support point of every dof, from every cell (the shared triangulation has them all).
  support_points.assign(dof_handler.n_dofs(), dealii::Point<3>());
  dealii::FEValues<3> fe_values(mapping, fe, dealii::Quadrature<3>(fe.get_unit_support_points()),
                                dealii::update_quadrature_points);
  std::vector<global_dof_index> dofs(fe.n_dofs_per_cell());
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    fe_values.reinit(cell);
    cell->get_dof_indices(dofs);
    for (unsigned int i = 0; i < dofs.size(); ++i) support_points[dofs[i]] = fe_values.quadrature_point(i);
  }
}

void ContactProblem::Impl::collect_fixed_dofs(const ContactProblem& model) {
  fixed_dof.assign(dof_handler.n_dofs(), false);
  bonded_dofs.clear();
  symmetry_dofs.clear();
  hanging_constraints.clear();
  hanging_constraints.reinit(all_dofs);
  dealii::DoFTools::make_hanging_node_constraints(dof_handler, hanging_constraints);
  hanging_constraints.close();
  for (global_dof_index i = 0; i < dof_handler.n_dofs(); ++i) {
    if (hanging_constraints.is_constrained(i)) fixed_dof[i] = true;
  }
  std::vector<global_dof_index> dofs(fe.n_dofs_per_cell());
  // Bonded first: a dof on both a bonded and a symmetry boundary follows the bone.
  for (const BondedBoundary& bonded : model.bonded_boundaries) {
    if (bonded.rigid_body >= static_cast<int>(model.rigid_bodies.size())) {
      throw_error("fem model: bonded boundary ", static_cast<int>(bonded.boundary_id),
                  " refers to rigid body ", bonded.rigid_body, " which does not exist");
    }
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      cell->get_dof_indices(dofs);
      for (const unsigned int face_no : cell->face_indices()) {
        const auto face = cell->face(face_no);
        if (!face->at_boundary() || face->boundary_id() != bonded.boundary_id) continue;
        for (unsigned int i = 0; i < dofs.size(); ++i) {
          if (!support_on_face[face_no][i] || fixed_dof[dofs[i]]) continue;
          const unsigned int component = component_of[i];
          double extra = 0.0;
          if (bonded.extra_displacement_mm) {
            extra = bonded.extra_displacement_mm(support_points[dofs[i]])[component];
          }
          bonded_dofs.push_back({dofs[i], component, bonded.rigid_body, extra});
          fixed_dof[dofs[i]] = true;
        }
      }
    }
  }
  for (const SymmetryBoundary& symmetry : model.symmetry_boundaries) {
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      cell->get_dof_indices(dofs);
      for (const unsigned int face_no : cell->face_indices()) {
        const auto face = cell->face(face_no);
        if (!face->at_boundary() || face->boundary_id() != symmetry.boundary_id) continue;
        for (unsigned int i = 0; i < dofs.size(); ++i) {
          if (!support_on_face[face_no][i] || fixed_dof[dofs[i]]) continue;
          if (component_of[i] != symmetry.axis) continue;
          symmetry_dofs.emplace_back(dofs[i], 0.0);
          fixed_dof[dofs[i]] = true;
        }
      }
    }
  }
}

void ContactProblem::Impl::collect_contact_nodes(const ContactProblem& model) {
  nodes.clear();
  const double diameter = dealii::GridTools::diameter(triangulation);
  dealii::FEFaceValues<3> face_values(mapping, fe, dealii::QGauss<2>(fe.degree + 1),
                                      dealii::update_values | dealii::update_JxW_values);
  std::vector<global_dof_index> dofs(fe.n_dofs_per_cell());
  for (unsigned int p = 0; p < model.contact_pairs.size(); ++p) {
    const ContactPair& pair = model.contact_pairs[p];
    std::unique_ptr<BoundaryProjector> projector;
    if (pair.master_rigid_body < 0) {
      projector = std::make_unique<BoundaryProjector>(mapping, dof_handler, pair.master_boundary_id);
      if (projector->n_faces() == 0) {
        throw_error("fem model: contact pair ", p, ": master boundary ",
                    static_cast<int>(pair.master_boundary_id), " has no faces");
      }
    } else if (pair.master_rigid_body >= static_cast<int>(model.rigid_bodies.size()) ||
               !model.rigid_bodies[pair.master_rigid_body].surface) {
      throw_error("fem model: contact pair ", p, ": rigid body ", pair.master_rigid_body,
                  " does not exist or has no surface");
    }
    std::map<global_dof_index, std::size_t> node_of_dof;  // keyed by the x-component dof
    const std::size_t first_node = nodes.size();
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      cell->get_dof_indices(dofs);
      for (const unsigned int face_no : cell->face_indices()) {
        const auto face = cell->face(face_no);
        if (!face->at_boundary() || face->boundary_id() != pair.slave_boundary_id) continue;
        face_values.reinit(cell, face_no);
        for (unsigned int i = 0; i < dofs.size(); ++i) {
          if (!support_on_face[face_no][i]) continue;
          const unsigned int component = component_of[i], base_index = base_of[i];
          if (component != 0) continue;
          auto [it, inserted] = node_of_dof.try_emplace(dofs[i], nodes.size());
          if (inserted) {
            NodeData node;
            node.pair = p;
            for (unsigned int c = 0; c < 3; ++c) {
              node.dofs[c] = dofs[system_index[base_index][c]];
            }
            node.position = support_points[dofs[i]];
            nodes.push_back(node);
          }
          double area = 0.0;
          for (unsigned int q = 0; q < face_values.n_quadrature_points; ++q) {
            area += face_values.shape_value(i, q) * face_values.JxW(q);
          }
          nodes[it->second].area += area;
        }
      }
    }
    if (nodes.size() == first_node) {
      throw_error("fem model: contact pair ", p, ": slave boundary ",
                  static_cast<int>(pair.slave_boundary_id), " has no faces");
    }
    // Deformable master: mortar weights. Node-to-surface interpolation of the master at the
    // slave node alone fails the patch test on non-matching meshes (a uniform pressure comes
    // out wavy); integrating the gap against the slave shape function instead,
    //   D_s (u_s . n) = sum_j M_sj (u_j . n) - integral phi_s (x_s - x_m) . n,
    //   D_s = integral phi_s,  M_sj = integral phi_s N_j(x_m),
    // over the covered part of the slave surface transmits a uniform pressure exactly when the
    // integrals are exact, which the segment-based integration makes them (flat faces).
    std::vector<std::array<std::map<global_dof_index, double>, 3>> mortar;
    std::vector<dealii::Tensor<1, 3>> weighted_gap;
    std::vector<double> covered;
    if (projector) {
      const std::size_t count = nodes.size() - first_node;
      mortar.resize(count);
      weighted_gap.assign(count, dealii::Tensor<1, 3>());
      covered.assign(count, 0.0);
      MortarSegmentOptions segment_options;
      segment_options.search_radius_mm = 0.05 * diameter;
      const MortarSegmenter segmenter(projector->faces(), segment_options);
      const dealii::FiniteElement<3>& base = fe.base_element(0);
      // The slave faces are integrated independently (threads), each into small dense blocks
      // per master face it sees; the blocks are then added into the sparse rows in face order,
      // so the sums do not depend on the number of threads.
      struct SlaveFace {
        dealii::DoFHandler<3>::active_cell_iterator cell;
        unsigned int face_no;
      };
      struct Block {
        const FacePatch* master = nullptr;
        std::vector<unsigned int> master_base;  // base indices of the master face's nodes
        std::vector<double> m;                  // [slave node][master node]
      };
      struct FaceResult {
        std::vector<unsigned int> slave_base;   // base indices of the slave face's nodes
        std::vector<double> covered;            // per slave node
        std::vector<dealii::Tensor<1, 3>> gap;  // per slave node
        std::vector<Block> blocks;
      };
      std::vector<SlaveFace> slave_faces;
      for (const auto& cell : dof_handler.active_cell_iterators()) {
        for (const unsigned int face_no : cell->face_indices()) {
          const auto face = cell->face(face_no);
          if (face->at_boundary() && face->boundary_id() == pair.slave_boundary_id) slave_faces.push_back({cell, face_no});
        }
      }
      std::vector<FaceResult> face_results(slave_faces.size());
      auto integrate_faces = [&](std::size_t first, std::size_t last) {
        for (std::size_t f = first; f < last; ++f) {
          const SlaveFace& slave_face = slave_faces[f];
          FaceResult& out = face_results[f];
          for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i) {
            if (support_on_face[slave_face.face_no][i] && component_of[i] == 0) out.slave_base.push_back(base_of[i]);
          }
          const std::size_t ns = out.slave_base.size();
          out.covered.assign(ns, 0.0);
          out.gap.assign(ns, dealii::Tensor<1, 3>());
          const FacePatch slave(mapping, slave_face.cell, slave_face.face_no);
          std::vector<double> slave_values(ns);
          for (const MortarPoint& point : segmenter.integrate(slave)) {
            if (out.blocks.empty() || out.blocks.back().master != point.master) {
              Block block;
              block.master = point.master;
              for (unsigned int j = 0; j < fe.n_dofs_per_cell(); ++j) {
                if (support_on_face[point.master->face_no][j] && component_of[j] == 0) block.master_base.push_back(base_of[j]);
              }
              block.m.assign(ns * block.master_base.size(), 0.0);
              out.blocks.push_back(std::move(block));
            }
            Block& block = out.blocks.back();
            const std::size_t nm = block.master_base.size();
            const dealii::Tensor<1, 3> separation = point.slave_point_mm - point.master_point_mm;
            for (std::size_t a = 0; a < ns; ++a) {
              slave_values[a] = base.shape_value(out.slave_base[a], point.slave_unit_point) * point.jxw;
              out.covered[a] += slave_values[a];
              out.gap[a] += slave_values[a] * separation;
            }
            for (std::size_t b = 0; b < nm; ++b) {
              const double value = base.shape_value(block.master_base[b], point.master_unit_point);
              for (std::size_t a = 0; a < ns; ++a) block.m[a * nm + b] += slave_values[a] * value;
            }
          }
        }
      };
      run_in_chunks(slave_faces.size(), comm, integrate_faces);

      std::vector<global_dof_index> master_dofs(fe.n_dofs_per_cell());
      for (std::size_t f = 0; f < slave_faces.size(); ++f) {
        const FaceResult& result = face_results[f];
        slave_faces[f].cell->get_dof_indices(dofs);
        std::vector<std::size_t> local(result.slave_base.size());
        for (std::size_t a = 0; a < local.size(); ++a) {
          local[a] = node_of_dof.at(dofs[system_index[result.slave_base[a]][0]]) - first_node;
          covered[local[a]] += result.covered[a];
          weighted_gap[local[a]] += result.gap[a];
        }
        for (const Block& block : result.blocks) {
          block.master->cell->get_dof_indices(master_dofs);
          const std::size_t nm = block.master_base.size();
          for (std::size_t a = 0; a < local.size(); ++a) {
            for (std::size_t b = 0; b < nm; ++b) {
              const double value = block.m[a * nm + b];
              for (unsigned int c = 0; c < 3; ++c) {
                mortar[local[a]][c][master_dofs[system_index[block.master_base[b]][c]]] += value;
              }
            }
          }
        }
      }
    }

    // Project, choose the constrained component, drop nodes that cannot be constrained.
    std::vector<NodeData> kept(nodes.begin(), nodes.begin() + first_node);
    for (std::size_t n = first_node; n < nodes.size(); ++n) {
      NodeData node = nodes[n];
      dealii::Point<3> master_point;
      if (pair.master_rigid_body >= 0) {
        // The surface is defined in the body's frame: query there, map the answer back.
        const RigidBody& body = model.rigid_bodies[pair.master_rigid_body];
        const dealii::Point<3>& c = body.rotation_center_mm;
        const SurfacePoint closest = body.surface->closest_point(
            c + dealii::transpose(body.rotation) * (node.position - c));
        master_point = c + body.rotation * (closest.point_mm - c);
        node.normal = body.rotation * closest.normal;
        node.rigid_body = pair.master_rigid_body;
      } else {
        // Search radius: contact partners are close; 5 % of the model size is generous.
        const BoundaryProjection projection = projector->project(node.position, 0.05 * diameter);
        if (!projection.found) continue;  // nothing opposite: this node cannot touch
        const std::size_t local = n - first_node;
        // Barely covered nodes (the master ends just past them) would give an ill-scaled row.
        if (!(covered[local] > 1e-6 * node.area)) continue;
        node.normal = projection.normal;
        for (unsigned int c = 0; c < 3; ++c) {
          for (const auto& [dof, value] : mortar[local][c]) {
            if (value != 0.0) node.master[c].emplace_back(dof, value / covered[local]);
          }
        }
        node.initial_gap = weighted_gap[local] * node.normal / covered[local];
      }
      if (pair.master_rigid_body >= 0) node.initial_gap = (node.position - master_point) * node.normal;
      // The slave component with the largest normal share that is still free; with less than
      // 0.3 the constraint would be ill-conditioned (the node sits on a wall parallel to n).
      double best = 0.3;
      bool found = false;
      for (unsigned int c = 0; c < 3; ++c) {
        if (fixed_dof[node.dofs[c]]) continue;
        if (std::abs(node.normal[c]) > best) {
          best = std::abs(node.normal[c]);
          node.constrained_component = c;
          found = true;
        }
      }
      if (found) kept.push_back(node);
    }
    nodes = std::move(kept);
  }
}

dealii::AffineConstraints<double> ContactProblem::Impl::make_constraints(
    const std::vector<dealii::Tensor<1, 3>>& translations) const {
  dealii::AffineConstraints<double> constraints(all_dofs);
  constraints.merge(hanging_constraints);
  for (const BondedDof& bonded : bonded_dofs) {
    double value = bonded.extra;
    if (bonded.rigid_body >= 0) value += translations[bonded.rigid_body][bonded.component];
    constraints.add_line(bonded.dof);
    constraints.set_inhomogeneity(bonded.dof, value);
  }
  for (const auto& [dof, value] : symmetry_dofs) {
    constraints.add_line(dof);
    constraints.set_inhomogeneity(dof, value);
  }
  // Active node: u_s . n = u_m . n - g0, solved for the slave component k.
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (!active[n]) continue;
    const NodeData& node = nodes[n];
    const unsigned int k = node.constrained_component;
    const double n_k = node.normal[k];
    const global_dof_index slave = node.dofs[k];
    constraints.add_line(slave);
    for (unsigned int c = 0; c < 3; ++c) {
      if (c != k && node.normal[c] != 0.0) constraints.add_entry(slave, node.dofs[c], -node.normal[c] / n_k);
    }
    double inhomogeneity = -node.initial_gap;
    if (node.rigid_body >= 0) {
      inhomogeneity += translations[node.rigid_body] * node.normal;
    } else {
      for (unsigned int c = 0; c < 3; ++c) {
        for (const auto& [dof, weight] : node.master[c]) {
          constraints.add_entry(slave, dof, weight * node.normal[c] / n_k);
        }
      }
    }
    constraints.set_inhomogeneity(slave, inhomogeneity / n_k);
  }
  constraints.close();
  return constraints;
}

void ContactProblem::Impl::cell_stiffness(const dealii::DoFHandler<3>::active_cell_iterator& cell,
                                          dealii::FEValues<3>& fe_values,
                                          dealii::FullMatrix<double>& matrix) const {
  fe_values.reinit(cell);
  const auto [lambda, mu] = lame_by_material.at(cell->material_id());
  const unsigned int n = fe.n_dofs_per_cell();
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

void ContactProblem::Impl::compute_cell_matrices() {
  const std::size_t n_cells = triangulation.n_active_cells();
  if (cell_matrices.size() != n_cells) {
    cell_matrices.assign(n_cells, dealii::FullMatrix<double>());
    cell_matrix_vertices.assign(n_cells, {});
    cell_matrix_lame.assign(n_cells, {std::numeric_limits<double>::quiet_NaN(), 0.0});
  }
  std::vector<dealii::DoFHandler<3>::active_cell_iterator> cells;
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    const std::size_t index = cell->active_cell_index();
    std::array<dealii::Point<3>, 8> vertices;
    for (unsigned int v = 0; v < 8; ++v) vertices[v] = cell->vertex(v);
    const std::pair<double, double> lame = lame_by_material.at(cell->material_id());
    if (cell_matrices[index].m() == fe.n_dofs_per_cell() && vertices == cell_matrix_vertices[index] &&
        lame == cell_matrix_lame[index]) {
      continue;  // unmoved since the last run
    }
    cell_matrix_vertices[index] = vertices;
    cell_matrix_lame[index] = lame;
    cells.push_back(cell);
  }
  auto compute = [&](std::size_t first, std::size_t last) {
    dealii::FEValues<3> fe_values(mapping, fe, dealii::QGauss<3>(fe.degree + 1),
                                  dealii::update_gradients | dealii::update_JxW_values);
    for (std::size_t k = first; k < last; ++k) {
      dealii::FullMatrix<double>& matrix = cell_matrices[cells[k]->active_cell_index()];
      matrix.reinit(fe.n_dofs_per_cell(), fe.n_dofs_per_cell());
      cell_stiffness(cells[k], fe_values, matrix);
    }
  };
  run_in_chunks(cells.size(), comm, compute);
}

void ContactProblem::Impl::add_internal_forces(std::vector<Linearization>& states) const {
  std::vector<dealii::Vector<double>*> displacements;
  for (Linearization& state : states) displacements.push_back(&state.displacement);
  std::vector<std::vector<double>> forces = internal_forces(displacements);
  for (std::size_t k = 0; k < states.size(); ++k) states[k].internal_force = std::move(forces[k]);
}

std::vector<std::vector<double>> ContactProblem::Impl::internal_forces(
    const std::vector<dealii::Vector<double>*>& displacements) const {
  // One pass over the cells for all states: the cell stiffness, the expensive part, is
  // computed once and applied to every state's local displacement.
  const std::size_t states = displacements.size();
  const std::size_t n_dofs = dof_handler.n_dofs();
  std::vector<double> forces(states * n_dofs, 0.0);
  const unsigned int n = fe.n_dofs_per_cell();
  dealii::Vector<double> local_u(n), local_f(n);
  std::vector<global_dof_index> dofs(n);
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    const dealii::FullMatrix<double>& matrix = cell_matrices[cell->active_cell_index()];
    cell->get_dof_indices(dofs);
    for (std::size_t k = 0; k < states; ++k) {
      for (unsigned int i = 0; i < n; ++i) local_u[i] = (*displacements[k])[dofs[i]];
      matrix.vmult(local_f, local_u);
      double* force = forces.data() + k * n_dofs;
      for (unsigned int i = 0; i < n; ++i) force[dofs[i]] += local_f[i];
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, forces.data(), static_cast<int>(forces.size()), MPI_DOUBLE, MPI_SUM,
                comm);
  std::vector<std::vector<double>> result(states);
  for (std::size_t k = 0; k < states; ++k) {
    result[k].assign(forces.begin() + k * n_dofs, forces.begin() + (k + 1) * n_dofs);
  }
  return result;
}

std::vector<Linearization> ContactProblem::Impl::solve_linear(
    const std::vector<std::vector<dealii::Tensor<1, 3>>>& translation_sets) {
  // One active set, several rigid translations: the condensed matrix depends only on the active
  // set (the translations enter the inhomogeneities), so it is assembled and its preconditioner
  // set up once, and every translation costs one right-hand side and one CG solve.
  Lap lap;
  std::vector<dealii::AffineConstraints<double>> constraints;
  for (const auto& translations : translation_sets) constraints.push_back(make_constraints(translations));
  if (options.linear_solver == LinearSolver::kDirect) {
    return dealii::Utilities::MPI::n_mpi_processes(comm) == 1 ? solve_reduced_serial(constraints, translation_sets)
                                                               : solve_reduced_direct(constraints);
  }
  const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);

  dealii::DynamicSparsityPattern pattern(all_dofs);
  dealii::DoFTools::make_sparsity_pattern(dof_handler, pattern, constraints[0], false, rank);
  dealii::SparsityTools::distribute_sparsity_pattern(pattern, owned_dofs, comm, all_dofs);
  dealii::PETScWrappers::MPI::SparseMatrix matrix;
  matrix.reinit(owned_dofs, owned_dofs, pattern, comm);
  times.sparsity += lap();
  std::vector<dealii::PETScWrappers::MPI::Vector> rhs(translation_sets.size());
  for (auto& vector : rhs) vector.reinit(owned_dofs, comm);

  const unsigned int n = fe.n_dofs_per_cell();
  dealii::Vector<double> cell_rhs(n);  // no body forces: loads enter through the constraints
  std::vector<global_dof_index> dofs(n);
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    const dealii::FullMatrix<double>& cell_matrix = cell_matrices[cell->active_cell_index()];
    cell->get_dof_indices(dofs);
    constraints[0].distribute_local_to_global(cell_matrix, cell_rhs, dofs, matrix, rhs[0]);
    for (std::size_t k = 1; k < constraints.size(); ++k) {
      constraints[k].distribute_local_to_global(cell_rhs, dofs, rhs[k], cell_matrix);
    }
  }
  matrix.compress(dealii::VectorOperation::add);
  for (auto& vector : rhs) vector.compress(dealii::VectorOperation::add);
  times.assembly += lap();

  std::vector<Linearization> states;
  std::unique_ptr<ElasticityPreconditioner> preconditioner;
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    dealii::PETScWrappers::MPI::Vector x(owned_dofs, comm);
    const double rhs_norm = rhs[k].l2_norm();
    ++linear_solves;
    if (rhs_norm > 0.0) {
      if (!preconditioner) {
        preconditioner = std::make_unique<ElasticityPreconditioner>(matrix, support_points, owned_dofs, comm,
                                                                     options.linear_solver);
        times.solver_setup += lap();
      }
      const int iterations = preconditioner->solve(rhs[k], x, options.linear_relative_tolerance,
                                                   options.max_linear_iterations);
      if (iterations < 0) linear_failure = true;
      linear_iterations += static_cast<unsigned int>(std::abs(iterations));
    }
    Linearization state;
    state.displacement = dealii::Vector<double>(x);
    constraints[k].distribute(state.displacement);
    states.push_back(std::move(state));
  }
  times.solves += lap();
  add_internal_forces(states);
  times.internal_force += lap();
  return states;
}

std::size_t ContactProblem::Impl::dof_layout_key() const {
  // FNV-1a over the dof indices of every cell, in cell order.
  std::size_t key = 1469598103934665603ull;
  const auto mix = [&key](std::size_t value) {
    key ^= value;
    key *= 1099511628211ull;
  };
  mix(dof_handler.n_dofs());
  std::vector<global_dof_index> dofs(fe.n_dofs_per_cell());
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    cell->get_dof_indices(dofs);
    for (const global_dof_index dof : dofs) mix(dof);
  }
  return key;
}

std::vector<Linearization> ContactProblem::Impl::solve_reduced_serial(
    const std::vector<dealii::AffineConstraints<double>>& constraints,
    const std::vector<std::vector<dealii::Tensor<1, 3>>>& translation_sets) {
  // One rank: the same reduced system P^T K P as solve_reduced_direct, built row by row from a
  // serial K instead of by PETSc's general triple product (which spent ~3 s per active set on
  // the 54 k dof hip, 10x the rest of the reduction). P is the identity on the free dofs, so
  // reduced row j is K's row j, plus the rows of the constrained dofs whose constraint names j
  // (scaled by its weight), with every column mapped through P: a free column to its reduced
  // index, a constrained one to the columns its constraint names, a Dirichlet one dropped.
  // Only the upper triangle is kept (the Cholesky factorisation reads no more).
  //
  // The factorised system (the "base": its active set, P and Cholesky factor) is kept for the
  // run. A later active set that differs from it in a few nodes is solved with the same factor
  // and a bordered correction (solve_low_rank) instead of a new reduction and factorisation:
  // most motion steps change 1-8 of several hundred contact nodes and then only confirm.
  Lap lap;
  const global_dof_index n_dofs = dof_handler.n_dofs();
  if (!stiffness_assembled) {
    const std::size_t key = dof_layout_key();
    if (key != serial_pattern_key || serial_pattern.n_rows() != n_dofs) {
      serial_stiffness.clear();
      dealii::DynamicSparsityPattern pattern(n_dofs);
      dealii::DoFTools::make_sparsity_pattern(dof_handler, pattern);
      serial_pattern.copy_from(pattern);
      serial_stiffness.reinit(serial_pattern);
      serial_pattern_key = key;
      times.sparsity += lap();
    }
    serial_stiffness = 0;
    std::vector<global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      cell->get_dof_indices(dofs);
      serial_stiffness.add(dofs, cell_matrices[cell->active_cell_index()]);
    }
    // A plain CSR copy for the row-by-row reduction below (no iterator layers in its loops).
    k_row_start.assign(n_dofs + 1, 0);
    k_columns.clear();
    k_values.clear();
    k_columns.reserve(serial_stiffness.n_nonzero_elements());
    k_values.reserve(serial_stiffness.n_nonzero_elements());
    for (global_dof_index i = 0; i < n_dofs; ++i) {
      for (auto entry = serial_stiffness.begin(i); entry != serial_stiffness.end(i); ++entry) {
        k_columns.push_back(entry->column());
        k_values.push_back(entry->value());
      }
      k_row_start[i + 1] = k_columns.size();
    }
    stiffness_assembled = true;
    times.assembly += lap();
  }

  if (options.low_rank_updates && serial_base.valid) {
    std::vector<Linearization> states;
    if (solve_low_rank(constraints, translation_sets, states)) {
      times.solves += lap();
      add_internal_forces(states);
      times.internal_force += lap();
      return states;
    }
  }
  build_serial_base(constraints.front());
  times.assembly += lap();
  return solve_with_base(constraints, lap);
}

void ContactProblem::Impl::build_serial_base(const dealii::AffineConstraints<double>& c0) {
  SerialBase& base = serial_base;
  base.reset();
  base.active = active;
  const global_dof_index n_dofs = dof_handler.n_dofs();
  std::vector<PetscInt>& mapped = base.mapped;
  std::vector<global_dof_index>& free_dofs = base.free_dofs;
  std::vector<std::size_t>& expansion_begin = base.expansion_begin;
  std::vector<SerialBase::Term>& expansion = base.expansion;
  std::vector<PetscInt>& expansion_last = base.expansion_last;
  std::vector<std::vector<std::pair<global_dof_index, double>>>& incoming = base.incoming;
  constexpr PetscInt kExpanded = SerialBase::kExpanded;
  mapped.assign(n_dofs, SerialBase::kDirichlet);
  free_dofs.clear();
  for (global_dof_index i = 0; i < n_dofs; ++i) {
    if (c0.is_constrained(i)) continue;
    mapped[i] = static_cast<PetscInt>(free_dofs.size());
    free_dofs.push_back(i);
  }
  const std::size_t n_free = free_dofs.size();
  expansion_begin.assign(1, 0);
  expansion.clear();
  expansion_last.clear();
  incoming.assign(n_free, {});
  for (global_dof_index i = 0; i < n_dofs; ++i) {
    if (mapped[i] >= 0) continue;
    const auto* entries = c0.get_constraint_entries(i);
    if (!entries) continue;
    for (const auto& [j, weight] : *entries) {
      if (weight == 0.0) continue;
      if (mapped[j] < 0) throw_error("fem: constraint of dof ", i, " names constrained dof ", j);
      expansion.push_back({mapped[j], weight});
      incoming[mapped[j]].emplace_back(i, weight);
    }
    if (expansion.size() == expansion_begin.back()) continue;
    mapped[i] = kExpanded - static_cast<PetscInt>(expansion_begin.size() - 1);
    PetscInt last = 0;
    for (std::size_t t = expansion_begin.back(); t < expansion.size(); ++t) last = std::max(last, expansion[t].column);
    expansion_last.push_back(last);
    expansion_begin.push_back(expansion.size());
  }

  // Rows in chunks on threads, each into its own CSR piece; concatenated in row order.
  struct Piece {
    std::vector<PetscInt> row_length, columns;
    std::vector<double> values;
  };
  const std::size_t n_threads = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 8);
  const std::size_t chunk = std::max<std::size_t>(1, (n_free + n_threads - 1) / n_threads);
  std::vector<Piece> pieces((n_free + chunk - 1) / chunk);
  auto build_rows = [&](std::size_t first, std::size_t last) {
    if (first >= last) return;
    Piece& piece = pieces[first / chunk];
    piece.row_length.reserve(last - first);
    piece.columns.reserve(k_row_start[free_dofs[last - 1] + 1] - k_row_start[free_dofs[first]]);
    piece.values.reserve(piece.columns.capacity());
    std::vector<double> accumulator(n_free, 0.0);
    std::vector<char> touched(n_free, 0);
    std::vector<PetscInt> row_columns;
    for (std::size_t r = first; r < last; ++r) {
      const PetscInt diagonal = static_cast<PetscInt>(r);
      const global_dof_index j = free_dofs[r];
      // Most rows are K's row with its columns renumbered: copied as they come (K's rows hold
      // the diagonal first, then ascending columns, which the renumbering keeps in order).
      if (incoming[r].empty()) {
        const std::size_t mark = piece.columns.size();
        bool simple = true;
        PetscInt previous = -1;
        for (std::size_t e = k_row_start[j]; e < k_row_start[j + 1]; ++e) {
          const PetscInt c = mapped[k_columns[e]];
          if (c >= diagonal) {
            if (c <= previous) {
              simple = false;
              break;
            }
            piece.columns.push_back(c);
            piece.values.push_back(k_values[e]);
            previous = c;
          } else if (c <= kExpanded) {
            simple = false;
            break;
          }
        }
        if (simple) {
          piece.row_length.push_back(static_cast<PetscInt>(piece.columns.size() - mark));
          continue;
        }
        piece.columns.resize(mark);
        piece.values.resize(mark);
      }
      row_columns.clear();
      const auto add = [&](PetscInt c, double value) {
        if (c < diagonal) return;  // lower triangle
        if (!touched[c]) {
          touched[c] = 1;
          row_columns.push_back(c);
        }
        accumulator[c] += value;
      };
      const auto add_row = [&](global_dof_index row, double scale) {
        for (std::size_t e = k_row_start[row]; e < k_row_start[row + 1]; ++e) {
          const PetscInt c = mapped[k_columns[e]];
          const double k = scale * k_values[e];
          if (c >= 0) {
            add(c, k);
          } else if (c <= kExpanded) {
            const std::size_t x = static_cast<std::size_t>(kExpanded - c);
            if (expansion_last[x] < diagonal) continue;  // all in the lower triangle
            for (std::size_t t = expansion_begin[x]; t < expansion_begin[x + 1]; ++t) {
              add(expansion[t].column, k * expansion[t].weight);
            }
          }
        }
      };
      add_row(j, 1.0);
      for (const auto& [row, weight] : incoming[r]) add_row(row, weight);
      std::sort(row_columns.begin(), row_columns.end());
      piece.row_length.push_back(static_cast<PetscInt>(row_columns.size()));
      for (const PetscInt c : row_columns) {
        piece.columns.push_back(c);
        piece.values.push_back(accumulator[c]);
        accumulator[c] = 0.0;
        touched[c] = 0;
      }
    }
  };
  {
    std::vector<std::thread> workers;
    for (std::size_t t = 1; t * chunk < n_free; ++t) {
      workers.emplace_back(build_rows, t * chunk, std::min(n_free, (t + 1) * chunk));
    }
    build_rows(0, std::min(n_free, chunk));
    for (std::thread& worker : workers) worker.join();
  }
  std::vector<PetscInt>& row_start = base.row_start;
  std::vector<PetscInt>& columns = base.columns;
  std::vector<double>& values = base.values;
  row_start.assign(n_free + 1, 0);
  columns.clear();
  values.clear();
  std::size_t nonzeros = 0;
  for (const Piece& piece : pieces) nonzeros += piece.columns.size();
  columns.reserve(nonzeros);
  values.reserve(nonzeros);
  std::size_t next_row = 0;
  for (Piece& piece : pieces) {
    for (const PetscInt length : piece.row_length) {
      row_start[next_row + 1] = row_start[next_row] + length;
      ++next_row;
    }
    columns.insert(columns.end(), piece.columns.begin(), piece.columns.end());
    values.insert(values.end(), piece.values.begin(), piece.values.end());
    piece = Piece();
  }
  // The arrays stay alive (and unchanged) until the base is reset.
  MatCreateSeqSBAIJWithArrays(PETSC_COMM_SELF, 1, static_cast<PetscInt>(n_free), static_cast<PetscInt>(n_free),
                              row_start.data(), columns.data(), values.data(), &base.matrix);
  MatSetOption(base.matrix, MAT_SPD, PETSC_TRUE);
  base.cholesky = std::make_unique<CholeskySolve>(PETSC_COMM_SELF, base.matrix);
  base.valid = true;
}

std::vector<Linearization> ContactProblem::Impl::solve_with_base(
    const std::vector<dealii::AffineConstraints<double>>& constraints, Lap& lap) {
  const SerialBase& base = serial_base;
  const global_dof_index n_dofs = dof_handler.n_dofs();
  const std::size_t n_free = base.free_dofs.size();
  std::vector<Linearization> states;
  dealii::Vector<double> g(n_dofs), kg(n_dofs);
  std::vector<std::vector<double>> rhs(constraints.size(), std::vector<double>(n_free)), v;
  for (std::size_t k = 0; k < constraints.size(); ++k) base_rhs(constraints[k], g, kg, rhs[k]);
  linear_solves += static_cast<unsigned int>(constraints.size());
  if (!base_solve(rhs, v, lap)) linear_failure = true;
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    // u = P v + g: the free dofs from v, the constrained ones from their constraints.
    Linearization state;
    state.displacement.reinit(n_dofs);
    for (std::size_t r = 0; r < n_free; ++r) state.displacement(base.free_dofs[r]) = v[k][r];
    constraints[k].distribute(state.displacement);
    states.push_back(std::move(state));
  }
  times.solves += lap();
  add_internal_forces(states);
  times.internal_force += lap();
  return states;
}

void ContactProblem::Impl::base_rhs(const dealii::AffineConstraints<double>& constraint, dealii::Vector<double>& g,
                                    dealii::Vector<double>& kg, std::vector<double>& rhs) const {
  // g: the inhomogeneities on the constrained rows; the right-hand side is P^T (-K g).
  const SerialBase& base = serial_base;
  g = 0.0;
  for (global_dof_index i = 0; i < g.size(); ++i) {
    if (base.mapped[i] < 0 && constraint.is_inhomogeneously_constrained(i)) g(i) = constraint.get_inhomogeneity(i);
  }
  serial_stiffness.vmult(kg, g);
  for (std::size_t r = 0; r < base.free_dofs.size(); ++r) {
    double value = -kg(base.free_dofs[r]);
    for (const auto& [row, weight] : base.incoming[r]) value -= weight * kg(row);
    rhs[r] = value;
  }
}

bool ContactProblem::Impl::base_solve(const std::vector<std::vector<double>>& rhs,
                                      std::vector<std::vector<double>>& x, Lap& lap) {
  SerialBase& base = serial_base;
  const std::size_t n = base.free_dofs.size();
  x.assign(rhs.size(), std::vector<double>(n, 0.0));
  // Zero right-hand sides have the zero solution (and a block of them would ask MUMPS for
  // nothing); the others go in one block.
  std::vector<std::size_t> columns;
  for (std::size_t i = 0; i < rhs.size(); ++i) {
    if (std::any_of(rhs[i].begin(), rhs[i].end(), [](double value) { return value != 0.0; })) columns.push_back(i);
  }
  if (columns.empty()) return true;
  if (!base.cholesky->factorised()) {
    base.cholesky->factorise();
    ++factorisations;
    times.solver_setup += lap();
  }
  const std::size_t k = columns.size();
  linear_iterations += static_cast<unsigned int>(k);
  const PetscInt rows = static_cast<PetscInt>(n);
  if (k == 1) {
    Vec b, v;
    VecCreateSeqWithArray(PETSC_COMM_SELF, 1, rows, rhs[columns.front()].data(), &b);
    VecCreateSeqWithArray(PETSC_COMM_SELF, 1, rows, x[columns.front()].data(), &v);
    const bool ok = base.cholesky->solve(b, v, pcout);
    VecDestroy(&b);
    VecDestroy(&v);
    return ok;
  }
  std::vector<double> block(n * k), answers(n * k, 0.0);
  for (std::size_t c = 0; c < k; ++c) {
    std::copy(rhs[columns[c]].begin(), rhs[columns[c]].end(), block.begin() + static_cast<std::ptrdiff_t>(c * n));
  }
  if (!base.cholesky->solve_block(rows, static_cast<PetscInt>(k), block.data(), answers.data(), pcout)) return false;
  for (std::size_t c = 0; c < k; ++c) {
    const auto first = answers.begin() + static_cast<std::ptrdiff_t>(c * n);
    const auto last = first + static_cast<std::ptrdiff_t>(n);
    if (!std::all_of(first, last, [](double value) { return std::isfinite(value); })) return false;
    std::copy(first, last, x[columns[c]].begin());
  }
  return true;
}

bool ContactProblem::Impl::solve_low_rank(const std::vector<dealii::AffineConstraints<double>>& constraints,
                                          const std::vector<std::vector<dealii::Tensor<1, 3>>>& translation_sets,
                                          std::vector<Linearization>& states) {
  // The base solves  min 1/2 u^T K u  over u = P v + g  (its constraints). The current active set
  // releases some of the base's contact nodes (R) and adds others (N). With E the unit vectors
  // of the released slave dofs and C_N u = h_N the added constraints, the current problem is
  //   min over (v, delta) of 1/2 u^T K u,  u = P v + E delta + g,  subject to C_N u = h_N,
  // whose optimality system borders the factorised A = P^T K P:
  //   [ A    B ] [ v ]   [ -P^T K g       ]      B = [ P^T K E , P^T C_N^T ]
  //   [ B^T  D ] [ y ] = [ -E^T K g ; h_N - C_N g ],  D = [ E^T K E , E^T C_N^T ; C_N E , 0 ],
  // y = (delta, multipliers). With Z = A^-1 B (one solve per change) and S = D - B^T Z (dense,
  // small): y = S^-1 (d - B^T A^-1 b), v = A^-1 b - Z y. Exact, as elimination would be; falls
  // back (false) when the change is large, when a released dof is named by a kept constraint
  // (the base's closed constraints would have it substituted away), or when S is singular.
  constexpr std::size_t kMaxChanges = 32;  // ~ the solves one factorisation costs at default
  SerialBase& base = serial_base;
  if (base.active.size() != active.size() || hanging_constraints.n_constraints() > 0) return false;
  std::vector<std::size_t> released, added;
  for (std::size_t n = 0; n < active.size(); ++n) {
    if (base.active[n] && !active[n]) released.push_back(n);
    if (!base.active[n] && active[n]) added.push_back(n);
  }
  const std::size_t n_released = released.size(), m = released.size() + added.size();
  if (m > kMaxChanges) return false;
  const global_dof_index n_dofs = dof_handler.n_dofs();
  std::vector<char> is_released(n_dofs, 0);
  std::vector<global_dof_index> slave(m);
  for (std::size_t i = 0; i < m; ++i) {
    const NodeData& node = nodes[i < n_released ? released[i] : added[i - n_released]];
    slave[i] = node.dofs[node.constrained_component];
    if (i < n_released) is_released[slave[i]] = 1;
  }
  for (std::size_t n = 0; n < active.size(); ++n) {
    if (!base.active[n] || !active[n]) continue;
    const NodeData& node = nodes[n];
    for (unsigned int c = 0; c < 3; ++c) {
      if (c != node.constrained_component && is_released[node.dofs[c]]) return false;
      for (const auto& entry : node.master[c]) {
        if (is_released[entry.first]) return false;
      }
    }
  }
  // The base's constraints with the current translations.
  std::vector<dealii::AffineConstraints<double>> base_constraints;
  {
    std::vector<bool> current = active;
    active = base.active;
    for (const auto& translations : translation_sets) base_constraints.push_back(make_constraints(translations));
    active = std::move(current);
  }
  const std::size_t n_free = base.free_dofs.size();
  const auto scatter = [&](global_dof_index dof, double value, std::vector<double>& y) {
    const PetscInt c = base.mapped[dof];
    if (c >= 0) {
      y[c] += value;
    } else if (c <= SerialBase::kExpanded) {
      const std::size_t x = static_cast<std::size_t>(SerialBase::kExpanded - c);
      for (std::size_t t = base.expansion_begin[x]; t < base.expansion_begin[x + 1]; ++t) {
        y[base.expansion[t].column] += value * base.expansion[t].weight;
      }
    }
  };
  std::vector<std::vector<double>> border(m, std::vector<double>(n_free, 0.0));
  dealii::FullMatrix<double> schur(m, m);
  for (std::size_t i = 0; i < n_released; ++i) {
    for (std::size_t e = k_row_start[slave[i]]; e < k_row_start[slave[i] + 1]; ++e) {
      scatter(k_columns[e], k_values[e], border[i]);  // K is symmetric: row = column
    }
    for (std::size_t j = 0; j < n_released; ++j) schur(i, j) = serial_stiffness.el(slave[i], slave[j]);
  }
  // Added constraints as rows c_n = e_s - sum_c a_c e_c (their closed lines: the same for every
  // translation set, only the inhomogeneities differ).
  const dealii::AffineConstraints<double>& c0 = constraints.front();
  std::vector<std::vector<std::pair<global_dof_index, double>>> rows(added.size());
  for (std::size_t a = 0; a < added.size(); ++a) {
    const global_dof_index s = slave[n_released + a];
    if (!c0.is_constrained(s)) return false;
    rows[a].emplace_back(s, 1.0);
    if (const auto* entries = c0.get_constraint_entries(s)) {
      for (const auto& [dof, weight] : *entries) rows[a].emplace_back(dof, -weight);
    }
    for (const auto& [dof, value] : rows[a]) {
      scatter(dof, value, border[n_released + a]);
      for (std::size_t i = 0; i < n_released; ++i) {
        if (dof != slave[i]) continue;
        schur(i, n_released + a) += value;
        schur(n_released + a, i) += value;
      }
    }
  }
  Lap lap;
  // Every solve with the base's factor in one block: the m border columns (Z = A^-1 B) and the
  // right-hand sides of the translation sets.
  const std::size_t n_sets = constraints.size();
  dealii::Vector<double> g(n_dofs), kg(n_dofs);
  std::vector<std::vector<double>> block(border);
  std::vector<dealii::Vector<double>> d_sets(n_sets, dealii::Vector<double>(m));
  for (std::size_t k = 0; k < n_sets; ++k) {
    std::vector<double> rhs_values(n_free);
    base_rhs(base_constraints[k], g, kg, rhs_values);
    block.push_back(std::move(rhs_values));
    for (std::size_t i = 0; i < n_released; ++i) d_sets[k][i] = -kg(slave[i]);
    for (std::size_t a = 0; a < added.size(); ++a) {
      double row_g = 0.0;
      for (const auto& [dof, value] : rows[a]) row_g += value * g(dof);
      d_sets[k][n_released + a] = constraints[k].get_inhomogeneity(slave[n_released + a]) - row_g;
    }
  }
  std::vector<std::vector<double>> solved;
  linear_solves += static_cast<unsigned int>(block.size());
  if (!base_solve(block, solved, lap)) return false;
  block.clear();
  const std::vector<std::vector<double>>& z = solved;  // z[i] = A^-1 border[i], i < m
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = 0; j < m; ++j) {
      double product = 0.0;
      for (std::size_t r = 0; r < n_free; ++r) product += border[i][r] * z[j][r];
      schur(i, j) -= product;
    }
  }
  if (m > 0) schur.gauss_jordan();
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = 0; j < m; ++j) {
      if (!std::isfinite(schur(i, j))) return false;
    }
  }
  dealii::Vector<double> y(m);
  std::vector<Linearization> result;
  for (std::size_t k = 0; k < n_sets; ++k) {
    std::vector<double>& v_values = solved[m + k];
    dealii::Vector<double>& d = d_sets[k];
    for (std::size_t i = 0; i < m; ++i) {
      for (std::size_t r = 0; r < n_free; ++r) d[i] -= border[i][r] * v_values[r];
    }
    schur.vmult(y, d);
    for (std::size_t i = 0; i < m; ++i) {
      for (std::size_t r = 0; r < n_free; ++r) v_values[r] -= z[i][r] * y[i];
    }
    Linearization state;
    state.displacement.reinit(n_dofs);
    for (std::size_t r = 0; r < n_free; ++r) state.displacement(base.free_dofs[r]) = v_values[r];
    base_constraints[k].distribute(state.displacement);
    for (std::size_t i = 0; i < n_released; ++i) state.displacement(slave[i]) += y[i];
    // The added constraints hold to round-off unless S was (nearly) singular.
    const double scale = state.displacement.linfty_norm();
    for (std::size_t a = 0; a < added.size(); ++a) {
      double residual = -constraints[k].get_inhomogeneity(slave[n_released + a]);
      for (const auto& [dof, value] : rows[a]) residual += value * state.displacement(dof);
      if (!(std::abs(residual) <= 1e-9 * scale + 1e-300)) return false;
    }
    result.push_back(std::move(state));
  }
  ++low_rank_updates;
  states = std::move(result);
  return true;
}

std::vector<Linearization> ContactProblem::Impl::solve_reduced_direct(
    const std::vector<dealii::AffineConstraints<double>>& constraints) {
  // Direct solver: the unconstrained stiffness K is assembled once per run; each active set
  // only changes the constraints u = P v + g (v: the unconstrained dofs, P: identity on them
  // and the closed constraint weights on the constrained rows, g: the inhomogeneities), so the
  // reduced matrix P^T K P comes from one sparse triple product (PETSc MatPtAP) instead of a
  // condensing re-assembly, and is factorised once for all right-hand sides P^T (-K g).
  // Same equations as the condensed assembly of solve_linear, only without the constrained
  // rows that carry no information.
  Lap lap;
  const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);
  if (!stiffness_assembled) {
    dealii::DynamicSparsityPattern pattern(all_dofs);
    dealii::DoFTools::make_sparsity_pattern(dof_handler, pattern, dealii::AffineConstraints<double>(), true, rank);
    dealii::SparsityTools::distribute_sparsity_pattern(pattern, owned_dofs, comm, all_dofs);
    stiffness.reinit(owned_dofs, owned_dofs, pattern, comm);
    times.sparsity += lap();
    std::vector<global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      if (!cell->is_locally_owned()) continue;
      cell->get_dof_indices(dofs);
      stiffness.add(dofs, cell_matrices[cell->active_cell_index()]);
    }
    stiffness.compress(dealii::VectorOperation::add);
    stiffness_assembled = true;
    times.assembly += lap();
  }
  const dealii::AffineConstraints<double>& c0 = constraints.front();
  const global_dof_index n_dofs = dof_handler.n_dofs();
  // Reduced index of every free dof (every rank knows all constraints: the same numbering).
  constexpr global_dof_index kConstrained = std::numeric_limits<global_dof_index>::max();
  std::vector<global_dof_index> reduced(n_dofs, kConstrained);
  global_dof_index n_free = 0;
  for (global_dof_index i = 0; i < n_dofs; ++i) {
    if (!c0.is_constrained(i)) reduced[i] = n_free++;
  }
  // Owned rows of P are the owned dofs; owned columns the free ones among them (the owned range
  // is contiguous and ordered by rank, so the reduced owned range is too).
  if (!owned_dofs.is_contiguous()) {
    // The shared triangulation numbers each rank's dofs contiguously; the reduced numbering
    // below relies on it.
    throw_error("fem: direct solver needs contiguous locally owned dofs on every rank");
  }
  const global_dof_index first = owned_dofs.is_empty() ? 0 : owned_dofs.nth_index_in_set(0);
  const global_dof_index n_owned = owned_dofs.n_elements();
  global_dof_index first_free = kConstrained, n_owned_free = 0;
  for (global_dof_index i = first; i < first + n_owned; ++i) {
    if (reduced[i] == kConstrained) continue;
    if (first_free == kConstrained) first_free = reduced[i];
    ++n_owned_free;
  }
  if (first_free == kConstrained) first_free = 0;
  std::vector<PetscInt> diagonal_count(n_owned, 0), off_diagonal_count(n_owned, 0);
  auto is_owned_column = [&](global_dof_index column) {
    return column >= first_free && column < first_free + n_owned_free;
  };
  for (global_dof_index r = 0; r < n_owned; ++r) {
    const global_dof_index i = first + r;
    if (reduced[i] != kConstrained) {
      ++diagonal_count[r];
      continue;
    }
    if (const auto* entries = c0.get_constraint_entries(i)) {
      for (const auto& [j, weight] : *entries) {
        if (weight == 0.0) continue;
        (is_owned_column(reduced[j]) ? diagonal_count[r] : off_diagonal_count[r])++;
      }
    }
  }
  Mat prolongation;
  // MPIAIJ on one rank too: deal.II's K is MPIAIJ, and PtAP needs matching types.
  MatCreate(comm, &prolongation);
  MatSetSizes(prolongation, static_cast<PetscInt>(n_owned), static_cast<PetscInt>(n_owned_free),
              static_cast<PetscInt>(n_dofs), static_cast<PetscInt>(n_free));
  MatSetType(prolongation, MATMPIAIJ);
  MatMPIAIJSetPreallocation(prolongation, 0, diagonal_count.data(), 0, off_diagonal_count.data());
  for (global_dof_index r = 0; r < n_owned; ++r) {
    const global_dof_index i = first + r;
    const PetscInt row = static_cast<PetscInt>(i);
    if (reduced[i] != kConstrained) {
      MatSetValue(prolongation, row, static_cast<PetscInt>(reduced[i]), 1.0, ADD_VALUES);
      continue;
    }
    if (const auto* entries = c0.get_constraint_entries(i)) {
      for (const auto& [j, weight] : *entries) {
        if (weight == 0.0) continue;
        MatSetValue(prolongation, row, static_cast<PetscInt>(reduced[j]), weight, ADD_VALUES);
      }
    }
  }
  MatAssemblyBegin(prolongation, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(prolongation, MAT_FINAL_ASSEMBLY);
  Mat reduced_matrix;
  MatPtAP(stiffness.petsc_matrix(), prolongation, MAT_INITIAL_MATRIX, 2.0, &reduced_matrix);
  MatSetOption(reduced_matrix, MAT_SPD, PETSC_TRUE);
  times.assembly += lap();

  std::optional<CholeskySolve> cholesky(std::in_place, comm, reduced_matrix);

  std::vector<Linearization> states;
  for (const dealii::AffineConstraints<double>& constraint : constraints) {
    // g: the inhomogeneities on the constrained rows.
    dealii::PETScWrappers::MPI::Vector g(owned_dofs, comm), kg(owned_dofs, comm), u(owned_dofs, comm);
    for (global_dof_index i = first; i < first + n_owned; ++i) {
      if (reduced[i] == kConstrained && constraint.is_inhomogeneously_constrained(i)) {
        g(i) = constraint.get_inhomogeneity(i);
      }
    }
    g.compress(dealii::VectorOperation::insert);
    stiffness.vmult(kg, g);
    kg *= -1.0;
    Vec rhs, v;
    MatCreateVecs(reduced_matrix, &v, &rhs);
    MatMultTranspose(prolongation, kg, rhs);
    PetscReal rhs_norm = 0.0;
    VecNorm(rhs, NORM_2, &rhs_norm);
    ++linear_solves;
    if (rhs_norm > 0.0) {
      if (!cholesky->factorised()) {
        cholesky->factorise();
        ++factorisations;
        times.solver_setup += lap();
      }
      if (!cholesky->solve(rhs, v, pcout)) linear_failure = true;
      ++linear_iterations;
    } else {
      VecSet(v, 0.0);
    }
    MatMult(prolongation, v, u);  // u = P v
    u += g;
    VecDestroy(&rhs);
    VecDestroy(&v);
    Linearization state;
    state.displacement = dealii::Vector<double>(u);
    constraint.distribute(state.displacement);
    states.push_back(std::move(state));
  }
  cholesky.reset();
  MatDestroy(&reduced_matrix);
  MatDestroy(&prolongation);
  times.solves += lap();
  add_internal_forces(states);
  times.internal_force += lap();
  return states;
}

std::vector<dealii::Tensor<1, 3>> ContactProblem::Impl::transmitted_force(
    const ContactProblem& model, const Linearization& state) const {
  // Force each rigid body applies to the deformable bodies: through its contact surface and
  // through its bonded interfaces (the reaction at the bonded dofs).
  std::vector<dealii::Tensor<1, 3>> force(model.rigid_bodies.size());
  for (const BondedDof& bonded : bonded_dofs) {
    if (bonded.rigid_body >= 0) force[bonded.rigid_body][bonded.component] += state.internal_force[bonded.dof];
  }
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const NodeData& node = nodes[n];
    if (node.rigid_body < 0 || !active[n]) continue;
    const double normal_force = state.internal_force[node.dofs[node.constrained_component]] /
                                node.normal[node.constrained_component];
    force[node.rigid_body] += normal_force * node.normal;
  }
  return force;
}

void ContactProblem::Impl::evaluate_nodes(const Linearization& state,
                                          const std::vector<dealii::Tensor<1, 3>>& translations,
                                          std::vector<double>& force,
                                          std::vector<double>& gap) const {
  force.assign(nodes.size(), 0.0);
  gap.assign(nodes.size(), 0.0);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const NodeData& node = nodes[n];
    const unsigned int k = node.constrained_component;
    // The condensed equations of the free slave components make the nodal force parallel to
    // n, so its k-th component alone gives the normal force.
    force[n] = state.internal_force[node.dofs[k]] / node.normal[k];
    double g = node.initial_gap;
    for (unsigned int c = 0; c < 3; ++c) {
      double master = 0.0;
      if (node.rigid_body >= 0) {
        master = translations[node.rigid_body][c];
      } else {
        for (const auto& [dof, weight] : node.master[c]) master += weight * state.displacement[dof];
      }
      g += node.normal[c] * (state.displacement[node.dofs[c]] - master);
    }
    gap[n] = g;
  }
}

void ContactProblem::Impl::initial_active_set(const std::vector<dealii::Tensor<1, 3>>& translations,
                                              double gap_tolerance) {
  // With the last converged displacement at hand (the previous step of a motion: same mesh, same
  // dof numbering), the gap of every node at the new pose is predicted from it, the new pose's
  // contact geometry and the current translations: the nodes it closes start active. The
  // displacement is not rotated with the femur (a few degrees per step turn a 0.1 mm
  // displacement by a few micrometres), so this is a prediction, the active-set loop decides.
  // Without one, a node starts as it ended the last converged run (warm start) or, new, closed
  // when its geometric gap is.
  active.assign(nodes.size(), false);
  std::vector<double> predicted(nodes.size());
  const bool predict = options.warm_start_active_set && converged_solution.size() == dof_handler.n_dofs();
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const NodeData& node = nodes[n];
    predicted[n] = node.initial_gap;
    if (node.rigid_body >= 0) predicted[n] -= translations[node.rigid_body] * node.normal;
    if (predict) {
      for (unsigned int c = 0; c < 3; ++c) {
        double master = 0.0;
        for (const auto& [dof, weight] : node.master[c]) master += weight * converged_solution[dof];
        predicted[n] += node.normal[c] * (converged_solution[node.dofs[c]] - master);
      }
    }
    const auto it = options.warm_start_active_set ? converged_active.find({node.pair, node.dofs[0]})
                                                  : converged_active.end();
    const bool was_active = it != converged_active.end() && it->second;
    active[n] = (it != converged_active.end() && !predict) ? was_active
                                                           : was_active || predicted[n] <= gap_tolerance;
  }
  one_constraint_per_node(active, predicted);
}

void ContactProblem::Impl::one_constraint_per_node(std::vector<bool>& set, const std::vector<double>& gap,
                                                   const std::vector<bool>* current) const {
  // A slave node can belong to several pairs (the acetabular cartilage and the labrum meet both
  // the femoral cartilage and, past its edge, the bone of the head-neck). Two constraints on one
  // node, each eliminating one of its components in terms of the others, can form a cycle that
  // the constraint closure cannot resolve, and where the two masters meet (the cartilage edge
  // on the bone) their normals are nearly parallel, so the pair would be singular anyway. Each
  // node is held by the master it penetrates most (smallest gap; ties: the earlier pair), which
  // leaves the other master in front of it. With `current` (the active set just solved), a node
  // keeps the master that holds it now: where the two masters meet, the gaps of a held node to
  // them trade places from one solve to the next, and the plain rule would hand the node back and
  // forth forever (an active-set 2-cycle of the cam against the cartilage's edge and the labrum)
  // unless the other master is penetrated by more than options.holder_switch_mm beyond it.
  std::map<global_dof_index, std::size_t> holder;
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (!set[n]) continue;
    const auto [it, inserted] = holder.try_emplace(nodes[n].dofs[0], n);
    if (inserted) continue;
    const std::size_t other = it->second;
    // The current holder is kept unless the other master is penetrated more, by over
    // options.holder_switch_mm (so a converged node penetrates its other master by less).
    const double margin = options.holder_switch_mm;
    const bool keep_n = current != nullptr && (*current)[n] && !(*current)[other] && !(gap[other] < gap[n] - margin);
    const bool keep_other = current != nullptr && (*current)[other] && !(*current)[n] && !(gap[n] < gap[other] - margin);
    if (keep_n || (!keep_other && gap[n] < gap[other])) {
      set[other] = false;
      it->second = n;
    } else {
      set[n] = false;
    }
  }
}

namespace {

geometry::Vec3 to_vec3(const dealii::Point<3>& point) { return {point[0], point[1], point[2]}; }
dealii::Point<3> to_point(const geometry::Vec3& vector) { return {vector[0], vector[1], vector[2]}; }

// The ball-averaged peak, or NaN when a sample is not finite (a diverged solve): make_finite
// then zeroes it and reports the result as kNonFinite, like every other summary.
BallPeak ball_peak_or_nan(const std::vector<FieldSample>& samples, double radius_mm) {
  for (const FieldSample& sample : samples) {
    if (!std::isfinite(sample.value) || !(sample.weight > 0.0) || !std::isfinite(sample.weight) ||
        !sample.position_mm.allFinite()) {
      BallPeak peak;
      peak.value = std::numeric_limits<double>::quiet_NaN();
      return peak;
    }
  }
  return ball_averaged_peak(samples, radius_mm);
}

}  // namespace

bool ContactProblem::Impl::make_finite(ContactResult& result, dealii::Vector<double>& displacement) {
  bool finite = true;
  const auto fix = [&finite](double& value) {
    if (!std::isfinite(value)) {
      finite = false;
      value = 0.0;
    }
  };
  const auto fix_tensor = [&fix](dealii::Tensor<1, 3>& tensor) {
    for (unsigned int d = 0; d < 3; ++d) fix(tensor[d]);
  };
  for (double& value : displacement) fix(value);
  for (ContactNode& node : result.nodes) {
    fix(node.force_n);
    fix(node.pressure_mpa);
    fix(node.gap_mm);
  }
  for (auto& force : result.pair_force_n) fix_tensor(force);
  for (auto& translation : result.rigid_translation_mm) fix_tensor(translation);
  for (double* value : {&result.max_penetration_mm, &result.contact_area_mm2, &result.max_pressure_mpa,
                        &result.mean_pressure_mpa}) {
    fix(*value);
  }
  for (double& value : result.max_von_mises_mpa) fix(value);
  for (double& value : result.p95_von_mises_mpa) fix(value);
  for (double& value : result.ball_peak_von_mises_mpa) fix(value);
  fix(result.ball_peak_pressure_mpa);
  return finite;
}

void ContactProblem::Impl::place_bodies(const ContactProblem& model) {
  // Every run starts from the reference vertices (saved on the first run), so the rotations of
  // successive motion steps do not accumulate round-off.
  if (reference_vertices.empty()) reference_vertices = triangulation.get_vertices();
  std::map<dealii::types::material_id, int> rigid_of_material;
  for (const Body& body : model.bodies) {
    if (body.bonded_rigid_body >= static_cast<int>(model.rigid_bodies.size())) {
      throw_error("fem model: body ", body.name, " is bonded to rigid body ", body.bonded_rigid_body,
                  " which does not exist");
    }
    rigid_of_material[body.material_id] = body.bonded_rigid_body;
  }
  std::vector<bool> placed(reference_vertices.size(), false);
  for (const auto& cell : triangulation.cell_iterators()) {
    const auto it = rigid_of_material.find(cell->material_id());
    const int rigid = it == rigid_of_material.end() ? -1 : it->second;
    for (const unsigned int v : cell->vertex_indices()) {
      const unsigned int index = cell->vertex_index(v);
      if (placed[index]) continue;  // bodies that share a vertex: the first one places it
      placed[index] = true;
      const dealii::Point<3>& x = reference_vertices[index];
      if (rigid < 0) {
        cell->vertex(v) = x;
      } else {
        const RigidBody& body = model.rigid_bodies[rigid];
        cell->vertex(v) = body.rotation_center_mm + body.rotation * (x - body.rotation_center_mm);
      }
    }
  }
}

ContactResult ContactProblem::Impl::run(ContactProblem& model) {
  const auto start = std::chrono::steady_clock::now();
  times = PhaseTimes();
  Lap lap;
  place_bodies(model);
  setup_system(model);
  collect_fixed_dofs(model);
  compute_cell_matrices();
  stiffness_assembled = false;
  serial_base.reset();
  factorisations = 0;
  low_rank_updates = 0;
  times.setup = lap();
  collect_contact_nodes(model);
  times.contact_search = lap();
  linear_solves = 0;
  linear_iterations = 0;
  linear_failure = false;

  ContactResult result;
  result.n_cells = triangulation.n_global_active_cells();
  result.n_dofs = dof_handler.n_dofs();
  result.n_ranks = dealii::Utilities::MPI::n_mpi_processes(comm);

  std::vector<dealii::Tensor<1, 3>> translations;
  struct FreeDirection {
    unsigned int body;
    dealii::Tensor<1, 3> direction;
  };
  std::vector<FreeDirection> free_directions;
  for (unsigned int b = 0; b < model.rigid_bodies.size(); ++b) {
    const RigidBody& body = model.rigid_bodies[b];
    translations.push_back(body.translation_mm);
    if (!body.load_controlled) continue;
    for (dealii::Tensor<1, 3> direction : body.free_directions) {
      const double length = direction.norm();
      if (!(length > 0.0)) throw_error("fem model: rigid body ", body.name, ": zero free direction");
      free_directions.push_back({b, direction / length});
    }
  }

  // Gaps well below the solver's resolution of the displacement count as closed.
  const double gap_tolerance = 1e-10 * dealii::GridTools::diameter(triangulation);
  initial_active_set(translations, gap_tolerance);
  pcout << "fem: " << result.n_cells << " cells, " << result.n_dofs << " dofs, " << nodes.size()
        << " contact nodes, " << result.n_ranks << " rank(s)" << std::endl;

  Linearization state;
  std::vector<double> force, gap;
  std::set<std::vector<bool>> tried;  // active sets already solved in this run
  bool least_index_rule = false;
  result.status = ContactStatus::kActiveSetNotConverged;
  for (unsigned int iteration = 1; iteration <= options.max_active_set_iterations; ++iteration) {
    result.active_set_iterations = iteration;
    const unsigned int iterations_before = linear_iterations;
    if (free_directions.empty()) {
      state = std::move(solve_linear({translations}).front());
    } else {
      // Affine in the free translations for a fixed active set: probe each direction once.
      const std::size_t m = free_directions.size();
      std::vector<std::vector<dealii::Tensor<1, 3>>> translation_sets = {translations};
      for (std::size_t j = 0; j < m; ++j) {
        translation_sets.push_back(translations);
        translation_sets.back()[free_directions[j].body] += free_directions[j].direction;
      }
      std::vector<Linearization> probes = solve_linear(translation_sets);
      const Linearization base = std::move(probes.front());
      probes.erase(probes.begin());
      const auto base_force = transmitted_force(model, base);
      dealii::FullMatrix<double> sensitivity(m, m);
      dealii::Vector<double> mismatch(m);
      for (std::size_t j = 0; j < m; ++j) {
        const auto probe_force = transmitted_force(model, probes[j]);
        for (std::size_t i = 0; i < m; ++i) {
          const auto& row = free_directions[i];
          sensitivity(i, j) = (probe_force[row.body] - base_force[row.body]) * row.direction;
        }
      }
      for (std::size_t i = 0; i < m; ++i) {
        const auto& row = free_directions[i];
        mismatch[i] = (model.rigid_bodies[row.body].force_n - base_force[row.body]) * row.direction;
      }
      double scale = 0.0;
      for (std::size_t i = 0; i < m; ++i) scale = std::max(scale, std::abs(sensitivity(i, i)));
      if (!(scale > 0.0)) {
        result.status = ContactStatus::kNoContact;
        break;
      }
      sensitivity.gauss_jordan();
      dealii::Vector<double> step(m);
      sensitivity.vmult(step, mismatch);
      state = base;
      for (std::size_t j = 0; j < m; ++j) {
        translations[free_directions[j].body] += step[j] * free_directions[j].direction;
        state.displacement.add(step[j], probes[j].displacement);
        state.displacement.add(-step[j], base.displacement);
        for (std::size_t d = 0; d < state.internal_force.size(); ++d) {
          state.internal_force[d] += step[j] * (probes[j].internal_force[d] - base.internal_force[d]);
        }
      }
    }
    if (linear_failure) {
      result.status = ContactStatus::kLinearSolverFailed;
      break;
    }
    evaluate_nodes(state, translations, force, gap);
    std::vector<bool> next(nodes.size());
    std::size_t n_active = 0, changes = 0;
    // Load control starts from the touching nodes only, so the first balance overshoots the
    // translation and the plain rule would activate the whole geometric overlap, which then
    // shrinks one ring per iteration. For smooth profiles the elastic contact area is about
    // half the geometric overlap (Hertz: a^2 = R d against 2 R d), i.e. the nodes penetrating
    // by more than half the maximum: enter only those after the first iteration. Later
    // iterations use the exact rule, so the converged set is unaffected.
    double enter_threshold = gap_tolerance;
    if (iteration == 1 && !free_directions.empty()) {
      double deepest = 0.0;
      for (std::size_t n = 0; n < nodes.size(); ++n) deepest = std::max(deepest, -gap[n]);
      enter_threshold = std::max(gap_tolerance, 0.5 * deepest);
    }
    for (std::size_t n = 0; n < nodes.size(); ++n) next[n] = active[n] ? force[n] > 0.0 : gap[n] < -enter_threshold;
    one_constraint_per_node(next, gap, &active);
    tried.insert(active);
    if (!least_index_rule && tried.count(next) > 0) {
      // The plain rule returns to a set already solved: it would cycle. From here on, one change
      // per iteration, the lowest-numbered node first (Murty's least-index rule, which ends for
      // the positive definite systems of linear elastic contact).
      least_index_rule = true;
      pcout << "fem: active-set cycle detected at iteration " << iteration << "; one change per iteration from here"
            << std::endl;
    }
    if (least_index_rule) {
      std::vector<bool> single = active;
      for (std::size_t n = 0; n < nodes.size(); ++n) {
        if (next[n] != active[n]) {
          single[n] = next[n];
          break;
        }
      }
      one_constraint_per_node(single, gap, &active);
      next = std::move(single);
    }
    for (std::size_t n = 0; n < nodes.size(); ++n) {
      n_active += next[n];
      changes += next[n] != active[n];
    }
    pcout << "fem: active-set iteration " << iteration << ": " << n_active << " active, "
          << changes << " changed, " << linear_iterations - iterations_before
          << " CG iterations" << std::endl;
    if (changes == 0) {
      result.status = ContactStatus::kConverged;
      break;
    }
    active = std::move(next);
  }

  solution = state.displacement;
  serial_base.reset();  // K changes with the next run's pose; the factor's memory goes now
  result.factorisations = factorisations;
  result.low_rank_updates = low_rank_updates;
  result.linear_solves = linear_solves;
  result.linear_iterations = linear_iterations;
  result.rigid_translation_mm = translations;
  result.pair_force_n.assign(model.contact_pairs.size(), dealii::Tensor<1, 3>());
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const NodeData& node = nodes[n];
    ContactNode out;
    out.pair = node.pair;
    out.position_mm = node.position;
    out.normal = node.normal;
    out.area_mm2 = node.area;
    out.active = active[n];
    out.force_n = active[n] && n < force.size() ? force[n] : 0.0;  // no force: the loop stopped early
    out.pressure_mpa = out.force_n / node.area;
    out.gap_mm = gap.empty() ? node.initial_gap : gap[n];
    result.max_penetration_mm = std::max(result.max_penetration_mm, -out.gap_mm);
    result.pair_force_n[node.pair] += out.force_n * node.normal;
    result.nodes.push_back(out);
  }
  double total_force = 0.0;
  std::vector<FieldSample> pressure_samples;
  std::vector<unsigned int> pair_of_sample;
  for (const ContactNode& node : result.nodes) {
    if (!node.active) continue;
    result.contact_area_mm2 += node.area_mm2;
    total_force += node.force_n;
    if (node.pressure_mpa > result.max_pressure_mpa) {
      result.max_pressure_mpa = node.pressure_mpa;
      result.max_pressure_position_mm = node.position_mm;
      result.max_pressure_pair = static_cast<int>(node.pair);
    }
    pressure_samples.push_back({to_vec3(node.position_mm), node.pressure_mpa, node.area_mm2});
    pair_of_sample.push_back(node.pair);
  }
  if (result.contact_area_mm2 > 0.0) result.mean_pressure_mpa = total_force / result.contact_area_mm2;
  result.peak_average_radius_mm = options.peak_average_radius_mm;
  const BallPeak pressure_peak = ball_peak_or_nan(pressure_samples, options.peak_average_radius_mm);
  result.ball_peak_pressure_mpa = pressure_peak.value;
  result.ball_peak_pressure_position_mm = to_point(pressure_peak.position_mm);
  if (pressure_peak.found) result.ball_peak_pressure_pair = static_cast<int>(pair_of_sample[pressure_peak.sample]);
  lap();
  von_mises(model, result);
  times.stress = lap();
  // Every rank holds the same replicated numbers, so all ranks reach the same verdict.
  if (!make_finite(result, solution)) result.status = ContactStatus::kNonFinite;
  node_pressure.assign(nodes.size(), 0.0);
  node_gap.assign(nodes.size(), 0.0);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    node_pressure[n] = result.nodes[n].pressure_mpa;
    node_gap[n] = result.nodes[n].gap_mm;
  }
  for (float& value : cell_von_mises) {
    if (!std::isfinite(value)) value = 0.0f;
  }
  if (result.status == ContactStatus::kConverged) {
    converged_active.clear();
    for (std::size_t n = 0; n < nodes.size(); ++n) converged_active[{nodes[n].pair, nodes[n].dofs[0]}] = active[n];
    converged_solution = solution;
  }
  if (!options.vtu_file.empty()) output_results(options.vtu_file);
  result.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  pcout << "fem: " << to_string(result.status) << " after " << result.active_set_iterations
        << " active-set iterations, " << result.linear_solves << " linear solves, "
        << result.linear_iterations << " CG iterations, " << result.factorisations << " factorisations, "
        << result.low_rank_updates << " low-rank updates, " << result.wall_time_s << " s\n";
  pcout << "fem: time (s): setup " << times.setup << ", contact search " << times.contact_search
        << ", sparsity " << times.sparsity << ", assembly " << times.assembly << ", solver setup "
        << times.solver_setup << ", solves " << times.solves << ", internal force "
        << times.internal_force << ", stress " << times.stress << std::endl;
  return result;
}

void ContactProblem::Impl::von_mises(const ContactProblem& model, ContactResult& result) {
  // Every rank holds the whole solution: evaluate all cells, no communication needed.
  std::map<dealii::types::material_id, std::size_t> body_of_material;
  for (std::size_t b = 0; b < model.bodies.size(); ++b) body_of_material[model.bodies[b].material_id] = b;
  std::vector<std::vector<double>> values(model.bodies.size());
  std::vector<std::vector<FieldSample>> samples(model.bodies.size());  // for the ball peaks
  dealii::FEValues<3> fe_values(mapping, fe, dealii::QGauss<3>(fe.degree + 1),
                                dealii::update_gradients | dealii::update_quadrature_points |
                                    dealii::update_JxW_values);
  const dealii::FEValuesExtractors::Vector displacement(0);
  std::vector<dealii::SymmetricTensor<2, 3>> strains(fe_values.n_quadrature_points);
  cell_von_mises.reinit(triangulation.n_active_cells());
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    fe_values.reinit(cell);
    fe_values[displacement].get_function_symmetric_gradients(solution, strains);
    const auto [lambda, mu] = lame_by_material.at(cell->material_id());
    const std::size_t body = body_of_material.at(cell->material_id());
    auto& out = values[body];
    for (unsigned int q = 0; q < strains.size(); ++q) {
      const dealii::SymmetricTensor<2, 3>& strain = strains[q];
      const dealii::SymmetricTensor<2, 3> stress =
          lambda * dealii::trace(strain) * dealii::unit_symmetric_tensor<3>() + 2.0 * mu * strain;
      const dealii::SymmetricTensor<2, 3> deviator = dealii::deviator(stress);
      out.push_back(std::sqrt(1.5 * (deviator * deviator)));
      samples[body].push_back({to_vec3(fe_values.quadrature_point(q)), out.back(), fe_values.JxW(q)});
      float& cell_max = cell_von_mises[cell->active_cell_index()];
      cell_max = std::max(cell_max, static_cast<float>(out.back()));
    }
  }
  result.max_von_mises_mpa.assign(model.bodies.size(), 0.0);
  result.p95_von_mises_mpa.assign(model.bodies.size(), 0.0);
  result.ball_peak_von_mises_mpa.assign(model.bodies.size(), 0.0);
  result.ball_peak_von_mises_position_mm.assign(model.bodies.size(), dealii::Point<3>());
  for (std::size_t b = 0; b < values.size(); ++b) {
    // Per body: a ball at a tissue boundary averages that tissue only.
    const BallPeak peak = ball_peak_or_nan(samples[b], options.peak_average_radius_mm);
    result.ball_peak_von_mises_mpa[b] = peak.value;
    result.ball_peak_von_mises_position_mm[b] = to_point(peak.position_mm);
    auto& v = values[b];
    if (v.empty()) continue;
    std::sort(v.begin(), v.end());
    result.max_von_mises_mpa[b] = v.back();
    // Nearest-rank 95th percentile.
    const std::size_t rank = static_cast<std::size_t>(std::ceil(0.95 * v.size()));
    result.p95_von_mises_mpa[b] = v[std::max<std::size_t>(rank, 1) - 1];
  }
}

void ContactProblem::Impl::output_results(const std::string& file) const {
  dealii::DataOut<3> data_out;
  data_out.attach_dof_handler(dof_handler);
  const std::vector<std::string> names(3, "displacement_mm");
  const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation>
      interpretation(3, dealii::DataComponentInterpretation::component_is_part_of_vector);
  data_out.add_data_vector(solution, names, dealii::DataOut<3>::type_dof_data, interpretation);
  dealii::Vector<float> material(triangulation.n_active_cells());
  for (const auto& cell : triangulation.active_cell_iterators()) {
    material[cell->active_cell_index()] = static_cast<float>(cell->material_id());
  }
  data_out.add_data_vector(material, "material_id");
  if (cell_von_mises.size() == triangulation.n_active_cells()) {
    data_out.add_data_vector(cell_von_mises, "von_mises_cell_max_mpa");
  }
  // Contact quantities live on the slave nodes: carried as the three scalar components of one
  // nodal vector (x: pressure, y: gap, z: active), zero away from the contact surfaces. The
  // patches are of the element degree, so their vertices are the nodes and show exact values.
  dealii::Vector<double> contact(dof_handler.n_dofs());
  for (std::size_t n = 0; n < nodes.size() && n < node_pressure.size(); ++n) {
    contact[nodes[n].dofs[0]] = node_pressure[n];
    contact[nodes[n].dofs[1]] = node_gap[n];
    contact[nodes[n].dofs[2]] = active[n] ? 1.0 : 0.0;
  }
  const std::vector<std::string> contact_names{"contact_pressure_mpa", "contact_gap_mm", "contact_active"};
  const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> scalars(
      3, dealii::DataComponentInterpretation::component_is_scalar);
  data_out.add_data_vector(contact, contact_names, dealii::DataOut<3>::type_dof_data, scalars);
  data_out.build_patches(mapping, fe.degree);
  data_out.write_vtu_in_parallel(file, comm);
}

dealii::Tensor<1, 3> ContactProblem::Impl::displacement_at(const dealii::Point<3>& point) const {
  dealii::Vector<double> value(3);
  dealii::VectorTools::point_value(mapping, dof_handler, solution, point, value);
  dealii::Tensor<1, 3> result;
  for (unsigned int d = 0; d < 3; ++d) result[d] = value[d];
  return result;
}

ContactProblem::ContactProblem(MPI_Comm communicator, ContactOptions options) {
  ensure_mpi_initialized();
  impl_ = std::make_unique<Impl>(communicator, std::move(options));
}

ContactProblem::~ContactProblem() = default;

dealii::parallel::shared::Triangulation<3>& ContactProblem::triangulation() {
  return impl_->triangulation;
}

ContactResult ContactProblem::run() {
  // Checked before the solve, not when the peaks are taken after it.
  const double radius_mm = impl_->options.peak_average_radius_mm;
  if (!std::isfinite(radius_mm) || radius_mm <= 0.0) {
    throw_error("fem model: peak_average_radius_mm must be finite and > 0, got ", radius_mm);
  }
  return impl_->run(*this);
}

dealii::Tensor<1, 3> ContactProblem::displacement_at(const dealii::Point<3>& point_mm) const {
  return impl_->displacement_at(point_mm);
}

MPI_Comm ContactProblem::communicator() const { return impl_->comm; }

ContactOptions& ContactProblem::options() { return impl_->options; }

void ContactProblem::write_vtu(const std::string& file) const { impl_->output_results(file); }

}  // namespace hipfai::fem
