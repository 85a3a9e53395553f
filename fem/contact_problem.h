// hipfai — frictionless small-strain contact between linear elastic bodies (deal.II + PETSc).
//
// The finite-element ground truth that replaces the thesis's ABAQUS models (Arbabi 2009,
// §4.3.2.3 and §4.5.3.3). All deformable bodies live in one triangulation, told apart by their
// material id; bones are rigid and enter as Dirichlet data on bonded interfaces, or as analytic
// or meshed rigid surfaces that deformable bodies touch. The model is one value type,
// fem::ContactModel (fem/contact_model.h).
//
// ContactProblem::run() is a sequence of stages, each in its own unit:
//   setup          fem/elastic_system.h      bodies placed in their pose, dofs, cell stiffness
//                  fem/contact_constraints.h hanging, bonded and symmetry dofs
//   contact search fem/mortar_coupling.h     slave nodes; rigid masters by closest point,
//                                            deformable masters by segment-based mortar weights
//   active sets    fem/active_set_strategy.h primal-dual active set method (semismooth Newton):
//                                            a node leaves the set when its force is tensile and
//                                            enters it when it penetrates; active nodes carry the
//                                            exact constraint g = 0 as an affine constraint
//                  fem/load_control.h        the translations of load-controlled rigid bodies
//                                            that balance their forces, exactly from
//                                            1 + (free directions) solves per active set
//                  fem/linear_solver.h       CG + GAMG, or MUMPS Cholesky (with bordered low-rank
//                                            updates between active sets on one rank)
//   results        fem/contact_summary.h     forces, pressures, von Mises, ball-averaged peaks
//                  fem/contact_output.h      VTU
// Each stage is timed by a deal.II TimerOutput section (printed with ContactOptions::verbose).
//
// Units: mm, N, MPa. Runs on any number of MPI ranks (parallel::shared::Triangulation: every rank
// keeps the whole mesh, which makes the contact search on non-matching meshes local). The direct
// and CG solvers distribute the system over the ranks; the substructured solver deals its
// compliance-column solves to them and solves the rest on rank 0 (fem/rank_team.h), so every
// rank returns the numbers of a one-rank run.
#pragma once

#include "core/literature.h"
#include "fem/contact_model.h"
#include "fem/contact_result.h"
#include "fem/linear_solver.h"

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/shared_tria.h>

#include <mpi.h>

#include <array>
#include <limits>
#include <memory>
#include <string>

namespace hipfai::fem {

// Which ranks of a substructured run on several ranks solve compliance columns (fem/rank_team.h).
enum class TeamColumns {
  // Rank 0 solves them; another rank takes blocks while it has a core to itself and only as
  // many as finish sooner than rank 0 alone, its own factorisation counted (fem/column_deal.h).
  kSpareCores,
  // Every rank takes an equal share of every set of columns (the helpers factorise when first
  // given one, as with kSpareCores).
  kEveryRank,
};
inline constexpr std::array<TeamColumns, 2> kTeamColumns{TeamColumns::kSpareCores,
                                                         TeamColumns::kEveryRank};
// "spare-cores", "every-rank".
const char* to_string(TeamColumns team_columns);

struct ContactOptions {
  unsigned int fe_degree = 2;                         // Q2: no volumetric locking at nu = 0.45
  unsigned int mapping_degree = 2;                    // curved boundaries follow their manifolds
  LinearSolver linear_solver = LinearSolver::kCgAmg;  // see fem/linear_solver.h
  double linear_relative_tolerance = 1e-12;           // CG: relative residual
  unsigned int max_linear_iterations = 10000;         // CG iterations per solve
  unsigned int max_active_set_iterations = 40;        // then kActiveSetNotConverged
  // A slave node on two masters (where they meet) keeps the one holding it until the other is
  // penetrated more by this much (mm). Infinite (the default): a held node never changes master
  // within a solve, which ends the 2-cycles of such corner nodes (the cam against the femoral
  // cartilage's edge and the labrum); the node may then penetrate its other master (reported in
  // ContactResult::peaks.max_penetration_mm; the hip tests bound it separately from single-master
  // nodes).
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
  // Contact search: skip master faces clear of a slave face's tangent-plane extent
  // (MortarSegmentOptions::tangent_plane_cull); off only to check that it changes nothing.
  bool tangent_plane_cull = true;
  // The substructured solver on several ranks: which ranks solve the compliance columns. Either
  // way the numbers are those of one rank, bit for bit; only the time differs.
  TeamColumns team_columns = TeamColumns::kSpareCores;
  std::string vtu_file;  // written after the solve when not empty
  bool verbose = false;  // per-iteration statistics and the stage timings on rank 0
  // Radius (mm) of the balls of the mesh-objective peaks (fem/peak_measures.h; ContactPeaks::
  // ball_peak_*): 1 mm, half the 2 mm cartilage thickness (core/literature.h). A ball that small
  // still resolves the stress gradient through the layer (one of 2 mm would average the loaded
  // surface with the bone interface), yet it is a fixed physical size, so the average is a
  // property of the field and not of the mesh, and at the hip model's levels it spans several
  // Gauss points through the thickness.
  double peak_average_radius_mm = 0.5 * literature::kAcetabularCartilageThicknessMm;
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
  // fe_degree, mapping_degree and whether the solver is the substructured one are fixed at
  // construction (run() throws hipfai::Error when the latter changed).
  ContactOptions& options();
  // The model, read by every run (a motion changes its rigid bodies between runs).
  ContactModel& model();
  const ContactModel& model() const;

  // Solves the contact problem; a status other than kConverged is a result, not an exception.
  // Throws hipfai::Error for an inconsistent model (unknown material id, empty contact surface,
  // a reference to a rigid body that does not exist) or a peak radius that is not finite and > 0.
  ContactResult run();
  // A hint for the next run(): the models of the runs that will most likely follow it, in order
  // (a motion's next poses). From the next run() on, their contact is searched while the runs
  // solve their own (fem/contact_search_ahead.h); a run uses such a search only if its model and
  // mesh are exactly those searched, and searches anew otherwise, so the hint changes no answer.
  // The searches take a thread of their own: ignored when the process has one thread per rank.
  void expect_next(std::vector<ContactModel> upcoming);

  // Displacement at a point of the reference configuration (after run()), for checks. On a
  // substructured run over several ranks only rank 0 holds it (hipfai::Error on the others).
  dealii::Tensor<1, 3> displacement_at(const dealii::Point<3>& point_mm) const;

  // Fields of the last run() to one .vtu file (every rank calls it: collective over the ranks
  // that share the mesh; a substructured run's rank 0 writes it alone); see fem/contact_output.h.
  void write_vtu(const std::string& file) const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// Initializes MPI and PETSc once per process (no-op when already done); safe to call repeatedly.
// The FE's threads are not limited by it: every hardware thread (or DEAL_II_NUM_THREADS), shared
// among the ranks on the machine (fem/thread_chunks.h).
void ensure_mpi_initialized();

// Limits the threads the FE stages of this process use (cell matrices, contact search, the
// condensed contact problem) to `threads` (0: every hardware thread), after initializing MPI. The
// results do not depend on it: the threaded stages write per-item slots.
void limit_threads(unsigned int threads);

}  // namespace hipfai::fem
