#include "geometry/hip_measure.h"

#include "geometry/hip_frame.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace hipfai::geometry {

std::vector<PlaneSegment> plane_section(const TriMesh& mesh, const Vec3& point, const Vec3& normal) {
  std::vector<PlaneSegment> segments;
  std::vector<double> distance(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const double d = (mesh.vertices[i] - point).dot(normal);
    // A vertex exactly on the plane counts as on the positive side, so every triangle crossing
    // yields exactly two edge crossings.
    distance[i] = d == 0.0 ? std::numeric_limits<double>::min() : d;
  }
  for (const Triangle& tri : mesh.triangles) {
    Vec3 hits[3];
    int count = 0;
    for (int k = 0; k < 3; ++k) {
      const auto i = static_cast<std::size_t>(tri[static_cast<std::size_t>(k)]);
      const auto j = static_cast<std::size_t>(tri[static_cast<std::size_t>((k + 1) % 3)]);
      if ((distance[i] > 0.0) != (distance[j] > 0.0)) {
        const double t = distance[i] / (distance[i] - distance[j]);
        hits[count++] = mesh.vertices[i] + t * (mesh.vertices[j] - mesh.vertices[i]);
      }
    }
    if (count == 2) segments.push_back({hits[0], hits[1]});
  }
  return segments;
}

CeMeasurement measure_ce_angle(const std::vector<const TriMesh*>& acetabulum, const Vec3& hjc_mm,
                               const Vec3& lateral, const Vec3& superior) {
  const Vec3 anterior = superior.cross(lateral).normalized();
  std::vector<Vec3> points;
  for (const TriMesh* mesh : acetabulum) {
    for (const auto& segment : plane_section(*mesh, hjc_mm, anterior)) {
      points.push_back(segment.a);
      points.push_back(segment.b);
    }
  }
  CeMeasurement result;
  if (points.empty()) return result;
  double nearest = std::numeric_limits<double>::infinity();
  for (const Vec3& p : points) nearest = std::min(nearest, (p - hjc_mm).norm());
  const double reach = 2.5 * nearest;
  double best = -std::numeric_limits<double>::infinity();
  for (const Vec3& p : points) {
    const Vec3 v = p - hjc_mm;
    const double z = v.dot(superior);
    if (z <= 0.0 || v.norm() > reach) continue;
    const double angle = std::atan2(v.dot(lateral), z);
    // Ties (the whole rim face has one angle): prefer the point nearest the HJC, the articular edge.
    if (angle > best + 1e-9 || (angle > best - 1e-9 && v.norm() < (result.rim_point_mm - hjc_mm).norm())) {
      best = std::max(best, angle);
      result.rim_point_mm = p;
    }
  }
  if (!std::isfinite(best)) return result;
  result.ce_deg = best * kRadToDeg;
  result.status = MeasureStatus::kOk;
  return result;
}

double alpha_in_plane(const std::vector<const TriMesh*>& femur, const Vec3& centre, double radius_mm,
                      const Vec3& neck_axis, const Vec3& u, double tolerance_mm, Vec3* departure_point,
                      double articular_gap_deg) {
  const Vec3 normal = neck_axis.cross(u).normalized();
  // Bins of 0.1 deg of the polar angle from the neck axis; each keeps the outermost deviation
  // from the sphere (bone and cartilage together: the union's outer contour).
  constexpr double kBinDeg = 0.1;
  constexpr int kBins = static_cast<int>(180.0 / kBinDeg) + 1;
  std::vector<double> outermost(kBins, -std::numeric_limits<double>::infinity());
  std::vector<Vec3> where(kBins, Vec3::Zero());
  // Sampling step well below the bin width at the head radius (0.1 deg ~ 0.044 mm at 25 mm).
  const double step = 0.25 * kBinDeg * kDegToRad * radius_mm;
  for (const TriMesh* mesh : femur) {
    for (const auto& segment : plane_section(*mesh, centre, normal)) {
      const double length = (segment.b - segment.a).norm();
      const int samples = std::max(1, static_cast<int>(std::ceil(length / step)));
      for (int s = 0; s <= samples; ++s) {
        const Vec3 q = segment.a + (static_cast<double>(s) / samples) * (segment.b - segment.a);
        const Vec3 v = q - centre;
        const double along_u = v.dot(u);
        if (along_u < 0.0) continue;  // the other half-plane
        const double phi_deg = std::atan2(along_u, v.dot(neck_axis)) * kRadToDeg;
        const int bin = std::clamp(static_cast<int>(phi_deg / kBinDeg), 0, kBins - 1);
        const double deviation = v.norm() - radius_mm;
        if (deviation > outermost[static_cast<std::size_t>(bin)]) {
          outermost[static_cast<std::size_t>(bin)] = deviation;
          where[static_cast<std::size_t>(bin)] = q;
        }
      }
    }
  }
  // Where the walk towards the neck starts. By default at the pole (180 deg): the first bin seen
  // on the sphere. With articular_gap_deg > 0 (real bones): inside the longest run of bins on the
  // sphere, runs bridged over gaps of up to articular_gap_deg (the fovea, segmentation noise), so
  // the walk leaves the articular surface at its neck-side end, not at a pit near the pole.
  int start = kBins - 1;
  if (articular_gap_deg > 0.0) {
    const int gap = static_cast<int>(std::lround(articular_gap_deg / kBinDeg));
    int best_low = -1, best_high = -1, low = -1, high = -1, off_run = 0;
    for (int bin = kBins - 1; bin >= 0; --bin) {
      const bool on = std::abs(outermost[static_cast<std::size_t>(bin)]) <= tolerance_mm;
      if (on) {
        if (high < 0 || off_run > gap) high = bin;
        low = bin;
        off_run = 0;
        if (high - low > best_high - best_low) {
          best_low = low;
          best_high = high;
        }
      } else if (high >= 0) {
        ++off_run;
      }
    }
    if (best_low < 0) return std::numeric_limits<double>::quiet_NaN();
    start = best_low;
  }
  // Walk towards the neck; start only once the contour has been seen on the sphere, then stop at
  // the first bin that is off it (or empty: the contour left the band).
  bool on_sphere = false;
  for (int bin = start; bin >= 0; --bin) {
    const double deviation = outermost[static_cast<std::size_t>(bin)];
    const bool off = !(std::abs(deviation) <= tolerance_mm);
    if (!on_sphere) {
      on_sphere = !off;
      continue;
    }
    if (off) {
      if (departure_point != nullptr) *departure_point = where[static_cast<std::size_t>(bin)];
      const double first_deg = (bin + 0.5) * kBinDeg;
      // The first off bin lies past the true departure by tolerance / slope. Near a transversal
      // departure the deviation grows linearly, so extrapolate back to zero deviation from this
      // bin and the first one at least three tolerances off (within 3 deg, same sign).
      if (!std::isfinite(deviation)) return first_deg;
      for (int further = bin - 1; further >= std::max(0, bin - static_cast<int>(3.0 / kBinDeg)); --further) {
        const double d2 = outermost[static_cast<std::size_t>(further)];
        if (!std::isfinite(d2) || (d2 > 0.0) != (deviation > 0.0)) break;
        if (std::abs(d2) >= 3.0 * tolerance_mm) {
          const double second_deg = (further + 0.5) * kBinDeg;
          const double slope = (d2 - deviation) / (second_deg - first_deg);
          const double back_deg = first_deg - deviation / slope;
          // Never move by more than the tolerance band could explain (guards a noisy slope).
          return std::clamp(back_deg, first_deg, first_deg + 2.0);
        }
      }
      return first_deg;
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

namespace {

// The outermost vertices near the head's pole (within 60 deg of -n from the HJC, and within 1 mm
// of the farthest: the articular surface, not the bone under the cartilage).
std::vector<Vec3> head_shell(const std::vector<const TriMesh*>& femur, const Vec3& hjc_mm, const Vec3& n) {
  std::vector<Vec3> candidates;
  double farthest = 0.0;
  for (const TriMesh* mesh : femur) {
    for (const Vec3& p : mesh->vertices) {
      const Vec3 v = p - hjc_mm;
      if (v.norm() > 0.0 && -v.normalized().dot(n) >= std::cos(60.0 * kDegToRad)) {
        candidates.push_back(p);
        farthest = std::max(farthest, v.norm());
      }
    }
  }
  std::vector<Vec3> shell;
  for (const Vec3& p : candidates) {
    if ((p - hjc_mm).norm() >= farthest - 1.0) shell.push_back(p);
  }
  return shell;
}

// Longest chord of the tessellated sphere: an edge with both ends on the fitted sphere.
double longest_chord_on_sphere(const std::vector<const TriMesh*>& femur, const Vec3& centre, double radius) {
  double longest = 0.0;
  for (const TriMesh* mesh : femur) {
    auto on_sphere = [&](std::int32_t v) {
      return std::abs((mesh->vertices[static_cast<std::size_t>(v)] - centre).norm() - radius) < 0.02;
    };
    for (const Triangle& tri : mesh->triangles) {
      for (int k = 0; k < 3; ++k) {
        const auto u = tri[static_cast<std::size_t>(k)];
        const auto w = tri[static_cast<std::size_t>((k + 1) % 3)];
        if (on_sphere(u) && on_sphere(w)) {
          longest = std::max(longest, (mesh->vertices[static_cast<std::size_t>(u)] -
                                       mesh->vertices[static_cast<std::size_t>(w)]).norm());
        }
      }
    }
  }
  return longest;
}

}  // namespace

AlphaMeasurement measure_alpha_angle(const std::vector<const TriMesh*>& femur, const Vec3& hjc_mm,
                                     const Vec3& neck_axis_in, const Vec3& superior_in,
                                     const Vec3& anterior_in, const AlphaOptions& options) {
  AlphaMeasurement result;
  const Vec3 n = neck_axis_in.normalized();
  const Vec3 superior = (superior_in - superior_in.dot(n) * n).normalized();
  Vec3 anterior = (anterior_in - anterior_in.dot(n) * n - anterior_in.dot(superior) * superior).normalized();

  // 1. Head sphere from the outermost vertices near the pole.
  const std::vector<Vec3> shell = head_shell(femur, hjc_mm, n);
  if (shell.size() < 10) return result;
  // |p|^2 = 2 c . p + (r^2 - |c|^2): linear in (c, k).
  Eigen::MatrixXd a(static_cast<Eigen::Index>(shell.size()), 4);
  Eigen::VectorXd b(static_cast<Eigen::Index>(shell.size()));
  for (std::size_t i = 0; i < shell.size(); ++i) {
    const Vec3 p = shell[i] - hjc_mm;
    a.row(static_cast<Eigen::Index>(i)) << 2.0 * p.x(), 2.0 * p.y(), 2.0 * p.z(), 1.0;
    b(static_cast<Eigen::Index>(i)) = p.squaredNorm();
  }
  const Eigen::Vector4d x = a.colPivHouseholderQr().solve(b);
  const bool given = options.head_radius_mm > 0.0;
  const Vec3 centre = given ? options.head_centre_mm : Vec3(hjc_mm + x.head<3>());
  const double radius = given ? options.head_radius_mm : std::sqrt(x(3) + x.head<3>().squaredNorm());
  result.head_centre_mm = centre;
  result.head_radius_mm = radius;
  const double longest = longest_chord_on_sphere(femur, centre, radius);
  result.tolerance_mm = options.tolerance_mm > 0.0
                            ? options.tolerance_mm
                            : std::max(0.1, 1.2 * longest * longest / (6.0 * radius));

  // 2. Sweep the sector, then refine around the largest.
  auto plane_direction = [&](double angle_deg) {
    return (std::cos(angle_deg * kDegToRad) * anterior + std::sin(angle_deg * kDegToRad) * superior).normalized();
  };
  auto alpha_at = [&](double angle_deg) {
    return alpha_in_plane(femur, centre, radius, n, plane_direction(angle_deg), result.tolerance_mm, nullptr,
                          options.articular_gap_deg);
  };
  double best_alpha = -1.0;
  double best_plane = 0.0;
  auto consider = [&](double angle_deg) {
    const double alpha = alpha_at(angle_deg);
    if (std::isfinite(alpha) && alpha > best_alpha) {
      best_alpha = alpha;
      best_plane = angle_deg;
    }
  };
  for (double angle = options.sector_begin_deg; angle <= options.sector_end_deg + 1e-9; angle += 2.0) consider(angle);
  if (best_alpha >= 0.0) {
    const double coarse = best_plane;
    for (double angle = coarse - 2.0; angle <= coarse + 2.0 + 1e-9; angle += 0.25) {
      if (angle >= options.sector_begin_deg && angle <= options.sector_end_deg) consider(angle);
    }
  }
  result.max_alpha_deg = best_alpha;
  result.max_plane_deg = best_plane;
  if (options.profile_step_deg > 0.0) {
    for (double angle = -180.0 + options.profile_step_deg; angle <= 180.0 + 1e-9; angle += options.profile_step_deg) {
      result.profile.emplace_back(angle, alpha_at(angle));
      result.profile_directions.push_back(plane_direction(angle));
    }
  }
  // 3. Nötzli's plane.
  result.plane_deg = options.notzli_clock_deg;
  result.plane_direction = plane_direction(result.plane_deg);
  result.alpha_deg = alpha_in_plane(femur, centre, radius, n, result.plane_direction, result.tolerance_mm,
                                    &result.departure_point_mm, options.articular_gap_deg);
  if (!std::isfinite(result.alpha_deg)) return result;
  result.status = MeasureStatus::kOk;
  return result;
}

std::string clock_label(double clock_deg) {
  // 3 o'clock at 0 deg, one hour per 30 deg towards 12.
  double hours = 3.0 - clock_deg / 30.0;
  hours = std::fmod(std::fmod(hours, 12.0) + 12.0, 12.0);
  int whole = static_cast<int>(std::floor(hours + 1e-9));
  int minutes = static_cast<int>(std::lround((hours - whole) * 60.0));
  if (minutes == 60) {
    ++whole;
    minutes = 0;
  }
  if (whole == 0) whole = 12;
  char text[16];
  std::snprintf(text, sizeof text, "%d:%02d", whole, minutes);
  return text;
}

}  // namespace hipfai::geometry
