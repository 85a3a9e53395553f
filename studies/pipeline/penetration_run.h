// hipfai — the penetration-depth method over a motion (thesis §4.3.2.1).
//
// Curvilinear depth: cylindrical segmenting, femur bone (mobile) against the labrum (fixed),
// about each step's rotation axis through the HJC; with the role swap, labrum vertices against the
// femur bone turning the opposite way. Radial depth: radial segmenting about the HJC, femoral
// cartilage (mobile, inside) against acetabular cartilage + labrum (fixed, outside); with the role
// swap, acetabular vertices against the femoral cartilage (counted where the ray from the HJC
// leaves the femur within the socket tissues' reach: beyond it the ray runs along the neck or
// shaft of a whole femur, not through the head). Each side is one contact::penetrate request
// over the motion (contact/penetrate.h): tables are built once per axis (or
// once, radial) and every step is one pass over the mobile vertices.
//
// Touching is not penetrating. The articulating surfaces of both sides are discretisations of the
// same sphere (radius R), so their vertices lie up to a chord's sagitta beyond the other side's
// triangles without any real overlap. The contact tolerance is that sagitta bound,
// e^2 / (2 R) with e the longest edge of the tissues involved (a triangle's circumradius is at
// most its longest edge), but never below the articular surfaces' own deviation from a sphere,
// 0.1 mm (literature::kSphericityToleranceMm): tol = max(e^2 / (2 R), 0.1 mm). Without the floor
// the set of counted vertices grows as the mesh is refined (cam flanks a few um outside R, whose
// arcs run along under the labrum's face), and the maximum curvilinear depth does not converge.
// Then:
//   - radial: a vertex penetrates only if its radial depth exceeds tol;
//   - curvilinear: only STRIKING vertices count — those farther than R + tol from the HJC. Vertices
//     on the articular sphere slide along it (thesis §3.6.3: the hybrid split by a distance
//     threshold gives sliding vertices to the radial method); along their circle the surfaces are
//     tangent and an arc depth would only magnify the sagitta.
#pragma once

#include "contact/radial_mapping.h"
#include "contact/radial_segmenting.h"
#include "contact/range_finder.h"
#include "contact/start_pose.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/motion.h"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace hipfai::studies {

struct PenetrationOptions {
  bool curvilinear = true;
  bool radial = true;
  bool rom = false;
  bool swap_roles = true;
  contact::RadialMapping mapping = contact::RadialMapping::kCube;
  // Which femur vertices count as radially penetrating (contact/radial_segmenting.h): kUnion,
  // inside the acetabular soft tissues (depth to their boundary towards the HJC); kBeyond, the
  // thesis' rule read literally: beyond the socket's surface along the ray from the HJC, also
  // after passing through the labrum (depth to the articular surface). kAdjacent is not offered.
  contact::RadialCrossingRule radial_rule = contact::RadialCrossingRule::kUnion;
  std::int64_t table_size = 20000;
  int threads = 2;
  std::filesystem::path cache_dir;  // radial tables are cached here when not empty
  // Negative: max(sagitta bound, sphericity) above; 0 disables the tolerance (raw geometric results).
  double contact_tolerance_mm = -1.0;
  // Curvilinear depth also sampled where each side's surface crosses the sphere R + tolerance
  // (geometry::split_at_sphere), the border of its striking region, not only at its vertices.
  bool sample_striking_boundary = false;
};

struct StepPenetration {
  double curvilinear_mm = 0.0;       // femur vertices in the labrum (max arc depth)
  double curvilinear_swap_mm = 0.0;  // labrum vertices in the femur
  double radial_mm = 0.0;            // femoral cartilage vertices in the acetabular soft tissue
  double radial_swap_mm = 0.0;       // acetabular soft-tissue vertices in the femoral cartilage
  int curvilinear_vertices = 0;      // penetrating vertices, both roles
  int radial_vertices = 0;
  double curvilinear_ms = 0.0;       // per-pose query time, both roles
  double radial_ms = 0.0;

  double curvilinear_max_mm() const { return std::max(curvilinear_mm, curvilinear_swap_mm); }
  double radial_max_mm() const { return std::max(radial_mm, radial_swap_mm); }
};

// Per-vertex depth fields, keyed "<tissue>/<quantity>", e.g. "femur_bone/curvilinear_depth_mm".
using DepthFields = std::map<std::string, std::vector<double>>;

struct PenetrationRun {
  std::vector<StepPenetration> steps;
  DepthFields max_fields;               // per-vertex maximum over the motion
  std::vector<Eigen::Vector3d> rom_axes;  // model coordinates
  std::vector<contact::RangeOfMotion> rom;
  double curvilinear_preprocessing_ms = 0.0;  // tables + pose caches
  double radial_preprocessing_ms = 0.0;       // tables (built or loaded)
  double contact_tolerance_mm = 0.0;          // as applied
  // Femur bone against labrum in the model's own (neutral) pose, touching below the contact
  // tolerance: the pair that must be apart before any motion (cartilage layers touch bone and each
  // other by construction, and the articular surfaces touch within the tolerance, so they are
  // not checked). Left empty (status kOk, no counts) when either tissue is not loaded.
  contact::StartPoseOverlap neutral_overlap;

  double max_curvilinear_mm() const;
  double max_radial_mm() const;
  // Each step's maximum, in step order.
  std::vector<double> curvilinear_maxima_mm() const;
  std::vector<double> radial_maxima_mm() const;
};

// Called after each step with the step index (0-based) and that step's per-vertex fields.
using StepObserver = std::function<void(std::size_t step, const DepthFields& fields)>;

// Throws hipfai::Error "<hip id>: femur_bone and labrum already intersect in the neutral pose: ..."
// when they overlap beyond the contact tolerance before any motion: every depth of
// the motion would include that overlap.
PenetrationRun compute_penetration(const LoadedHip& hip, const Motion& motion,
                                   const PenetrationOptions& options, StageLog& log,
                                   const StepObserver& observer = {});

}  // namespace hipfai::studies
