// hipfai — hybrid collision detection: sliding parts by radial, striking parts by cylindrical
// segmenting (thesis §3.6.3, Fig. 42).
//
// A mobile object can slide near the centre of rotation and strike further out. Distance
// thresholds T_1 < T_2 < ... split the mobile vertices into bands by |v - c|; each band is tested
// by the method chosen for it (default: radial below T_1, cylindrical above — the thesis' single
// threshold). Both methods find the same penetrating vertices of a closed fixed mesh; the split
// chooses the meaningful depth (radial depth for the sliding part, curvilinear depth for the
// striking part) and lets each method work where it is fast. Each vertex is tested by exactly one
// method, so the hybrid costs no more than one method over all vertices.
// A vertex exactly at a threshold belongs to the band above it.
#pragma once

#include "contact/cylindrical_segmenting.h"
#include "contact/radial_segmenting.h"

#include <vector>

namespace hipfai::contact {

enum class HybridMethod { kRadial, kCylindrical };

struct HybridOptions {
  std::vector<double> thresholds_mm;            // strictly increasing, > 0
  // One method per band (thresholds_mm.size() + 1); empty = radial, cylindrical, radial, ...
  std::vector<HybridMethod> band_methods;
  RadialQueryOptions radial;
  CylindricalQueryOptions cylindrical;
};

struct HybridResult {
  PenetrationResult result;                     // pairs of both methods, sorted by vertex
  std::vector<HybridMethod> vertex_method;      // per mobile vertex: the method that tested it
};

// `cylindrical_table` must be built for the rotation axis through the same centre as
// `radial_table`; `fixed` is the mesh both tables were built from; `posed_mobile` is the mobile
// mesh in its current pose. Radial pairs carry angle_deg = NaN, cylindrical pairs the arc angle.
HybridResult hybrid_segmenting(const CylindricalTable& cylindrical_table,
                               const RadialTable& radial_table, const geometry::TriMesh& fixed,
                               const geometry::TriMesh& posed_mobile, const HybridOptions& options);

}  // namespace hipfai::contact
