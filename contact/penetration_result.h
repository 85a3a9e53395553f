// hipfai — what every collision query returns: penetration pairs with their depths.
//
// A pair links one vertex of the MOBILE mesh to the triangle of the FIXED mesh it penetrates.
// Indices are 0-based into the meshes as given. Depths are non-negative, in millimetres:
//   - cylindrical segmenting: the curvilinear (arc) depth r * angle along the vertex's circle
//     about the rotation axis, angle_deg being the rotation that brings the vertex back onto
//     the fixed surface (thesis §3.2, App. C-D);
//   - radial segmenting: the radial depth along the ray from the centre through the vertex
//     (thesis §3.3, App. F); angle_deg is NaN.
// Pairs are sorted by mobile vertex; each mobile vertex appears at most once.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace hipfai::contact {

struct PenetrationPair {
  std::int32_t mobile_vertex = -1;
  std::int32_t fixed_triangle = -1;
  double depth_mm = 0.0;
  double angle_deg = std::numeric_limits<double>::quiet_NaN();
};

enum class QueryStatus {
  kOk,              // the query ran; `pairs` holds every penetrating vertex (possibly none)
  kNoOverlap,       // the search intervals do not overlap: nothing can collide
  kInvalidInput,    // axis of zero length, non-finite input, empty mesh: see `message`
};

struct PenetrationResult {
  QueryStatus status = QueryStatus::kOk;
  std::vector<PenetrationPair> pairs;
  std::string message;  // empty unless status == kInvalidInput

  double max_depth_mm() const {
    double deepest = 0.0;
    for (const auto& pair : pairs) deepest = pair.depth_mm > deepest ? pair.depth_mm : deepest;
    return deepest;
  }
};

}  // namespace hipfai::contact

namespace hipfai::contact {

// Sorts pairs by mobile vertex (the documented order of every query's output).
void sort_by_mobile_vertex(std::vector<PenetrationPair>& pairs);

}  // namespace hipfai::contact
