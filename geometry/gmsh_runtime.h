// hipfai — gmsh's process-wide runtime, shared by everything in geometry/ that calls gmsh.
//
// gmsh keeps one global model and one set of options per process and is not re-entrant: every
// use holds this lock, and gmsh is initialised once, by whichever user comes first (the hip
// generator and the volume mesher both call it, possibly from different threads).
#pragma once

#include <mutex>

namespace hipfai::geometry {

// Locks gmsh for the caller's scope; initialises gmsh (quiet terminal) on the first call.
std::unique_lock<std::mutex> lock_gmsh();

// Restarts gmsh (finalize, initialize, quiet terminal again) for a caller holding `held` from
// lock_gmsh(); throws hipfai::Error for any other lock. After a failed 3D mesh gmsh keeps an error
// state in which later meshing silently produces nothing; a restart clears it. Every option goes
// back to gmsh's default, which is safe for users that set (or save and restore) their own.
void reset_gmsh_locked(const std::unique_lock<std::mutex>& held);

}  // namespace hipfai::geometry
