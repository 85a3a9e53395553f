// hipfai — what the helper ranks of a substructured run hold after it: the result and the fields
// rank 0 solved, as bytes (fem/rank_team.h, RankTeam::Message::kRunDone).
//
// On several ranks the substructured solver's rank 0 solves the run; the callers of
// ContactProblem on the other ranks read the same things as on rank 0: the result (a motion's
// cutbacks and next translation depend on it), the displacement (displacement_at) and the fields
// write_vtu writes, which is collective (each rank writes its own cells).
#pragma once

#include "fem/contact_output.h"
#include "fem/contact_result.h"
#include "fem/mortar_coupling.h"
#include "fem/rank_team.h"

#include <deal.II/lac/vector.h>

#include <vector>

namespace hipfai::fem {

// A run's state as ContactProblem keeps it for its callers.
struct RunState {
  ContactResult result;
  dealii::Vector<double> displacement;   // every dof
  dealii::Vector<float> cell_von_mises;  // per active cell
  std::vector<SlaveNode> nodes;          // the run's contact nodes
  ContactFields fields;                  // per node of `nodes`
};

void write_run_state(const RunState& state, ByteWriter& out);
// Throws hipfai::Error when the bytes end early.
RunState read_run_state(ByteReader& in);

}  // namespace hipfai::fem
