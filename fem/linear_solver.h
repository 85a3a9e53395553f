// hipfai — the linear solves of the contact problem, behind one interface.
//
// For a fixed active set the contact problem is linear: minimise 1/2 u^T K u over the
// displacements that satisfy the closed constraints u = P v + g (fem/contact_constraints.h). The
// constraints of one active set differ between its rigid translations only in g, so a solver is
// given all translation sets of an active set at once and sets up its matrix once for them.
//
//   kCgAmg   CgAmgLinearSolver: the condensed system assembled through the constraints, CG +
//            GAMG (fem/petsc_solvers.h); scales to large meshes and many ranks.
//   kDirect  on several ranks DistributedDirectSolver (P^T K P by PETSc's MatPtAP, MUMPS
//            Cholesky); on one rank SerialDirectSolver (P^T K P row by row, MUMPS Cholesky, and
//            active sets near the factorised one by a bordered low-rank correction).
//   kSubstructured  not a linear solver of this interface: each body factorised once in its own
//            frame and the contact problem condensed onto the active constraints and the free
//            translations (fem/body_compliance.h, fem/condensed_contact.h; one rank).
#pragma once

#include "fem/contact_constraints.h"
#include "fem/elastic_system.h"
#include "fem/mortar_coupling.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <vector>

namespace hipfai::fem {

// kCgAmg: CG + smoothed-aggregation AMG (GAMG with rigid-body modes), scales to large meshes
// and many ranks. kDirect: sparse Cholesky by MUMPS, factorised once per active set and reused
// for its 1 + (free directions) right-hand sides; faster on small problems (a few 10^4 dofs),
// memory grows faster than linearly. kSubstructured: each body's stiffness factorised once per
// model (not per active set or step), the contact problem solved on the condensed contact
// interface; the same discrete problem as kDirect, the fastest path for a motion.
enum class LinearSolver { kCgAmg, kDirect, kSubstructured };
const char* to_string(LinearSolver solver);

// Settings a run reads (ContactOptions has them).
struct LinearSolverSettings {
  double relative_tolerance = 1e-12;    // CG: relative residual
  unsigned int max_iterations = 10000;  // CG iterations per solve
  bool low_rank_updates = true;         // one-rank direct solver: bordered corrections allowed
};

// Counts of one run.
struct LinearSolverStatistics {
  unsigned int linear_solves = 0;  // right-hand sides solved
  unsigned int linear_iterations =
      0;                            // CG iterations; direct: right-hand sides with a nonzero solve
  unsigned int factorisations = 0;  // direct solver: Cholesky factorisations
  unsigned int low_rank_updates = 0;  // direct solver: active sets solved by a bordered correction
  bool failed = false;                // a solve failed (CG not converged, factorisation failed)
};

// The systems of one active set: constraints[k] are the closed constraints for
// translation_sets[k]; nodes and active are the contact nodes and the active set they express.
struct ActiveSetSystems {
  const std::vector<dealii::AffineConstraints<double>>& constraints;  // one per translation set
  const std::vector<std::vector<dealii::Tensor<1, 3>>>&
      translation_sets;                 // one translation per rigid body
  const std::vector<SlaveNode>& nodes;  // the run's contact nodes
  const std::vector<bool>& active;      // per node
};

class ContactLinearSolver {
 public:
  virtual ~ContactLinearSolver() = default;
  // A new run: the dofs and cell matrices may have changed; statistics start at zero.
  virtual void begin_run(const LinearSolverSettings& settings);
  // The run is over: per-run memory (factors) can go.
  virtual void end_run() {}
  // The displacement of every constraint set (constraints distributed), in their order.
  virtual std::vector<dealii::Vector<double>> solve(const ActiveSetSystems& systems) = 0;
  const LinearSolverStatistics& statistics() const { return statistics_; }

 protected:
  LinearSolverSettings settings_;
  LinearSolverStatistics statistics_;
};

// The solver of `kind` for the system's communicator (see above). The solver keeps references to
// all arguments; it times itself in the sections "assembly", "solver setup" (preconditioner,
// factorisation) and "linear solves".
std::unique_ptr<ContactLinearSolver> make_contact_linear_solver(
    LinearSolver kind, const ElasticSystem& system, const ContactConstraints& constraints,
    dealii::TimerOutput& timer, dealii::ConditionalOStream& log);

}  // namespace hipfai::fem
