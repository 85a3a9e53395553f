// hipfai — ray-based sampling (Maciel, Boulic & Thalmann 2007), the approximate peer of radial
// segmenting (thesis §3.3.1-3.3.2, Figs. 18-19).
//
// Pre-processing: one ray from O per table cell, through the cell-centre direction
// (cell_centre_direction); the cell stores ONE fixed triangle: the crossing of that ray nearest to
// O whose facing suits the configuration (entering for kMobileInsideFixed: the socket's inner
// surface; exiting for kFixedInsideMobile: the fixed object's outer surface), ties to the lowest
// index. Empty cells store -1.
// Query: each mobile vertex is tested against the one triangle of its cell only, with the
// ray_triangle.h test and the depth/inequalities of radial_segmenting.h: it penetrates if its ray
// crosses that triangle on the configuration's side (t < 1 entering, or t > 1 exiting).
// Approximate by design: a vertex whose ray crosses another triangle of the same cell is missed
// (Fig. 19); the miss rate falls as the table grows but does not reach zero for every shape.
//
// By default the per-cell search uses the exact radial table (radial_table.h) as an accelerator;
// `scan_all_triangles` = true runs the original pre-processing instead (every triangle for every
// cell, O(cells x triangles), thesis §3.3.3.1.4), for timing comparisons. Both store the same
// triangles.
#pragma once

#include "contact/penetration_result.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_table.h"

#include <cstdint>
#include <vector>

namespace hipfai::contact {

struct RaySamplingTable {
  RadialGrid grid;
  Vec3 centre = Vec3::Zero();
  RadialConfiguration configuration = RadialConfiguration::kMobileInsideFixed;
  std::vector<std::int32_t> cell_triangle;  // cell id -> triangle, or -1
  std::size_t num_triangles = 0;
};

RaySamplingTable build_ray_sampling_table(const geometry::TriMesh& fixed, const Vec3& centre,
                                          const RadialTableOptions& options,
                                          RadialConfiguration configuration,
                                          bool scan_all_triangles = false);

// Same status conventions as radial_segmenting().
PenetrationResult ray_sampling(const RaySamplingTable& table, const geometry::TriMesh& fixed,
                               const geometry::TriMesh& mobile);

}  // namespace hipfai::contact
