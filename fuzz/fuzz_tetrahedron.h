// The small closed mesh the harnesses and their seeds use: a tetrahedron with a vertex field.
#pragma once

#include "geometry/tri_mesh.h"

namespace hipfai::fuzz {

geometry::TriMesh tetrahedron();

}  // namespace hipfai::fuzz
