// hipfai — least-squares sphere fits: one sphere, or two concentric spheres (thesis §4.4.2.2.1,
// the femoralheadsphere, acetabulumsphere and doublesphere HJC estimators).
//
// The fit minimises the GEOMETRIC distance sum_i (|p_i - c| - r)^2, not the algebraic one
// (|p_i - c|^2 - r^2)^2: the algebraic fit weighs points by their distance from the centre and is
// biased on a partial sphere (a femoral head covers about half of one, a lunate surface less), the
// geometric fit is the maximum-likelihood centre under isotropic surface noise. The algebraic fit
// (linear, Kasa 1976) only gives the start; Levenberg-Marquardt on (c, r) then converges in a few
// iterations. Concentric spheres (doublesphere): one centre c and two radii r_a, r_b, the residual
// of every point against the radius of its own set.
//
// Status, Eigen style: a fit that cannot be trusted says so in `status` and `message` and the
// caller must look. kFlat: the points span no sphere (coplanar or collinear within 1e-6 of their
// extent, or the fitted radius exceeds 1000 times the extent: a plane seen as a huge sphere).
// kTooFewPoints: fewer than 4 (one sphere) or 4 + 1 (two, each set at least 2). Touching cases:
// points exactly on a sphere give residual 0 to round-off (the tests ask 1e-9 mm).
#pragma once

#include "geometry/tri_mesh.h"

#include <string>
#include <vector>

namespace hipfai::geometry {

enum class FitStatus { kOk, kTooFewPoints, kFlat, kNotConverged };

const char* to_string(FitStatus status);

struct SphereFitOptions {
  int max_iterations = 100;
  double tolerance_mm = 1e-12;   // stop when the centre moves less than this per iteration
  bool geometric = true;         // false: algebraic (Kasa) fit only
};

struct SphereFit {
  FitStatus status = FitStatus::kTooFewPoints;
  std::string message;
  Vec3 center_mm = Vec3::Zero();
  double radius_mm = 0.0;
  double rms_mm = 0.0;        // sqrt(mean(residual^2)), residual = |p - c| - r
  double max_abs_mm = 0.0;    // max |residual|
  int iterations = 0;
  std::size_t points = 0;
  bool ok() const { return status == FitStatus::kOk; }
};

// Least-squares sphere through `points` (mm).
SphereFit fit_sphere(const std::vector<Vec3>& points, const SphereFitOptions& options = {});

struct ConcentricSphereFit {
  FitStatus status = FitStatus::kTooFewPoints;
  std::string message;
  Vec3 center_mm = Vec3::Zero();
  double radius_a_mm = 0.0, radius_b_mm = 0.0;
  double rms_mm = 0.0, max_abs_mm = 0.0;   // over both sets
  double rms_a_mm = 0.0, rms_b_mm = 0.0;   // per set
  int iterations = 0;
  bool ok() const { return status == FitStatus::kOk; }
};

// One centre, two radii: set a on a sphere of radius r_a, set b on one of radius r_b.
ConcentricSphereFit fit_concentric_spheres(const std::vector<Vec3>& points_a,
                                           const std::vector<Vec3>& points_b,
                                           const SphereFitOptions& options = {});

}  // namespace hipfai::geometry
