// hipfai — the functional HJC estimators dconst and dref (thesis §4.4.2.2.2, after Gilles 2007).
//
// A simulated circumduction: the femur is turned by `elevation_deg` (20 deg, Kang et al. 2003)
// about `poses` axes evenly spaced around the femur's long axis (the long axis sweeps a cone),
// each turn about a start centre c0 (the femoralheadsphere centre). At each pose the femur is then
// shifted, by Gauss-Newton on three translations, so that the signed distance d_i from every
// lunate vertex P_i to the femoral head surface (the head patch, closest point on its triangles)
// comes back to its target: |d_i - d_i^target| minimised in the least-squares sense.
//   dconst: d_i^target = r_acetabulum - r_head, the same for every vertex (radii of the two
//           single-sphere fits);
//   dref:   d_i^target = d_i in the scanned pose.
// The thesis shifts the pelvis; shifting the femur by the opposite vector is the same relative
// motion. Each pose k is then x -> R_k x + b_k (femur in the pelvis frame) and the HJC is the femur
// point that moves least over the circumduction: argmin_c sum_k |(R_k - I) c + b_k|^2, linear least
// squares ("a global minimisation", thesis). residual motion = that point's displacement per pose
// (RMS and max over the poses): 0 for a perfect ball and socket.
//
// Lunate vertices whose nearest head vertex lies on the head patch's border are left out of a
// pose (beyond the patch the distance is to its edge, not to the head). Penetration (dconst on an
// uneven joint space) is a negative signed distance: the sign is that of the head normal.
#pragma once

#include "core/literature.h"
#include "geometry/tri_mesh.h"

#include <string>
#include <vector>

namespace hipfai::geometry {

struct FunctionalHjcOptions {
  double elevation_deg = literature::kCircumductionElevationDeg;  // circumduction cone half-angle
  int poses = 24;                // axes around the cone
  int max_iterations = 30;       // Gauss-Newton per pose
  double tolerance_mm = 1e-7;    // stop when the shift changes less than this
};

enum class FunctionalTarget { kConstant, kReference };

struct FunctionalHjc {
  bool ok = false;
  std::string message;
  Vec3 center_mm = Vec3::Zero();
  double residual_motion_rms_mm = 0.0;  // displacement of the centre per pose
  double residual_motion_max_mm = 0.0;
  double distance_rms_mm = 0.0;         // RMS of d_i - d_i^target after the shifts, over all poses
  double distance_max_mm = 0.0;
  double target_mm = 0.0;               // dconst's constant (NaN-free: 0 for dref)
  int poses_used = 0;
  std::vector<Vec3> shifts_mm;          // femur shift per pose
};

// head: the femoral head patch (triangles, outward normals per vertex); lunate: the lunate points.
// start_center_mm: c0; long_axis: direction the circumduction cone is built around (any length).
// constant_mm: the dconst target (ignored for kReference).
FunctionalHjc functional_hjc(const TriMesh& head, const std::vector<Vec3>& head_normals,
                             const std::vector<Vec3>& lunate, const Vec3& start_center_mm,
                             const Vec3& long_axis, FunctionalTarget target, double constant_mm,
                             const FunctionalHjcOptions& options = {});

// Signed distance from `point` to the surface patch (closest point over the triangles of the
// nearest vertex's one-ring; sign of the nearest vertex's normal); `on_border` tells whether the
// nearest vertex is on the patch border. Exposed for the tests.
class PatchDistance {
 public:
  PatchDistance(const TriMesh& patch, const std::vector<Vec3>& normals);
  double signed_distance(const Vec3& point, Vec3& gradient, bool& on_border) const;

 private:
  std::int32_t nearest_vertex(const Vec3& point) const;
  const TriMesh& patch_;
  const std::vector<Vec3>& normals_;
  std::vector<std::vector<std::int32_t>> ring_;  // triangles per vertex
  std::vector<char> border_;
  double cell_mm_ = 1.0;
  Vec3 origin_ = Vec3::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Ones();
  std::vector<std::vector<std::int32_t>> cells_;
};

}  // namespace hipfai::geometry
