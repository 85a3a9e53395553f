// hipfai — the acetabulum of a right hip found on the pelvis (see acetabulum.h for the method).
#include "anatomy/acetabulum.h"

#include "core/error.h"
#include "geometry/hip_frame.h"
#include "geometry/hjc_regions.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hipfai::anatomy {
namespace {

using geometry::Vec3;

// Rounds of axis -> rim -> plane; the axis moves by less than 0.1 deg after the second on the
// bones tried (tests/anatomy/acetabulum_test.cpp).
constexpr int kAxisRounds = 4;
// Robust plane fit: a rim point more than this many scaled MADs from the plane is not rim (the
// notch's floor, the fossa), but never below kMinResidualBandMm (segmentation noise, thesis
// §4.4.2.1.2: 1.5 mm).
constexpr double kResidualMads = 3.0;
constexpr double kMinResidualBandMm = 1.5;
// Ties (rounding, not geometry): polar angles this close are equal, clock positions this close to
// a bin boundary lie on it.
constexpr double kTiePolarRad = 1e-9;
constexpr double kBoundaryFraction = 1e-7;

struct Basis {
  Vec3 e0, e90;
};

Basis clock_basis(const Vec3& axis, const AnatomicalFrame& frame) {
  Vec3 e0 = frame.anterior - frame.anterior.dot(axis) * axis;
  if (e0.norm() < 1e-6) e0 = frame.superior.cross(axis);
  e0.normalize();
  return {e0, axis.cross(e0)};
}

double clock_angle(const Basis& basis, const Vec3& d) {
  return std::atan2(basis.e90.dot(d), basis.e0.dot(d)) * geometry::kRadToDeg;
}

struct Plane {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
};

Plane fit_plane(const std::vector<Vec3>& points) {
  Plane plane;
  for (const Vec3& p : points) plane.point += p;
  plane.point /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) covariance += (p - plane.point) * (p - plane.point).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  plane.normal = solver.eigenvectors().col(0);
  return plane;
}

double median(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// The rim about `axis`: per clock bin, the smallest polar angle of the vertices `near` the
// centre c, at the mean of the vertices that tie with it (a generated socket's rim is an exact
// cone: every rim vertex has the same polar angle, and which one rounding makes "the" minimum must
// not matter). A vertex on a bin boundary (to rounding) counts in both bins. Bins without bone
// have no point.
std::vector<RimPoint> rim_points(const geometry::TriMesh& pelvis, const std::vector<std::int32_t>& near, const Vec3& c,
                                 const Vec3& axis, const Basis& basis, int bins) {
  std::vector<double> best(bins, std::numeric_limits<double>::infinity());
  std::vector<Vec3> tied_sum(bins, Vec3::Zero());
  std::vector<int> ties(bins, 0);
  auto offer = [&](int bin, double polar, const Vec3& p) {
    bin = (bin % bins + bins) % bins;
    if (polar < best[bin] - kTiePolarRad) {
      best[bin] = polar;
      tied_sum[bin] = p;
      ties[bin] = 1;
    } else if (polar <= best[bin] + kTiePolarRad) {
      best[bin] = std::min(best[bin], polar);
      tied_sum[bin] += p;
      ++ties[bin];
    }
  };
  for (const std::int32_t i : near) {
    const Vec3 d = pelvis.vertices[i] - c;
    const double r = d.norm();
    if (r <= 0.0) continue;
    const double polar = std::acos(std::clamp(d.dot(axis) / r, -1.0, 1.0));
    const double position = (clock_angle(basis, d) + 180.0) / 360.0 * bins;
    const int bin = static_cast<int>(std::floor(position));
    offer(bin, polar, pelvis.vertices[i]);
    if (position - bin < kBoundaryFraction) offer(bin - 1, polar, pelvis.vertices[i]);
    if (bin + 1 - position < kBoundaryFraction) offer(bin + 1, polar, pelvis.vertices[i]);
  }
  std::vector<RimPoint> rim;
  for (int b = 0; b < bins; ++b) {
    if (ties[b] == 0) continue;
    RimPoint p;
    p.point_mm = tied_sum[b] / ties[b];
    p.clock_deg = clock_angle(basis, p.point_mm - c);
    p.polar_deg = best[b] * geometry::kRadToDeg;
    rim.push_back(p);
  }
  return rim;
}

// Robust plane: fit, drop far points, refit; the points kept marked in_plane_fit.
Plane fit_rim_plane(std::vector<RimPoint>& rim, const std::string& what) {
  for (auto& p : rim) p.in_plane_fit = true;
  Plane plane;
  for (int pass = 0; pass < 3; ++pass) {
    std::vector<Vec3> kept;
    for (const auto& p : rim) if (p.in_plane_fit) kept.push_back(p.point_mm);
    if (kept.size() < 6) throw_error(what, ": too few rim points for the rim plane");
    plane = fit_plane(kept);
    std::vector<double> residuals;
    for (const auto& p : rim) residuals.push_back(std::abs(plane.normal.dot(p.point_mm - plane.point)));
    const double band = std::max(kMinResidualBandMm, kResidualMads * 1.4826 * median(residuals));
    for (std::size_t k = 0; k < rim.size(); ++k) rim[k].in_plane_fit = residuals[k] <= band;
  }
  return plane;
}

// RMS distance of the plane-fit rim points from the plane.
double rim_plane_rms(const std::vector<RimPoint>& rim, const Plane& plane) {
  double sum = 0.0;
  int count = 0;
  for (const auto& p : rim) {
    if (!p.in_plane_fit) continue;
    const double r = plane.normal.dot(p.point_mm - plane.point);
    sum += r * r;
    ++count;
  }
  return std::sqrt(sum / std::max(1, count));
}

}  // namespace

double Acetabulum::clock_of(const Vec3& point_mm) const {
  return clock_angle({clock_anterior, clock_superior}, point_mm - centre_mm);
}

std::vector<std::pair<double, double>> Acetabulum::rim_profile() const {
  std::vector<std::pair<double, double>> profile;
  profile.reserve(rim.size());
  for (const RimPoint& p : rim) profile.emplace_back(p.clock_deg, p.polar_deg);
  return profile;
}

std::array<double, 4> murray_angles(const Vec3& a) {
  const double lateral = a.x(), anterior = a.y(), superior = a.z();
  return {std::atan2(lateral, -superior) * geometry::kRadToDeg,
          std::asin(std::clamp(anterior / a.norm(), -1.0, 1.0)) * geometry::kRadToDeg,
          std::acos(std::clamp(-superior / a.norm(), -1.0, 1.0)) * geometry::kRadToDeg,
          std::atan2(anterior, lateral) * geometry::kRadToDeg};
}

Acetabulum find_acetabulum(const AcetabulumRequest& request) {
  if (request.pelvis == nullptr || request.pelvis->empty()) throw_error(request.what, ": empty mesh");
  const geometry::TriMesh& pelvis = *request.pelvis;
  const geometry::SurfaceRegion lunate =
      geometry::find_lunate_surface(pelvis, request.head_centre_mm, request.head_radius_mm, {}, request.what);
  if (!lunate.sphere.ok()) throw_error(request.what, ": no sphere fits the lunate surface: ", lunate.sphere.message);

  Acetabulum result;
  result.centre_mm = lunate.sphere.center_mm;
  result.radius_mm = lunate.sphere.radius_mm;
  result.lunate_rms_mm = lunate.sphere.rms_mm;
  const Vec3& c = result.centre_mm;

  // First axis: away from the lunate surface's mean direction.
  Vec3 mean_direction = Vec3::Zero();
  for (const Vec3& v : lunate.patch.vertices) mean_direction += (v - c).normalized();
  if (!(mean_direction.norm() > 0.0)) throw_error(request.what, ": the lunate surface has no direction");
  Vec3 axis = -mean_direction.normalized();

  const double reach = request.rim_reach * result.radius_mm;
  std::vector<std::int32_t> near;
  for (std::size_t i = 0; i < pelvis.num_vertices(); ++i) {
    if ((pelvis.vertices[i] - c).norm() <= reach) near.push_back(static_cast<std::int32_t>(i));
  }
  const int bins = std::max(8, request.clock_bins);
  for (int round = 0; round < kAxisRounds; ++round) {
    const Basis basis = clock_basis(axis, request.pelvis_frame);
    result.rim = rim_points(pelvis, near, c, axis, basis, bins);
    if (result.rim.size() < static_cast<std::size_t>(bins) / 2) {
      throw_error(request.what, ": no acetabular rim around the lunate surface (", result.rim.size(), " of ",
                  bins, " clock sectors have bone)");
    }
    const Plane plane = fit_rim_plane(result.rim, request.what);
    Vec3 next = plane.normal;
    if (next.dot(axis) < 0.0) next = -next;
    result.rim_plane_rms_mm = rim_plane_rms(result.rim, plane);
    axis = next;
  }
  result.axis = axis;
  const Basis basis = clock_basis(axis, request.pelvis_frame);
  result.clock_anterior = basis.e0;
  result.clock_superior = basis.e90;
  for (auto& p : result.rim) {
    const Vec3 d = p.point_mm - c;
    p.clock_deg = clock_angle(basis, d);
    p.polar_deg = std::acos(std::clamp(d.normalized().dot(axis), -1.0, 1.0)) * geometry::kRadToDeg;
  }
  std::sort(result.rim.begin(), result.rim.end(),
            [](const RimPoint& a, const RimPoint& b) { return a.clock_deg < b.clock_deg; });
  const Eigen::Matrix3d to_frame = request.pelvis_frame.axes().transpose();
  const auto angles = murray_angles(to_frame * axis);
  result.radiographic_inclination_deg = angles[0];
  result.radiographic_anteversion_deg = angles[1];
  result.anatomic_inclination_deg = angles[2];
  result.anatomic_anteversion_deg = angles[3];
  return result;
}

}  // namespace hipfai::anatomy
