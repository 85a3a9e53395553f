// hipfai — what the helper ranks of a substructured run hold after it: the result rank 0
// solved, as bytes (fem/rank_team.h, RankTeam::Message::kRunDone).
//
// On several ranks the substructured solver's rank 0 solves the run; the callers of
// ContactProblem on the other ranks read the result as on rank 0 (a motion's cutbacks and next
// translation depend on it). The fields stay on rank 0, the only rank with the run's mesh set
// up: write_vtu writes rank 0's file alone and displacement_at is rank 0's alone on such a run.
#pragma once

#include "fem/contact_result.h"
#include "fem/rank_team.h"

namespace hipfai::fem {

// A run's state as the helpers keep it for their callers.
struct RunState {
  ContactResult result;
};

void write_run_state(const RunState& state, ByteWriter& out);
// Throws hipfai::Error when the bytes end early.
RunState read_run_state(ByteReader& in);

}  // namespace hipfai::fem
