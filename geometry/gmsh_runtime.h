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

}  // namespace hipfai::geometry
