// hipfai — switches that turn one speed-up of a query off, for the benchmark's ablations and for the
// tests that check each speed-up leaves the answer unchanged. Not user options: every switch
// changes the time a query takes, never its pairs. Callers of contact/penetrate.h never see them.
#pragma once

#include "contact/cylindrical_segmenting.h"
#include "contact/radial_segmenting.h"

namespace hipfai::contact::detail {

// The one-pass cylindrical query (cylindrical_segmenting.h); true everywhere is the public query.
struct CylindricalAblation {
  // Find each circle's nearest crossing through the table's angular index (true) or by offering
  // every candidate of its cell (false: the reference the index is tested against).
  bool angular_walk = true;
  // Skip the walk of a vertex in an outside region of its ring cell
  // (CylindricalTable::outside_every_shell), whose nearest crossing can only say "outside".
  // False: every circle gets its nearest crossing (the reference these regions are tested against).
  bool outside_regions = true;
  // When the table keeps the clusters of a mobile mesh with as many vertices
  // (CylindricalTable::mobile_clusters), test each cluster's posed bounding ball before its
  // vertices. False: every vertex on its own.
  bool mobile_clusters = true;
};

// The three one-pass queries of cylindrical_segmenting.h with speed-ups switched off.
PenetrationResult cylindrical_segmenting(const CylindricalTable& table, const geometry::TriMesh& posed_mobile,
                                         const CylindricalQueryOptions& options,
                                         const CylindricalAblation& ablation);
PenetrationResult cylindrical_segmenting(const CylindricalTable& table, const geometry::TriMesh& mobile,
                                         const Eigen::Isometry3d& pose, const CylindricalQueryOptions& options,
                                         const CylindricalAblation& ablation);
PenetrationResult cylindrical_segmenting(const CylindricalTable& table, const VertexClusters& mobile,
                                         const Eigen::Isometry3d& pose, const CylindricalQueryOptions& options,
                                         const CylindricalAblation& ablation);

// The radial query (radial_segmenting.h) with speed-ups switched off.
struct RadialAblation {
  // Radial spans (radial_spans.h): vertices outside the table's cap, or at a distance from O
  // where the rule cannot find its crossing, are decided without a triangle test. False tests
  // every vertex (the reference the spans are tested against).
  bool cull = true;
};

PenetrationResult radial_segmenting(const RadialTable& table, const geometry::TriMesh& fixed,
                                    const geometry::TriMesh& mobile, const RadialQueryOptions& options,
                                    const RadialAblation& ablation);

}  // namespace hipfai::contact::detail
