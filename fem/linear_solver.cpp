#include "fem/linear_solver.h"

#include "core/error.h"
#include "fem/cg_amg_linear_solver.h"
#include "fem/distributed_direct_solver.h"
#include "fem/serial_direct_solver.h"

#include <deal.II/base/mpi.h>

namespace hipfai::fem {

const char* to_string(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::kCgAmg:
      return "cg_amg";
    case LinearSolver::kDirect:
      return "direct";
    case LinearSolver::kSubstructured:
      return "substructured";
  }
  return "unknown";
}

void ContactLinearSolver::begin_run(const LinearSolverSettings& settings) {
  settings_ = settings;
  statistics_ = LinearSolverStatistics();
}

std::unique_ptr<ContactLinearSolver> make_contact_linear_solver(
    LinearSolver kind, const ElasticSystem& system, const ContactConstraints& constraints,
    dealii::TimerOutput& timer, dealii::ConditionalOStream& log) {
  if (kind == LinearSolver::kSubstructured) {
    throw_error("fem: the substructured solver solves the contact problem itself; it has no "
                "linear solver of this interface");
  }
  if (kind == LinearSolver::kCgAmg) return std::make_unique<CgAmgLinearSolver>(system, timer);
  if (dealii::Utilities::MPI::n_mpi_processes(system.communicator()) == 1) {
    return std::make_unique<SerialDirectSolver>(system, constraints, timer, log);
  }
  return std::make_unique<DistributedDirectSolver>(system, timer, log);
}

}  // namespace hipfai::fem
