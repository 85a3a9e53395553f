// hipfai — Embree 3 radial ray casting, the ray-tracer peer of radial segmenting.
//
// The way a user computes radial depth with a ray tracer: one BVH of the fixed mesh (the
// pre-processing), then per posed mobile vertex v (posed as its ray is made) one ray along the line from the centre O through
// v, and the crossing adjacent to v decides (the crossing rule of contact/radial_segmenting.h):
//   kMobileInsideFixed: ray from v towards O, limited to |v - O|; the first hit is the last
//     crossing between O and v; v penetrates iff that surface is entered when going from O
//     outwards (outward normal . (v - O) < 0), depth = hit distance;
//   kFixedInsideMobile: ray from v away from O; the first hit is the first crossing beyond v; v
//     penetrates iff that surface is exited going outwards, depth = hit distance.
// The facing is taken from the mesh's own outward normal of the hit triangle, not from Embree's
// geometric normal, so the winding convention of Embree cannot flip it. Embree intersects in
// single precision (coordinates are stored relative to O to keep them small), so rays through
// edges, vertices, or vertices lying on the fixed surface may be judged differently from the
// watertight double-precision rule; the benchmark counts those differences. Embree's types stay in
// peer_embree.cpp.
#pragma once

#include "contact/penetration_result.h"
#include "contact/radial_segmenting.h"
#include "geometry/tri_mesh.h"

#include <memory>

namespace hipfai::bench {

class EmbreeRadialCaster {
 public:
  // Builds the BVH of `fixed` (with `build_threads` Embree worker threads; 0 = all).
  EmbreeRadialCaster(const geometry::TriMesh& fixed, const Eigen::Vector3d& centre,
                     int build_threads = 0);
  ~EmbreeRadialCaster();
  EmbreeRadialCaster(const EmbreeRadialCaster&) = delete;
  EmbreeRadialCaster& operator=(const EmbreeRadialCaster&) = delete;

  // One ray per vertex of `mobile` posed by `pose` (each vertex posed as the ray is made, so no
  // posed copy of the mesh is built: Embree's best use for a rigid pose), over `num_threads`
  // threads (1 or 2). Pairs sorted by vertex; depth_mm as in radial_segmenting.h.
  contact::PenetrationResult query(const geometry::TriMesh& mobile, const Eigen::Isometry3d& pose,
                                   contact::RadialConfiguration configuration, int num_threads = 1) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hipfai::bench
