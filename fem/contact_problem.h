// hipfai — frictionless small-strain contact between linear elastic bodies (deal.II + PETSc).
//
// The finite-element ground truth that replaces the thesis's ABAQUS models (Arbabi 2009,
// §4.3.2.3 and §4.5.3.3). All deformable bodies live in one triangulation, told apart by their
// material id; bones are rigid and enter as Dirichlet data on bonded interfaces, or as analytic
// rigid surfaces that deformable bodies touch.
//
// Contact is node-to-surface: every node of a slave surface is projected onto the closest point
// of its master surface (a deformable boundary on a non-matching mesh, or a rigid surface), and
// the gap is measured along the master normal there, g = (x_s + u_s - x_m - u_m) . n >= 0.
// Active nodes carry the exact constraint g = 0, written as an affine constraint on the slave
// component with the largest normal component (so the condensed system stays symmetric positive
// definite and is solved by PETSc CG + BoomerAMG). The active set is found by the primal-dual
// active set method (a semismooth Newton method for this linear complementarity problem): a node
// leaves the set when its contact force is tensile and enters it when it penetrates.
//
// Load control: a rigid body may have free translation directions with a prescribed force. For a
// fixed active set the displacement is affine in the translation, so the translation that
// balances the force is found exactly from 1 + (number of free directions) linear solves — the
// mechanism the hip model needs (femur free to translate under the joint reaction force).
//
// Units: mm, N, MPa. Runs on any number of MPI ranks (parallel::shared::Triangulation: every rank
// keeps the whole mesh, which makes the closest-point search on non-matching meshes local).
#pragma once

#include "core/literature.h"
#include "fem/elastic_material.h"
#include "fem/rigid_surface.h"

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>
#include <deal.II/distributed/shared_tria.h>

#include <mpi.h>

#include <functional>
#include <memory>
#include <limits>
#include <string>
#include <vector>

namespace hipfai::fem {

struct Body {
  std::string name;
  dealii::types::material_id material_id = 0;
  ElasticMaterial material;
  // Rigid body this body is bonded to (-1: none). Its cells follow that body's rotation: the
  // mesh is rotated rigidly before the solve, so a large rotation (the femur's flexion) costs no
  // strain in the small-strain model, and the contact search runs in the rotated configuration.
  int bonded_rigid_body = -1;
};

// A rigid body: its translation is either prescribed (translation_mm) or, when load_controlled,
// unknown along free_directions so that the contact force it transmits equals force_n.
// Its motion is x -> c + R (x - c) + t: the rotation R about c (the hip joint centre) is always
// prescribed (identity by default), t is prescribed or solved for.
struct RigidBody {
  std::string name;
  std::shared_ptr<const RigidSurface> surface;  // null for a bone that is only bonded
  dealii::Tensor<1, 3> translation_mm;          // prescribed, or the starting guess
  bool load_controlled = false;
  std::vector<dealii::Tensor<1, 3>> free_directions;  // unit vectors
  dealii::Tensor<1, 3> force_n;  // force the body applies to the deformable bodies
  dealii::Tensor<2, 3> rotation = dealii::unit_symmetric_tensor<3>();  // R, proper orthogonal
  dealii::Point<3> rotation_center_mm;                                 // c
};

// Boundary bonded to bone: u = translation of rigid_body (if >= 0) + extra_displacement_mm(x).
struct BondedBoundary {
  dealii::types::boundary_id boundary_id = 0;
  int rigid_body = -1;
  std::function<dealii::Tensor<1, 3>(const dealii::Point<3>&)> extra_displacement_mm;
};

// Frictionless symmetry plane (or frictionless wall) normal to a coordinate axis: u[axis] = 0.
struct SymmetryBoundary {
  dealii::types::boundary_id boundary_id = 0;
  unsigned int axis = 0;
};

// Slave surface (a boundary id) against either a rigid body's surface or a deformable boundary.
struct ContactPair {
  dealii::types::boundary_id slave_boundary_id = 0;
  int master_rigid_body = -1;  // >= 0: rigid master
  dealii::types::boundary_id master_boundary_id = 0;  // used when master_rigid_body < 0
};

// kCgAmg: CG + smoothed-aggregation AMG (GAMG with rigid-body modes), scales to large meshes
// and many ranks. kDirect: sparse Cholesky by MUMPS, factorised once per active set and reused
// for its 1 + (free directions) right-hand sides; faster on small problems (a few 10^4 dofs),
// memory grows faster than linearly.
enum class LinearSolver { kCgAmg, kDirect };
const char* to_string(LinearSolver solver);

struct ContactOptions {
  unsigned int fe_degree = 2;       // Q2: no volumetric locking at nu = 0.45
  unsigned int mapping_degree = 2;  // curved boundaries follow their manifolds
  LinearSolver linear_solver = LinearSolver::kCgAmg;
  double linear_relative_tolerance = 1e-12;
  unsigned int max_linear_iterations = 10000;
  unsigned int max_active_set_iterations = 40;
  // A slave node on two masters (where they meet) keeps the one holding it until the other is
  // penetrated more by this much (mm). Infinite (the default): a held node never changes master
  // within a solve, which ends the 2-cycles of such corner nodes (the cam against the femoral
  // cartilage's edge and the labrum); the node may then penetrate its other master (reported in
  // ContactResult::max_penetration_mm; the hip tests bound it separately from single-master nodes).
  // Smaller values (1e-3 or 1e-2 mm measured on CE 40 / alpha 80) let such cycles return.
  double holder_switch_mm = std::numeric_limits<double>::infinity();
  // Start the active set from the last converged solve's (nodes matched by their dofs; nodes
  // new to the contact search are predicted from the geometric overlap). A motion's step is
  // close to the previous one, so this saves most active-set iterations; the converged set
  // does not depend on the start.
  bool warm_start_active_set = true;
  // Direct solver on one rank: an active set that differs from the factorised one in a few
  // nodes is solved with that factor and a bordered (low-rank) correction, exactly, instead of
  // a new factorisation. Off: every active set is factorised anew (for comparison).
  bool low_rank_updates = true;
  std::string vtu_file;  // written after the solve when not empty
  bool verbose = false;  // per-iteration statistics on rank 0
  // Radius (mm) of the balls of the mesh-objective peaks (fem/peak_measures.h; ContactResult::
  // ball_peak_*): 1 mm, half the 2 mm cartilage thickness (core/literature.h). A ball that small
  // still resolves the stress gradient through the layer (one of 2 mm would average the loaded
  // surface with the bone interface), yet it is a fixed physical size, so the average is a
  // property of the field and not of the mesh, and at the hip model's levels it spans several
  // Gauss points through the thickness.
  double peak_average_radius_mm = 0.5 * literature::kAcetabularCartilageThicknessMm;
};

// kNonFinite: a NaN or infinity appeared in the solution or a summary (the numbers of such a
// result are replaced by 0, so no NaN ever leaves the solver).
enum class ContactStatus { kConverged, kActiveSetNotConverged, kLinearSolverFailed, kNoContact, kNonFinite };
const char* to_string(ContactStatus status);

struct ContactNode {
  unsigned int pair = 0;
  dealii::Point<3> position_mm;   // reference position
  dealii::Tensor<1, 3> normal;    // master normal at the closest point (into the slave)
  double area_mm2 = 0.0;          // integral of the node's shape function over the slave surface
  double force_n = 0.0;           // normal contact force (compressive > 0)
  double pressure_mpa = 0.0;      // force / area
  double gap_mm = 0.0;            // after the solve; negative = penetration
  bool active = false;
};

struct ContactResult {
  ContactStatus status = ContactStatus::kNoContact;
  unsigned int n_cells = 0;
  unsigned long n_dofs = 0;
  unsigned int n_ranks = 1;
  unsigned int active_set_iterations = 0;
  unsigned int linear_solves = 0;
  unsigned int linear_iterations = 0;
  unsigned int factorisations = 0;    // direct solver: Cholesky factorisations
  unsigned int low_rank_updates = 0;  // direct solver: active sets solved by a bordered correction
  double wall_time_s = 0.0;
  // Set by run_motion: solves the step was split into (1: none) and failed attempts that were
  // cut back; the counters and wall time above then sum over all attempts.
  unsigned int sub_steps = 1;
  unsigned int cutbacks = 0;
  std::vector<ContactNode> nodes;
  std::vector<dealii::Tensor<1, 3>> pair_force_n;  // force on the slave bodies, per pair
  std::vector<dealii::Tensor<1, 3>> rigid_translation_mm;
  double max_penetration_mm = 0.0;
  // Summaries over the active contact nodes (all pairs).
  double contact_area_mm2 = 0.0;
  double max_pressure_mpa = 0.0;
  double mean_pressure_mpa = 0.0;  // total normal force / contact area
  // Von Mises stress per body (index into ContactProblem::bodies), over the Gauss points.
  std::vector<double> max_von_mises_mpa;
  std::vector<double> p95_von_mises_mpa;
  // Mesh-objective peaks (fem/peak_measures.h): the largest mean over a ball of radius
  // ContactOptions::peak_average_radius_mm, and the ball's centre (hip frame, the step's pose,
  // undeformed). Von Mises per body, JxW-weighted over the body's Gauss points; pressure
  // area-weighted over the active slave nodes of all pairs (= contact force / contact area
  // inside the ball). 0 (and the origin) where there are no samples.
  double peak_average_radius_mm = 0.0;  // the radius used
  std::vector<double> ball_peak_von_mises_mpa;
  std::vector<dealii::Point<3>> ball_peak_von_mises_position_mm;
  double ball_peak_pressure_mpa = 0.0;
  dealii::Point<3> ball_peak_pressure_position_mm;
  // The node of max_pressure_mpa (same frame) and the contact pair of that node and of the ball
  // peak's centre (index into ContactProblem::contact_pairs; -1: no active node).
  dealii::Point<3> max_pressure_position_mm;
  int max_pressure_pair = -1;
  int ball_peak_pressure_pair = -1;
};

class ContactProblem {
 public:
  ContactProblem(MPI_Comm communicator, ContactOptions options);
  ~ContactProblem();
  ContactProblem(const ContactProblem&) = delete;
  ContactProblem& operator=(const ContactProblem&) = delete;

  // Fill the mesh (identically on every rank), set material and boundary ids, attach manifolds.
  dealii::parallel::shared::Triangulation<3>& triangulation();
  MPI_Comm communicator() const;
  // The solver options, to change between runs (iteration limits, solver, warm start);
  // fe_degree and mapping_degree are fixed at construction.
  ContactOptions& options();

  std::vector<Body> bodies;
  std::vector<RigidBody> rigid_bodies;
  std::vector<BondedBoundary> bonded_boundaries;
  std::vector<SymmetryBoundary> symmetry_boundaries;
  std::vector<ContactPair> contact_pairs;

  // Solves the contact problem; a status other than kConverged is a result, not an exception.
  // Throws hipfai::Error for an inconsistent model (unknown material id, empty contact surface).
  ContactResult run();

  // Displacement at a point of the reference configuration (after run()), for checks.
  dealii::Tensor<1, 3> displacement_at(const dealii::Point<3>& point_mm) const;

  // Fields of the last run() to one .vtu file (collective: every rank calls it): displacement
  // (mm, on the rotated configuration), material id, von Mises (MPa, largest over each cell's
  // Gauss points) and, at the contact slave nodes, contact pressure (MPa), gap (mm) and the
  // active flag (0 elsewhere).
  void write_vtu(const std::string& file) const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// Initializes MPI and PETSc once per process (no-op when already done); safe to call repeatedly.
void ensure_mpi_initialized();

}  // namespace hipfai::fem
