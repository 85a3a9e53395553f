#include "fem/contact_result.h"

namespace hipfai::fem {

const char* to_string(ContactStatus status) {
  switch (status) {
    case ContactStatus::kConverged:
      return "converged";
    case ContactStatus::kActiveSetNotConverged:
      return "active set not converged";
    case ContactStatus::kLinearSolverFailed:
      return "linear solver failed";
    case ContactStatus::kNoContact:
      return "no contact";
    case ContactStatus::kNonFinite:
      return "non-finite numbers";
  }
  return "unknown";
}

}  // namespace hipfai::fem
