// hipfai — CGAL's AABB tree as a second radial ray caster (double precision, CGAL's exact
// predicates kernel for the intersection tests).
//
// Same contract as peer_embree.h: the AABB tree of the fixed mesh is the pre-processing; per posed
// mobile vertex one ray along the line from the centre O through v, first_intersection() gives the
// crossing adjacent to v, and the mesh's outward normal of that triangle decides (crossing rule of
// contact/radial_segmenting.h). CGAL's ray-triangle test is exact, so differences with the
// watertight rule can only come from the constructed hit point (rounded) and from ties between
// triangles sharing the hit edge (CGAL returns one of them, not the lowest index): the vertex set
// must match exactly, depths to rounding. CGAL's types stay in peer_cgal.cpp.
#pragma once

#include "contact/penetration_result.h"
#include "contact/radial_segmenting.h"
#include "geometry/tri_mesh.h"

#include <memory>

namespace hipfai::bench {

class CgalRadialCaster {
 public:
  CgalRadialCaster(const geometry::TriMesh& fixed, const Eigen::Vector3d& centre);
  ~CgalRadialCaster();
  CgalRadialCaster(const CgalRadialCaster&) = delete;
  CgalRadialCaster& operator=(const CgalRadialCaster&) = delete;

  contact::PenetrationResult query(const geometry::TriMesh& posed_mobile,
                                   contact::RadialConfiguration configuration,
                                   int num_threads = 1) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hipfai::bench
