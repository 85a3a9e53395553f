// hipfai — what the collision queries return: penetration pairs with their depths
// (PenetrationResult, one query at one pose), and what contact/penetrate.h returns for a whole
// request (PenetrationResponse: those pairs per step and depth, and the cost of getting them).
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
  std::int32_t mobile_vertex = -1;   // index into the mobile mesh's vertices
  std::int32_t fixed_triangle = -1;  // index into the fixed mesh's triangles
  double depth_mm = 0.0;             // curvilinear or radial depth (see above), >= 0
  double angle_deg = std::numeric_limits<double>::quiet_NaN();  // curvilinear: the arc's angle; radial: NaN
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

// One step of a request (penetration_request.h): the pairs of each depth asked for.
struct StepPairs {
  // Curvilinear pairs (angle_deg set); status kOk and no pairs when curvilinear depth was not asked.
  PenetrationResult curvilinear;
  // Radial pairs (angle_deg NaN); status kOk and no pairs when radial depth was not asked.
  PenetrationResult radial;
  double curvilinear_ms = 0.0;  // wall time of this step's curvilinear query
  double radial_ms = 0.0;       // wall time of this step's radial query
};

// How the pre-processing of one depth was obtained (penetration_request.h: cache_dir).
struct PreprocessingCount {
  int built = 0;   // tables or pose caches built (and saved, with a cache folder)
  int loaded = 0;  // loaded from the cache folder instead
};

// What penetrate() returns. Like an Eigen solver's info(), `status` must be looked at first.
struct PenetrationResponse {
  // kOk: every step was queried (a step's own result may still say kNoOverlap). kInvalidInput: a
  // mesh is missing or a query rejected its input; `message` says which, and `steps` holds what
  // was computed before it (nothing is thrown for data-dependent reasons).
  QueryStatus status = QueryStatus::kOk;
  std::string message;  // empty unless status == kInvalidInput
  std::vector<StepPairs> steps;  // one per request step, in order

  // Curvilinear: ring tables and pose caches, one per distinct axis; radial: F's table about the centre.
  PreprocessingCount curvilinear_preprocessing;
  PreprocessingCount radial_preprocessing;
  double curvilinear_preprocessing_ms = 0.0;  // wall time of the curvilinear pre-processing, all axes
  double radial_preprocessing_ms = 0.0;       // wall time of the radial table and pose query
};

}  // namespace hipfai::contact

namespace hipfai::contact {

// Sorts pairs by mobile vertex (the documented order of every query's output).
void sort_by_mobile_vertex(std::vector<PenetrationPair>& pairs);

}  // namespace hipfai::contact
