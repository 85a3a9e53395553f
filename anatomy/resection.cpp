// hipfai — virtual cam resection and rim trimming with curved-box cutting tools.
#include "anatomy/resection.h"

#include "anatomy/mesh_boolean.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "geometry/hip_frame.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <utility>

namespace hipfai::anatomy {
namespace {

using geometry::kDegToRad;
using geometry::kRadToDeg;
using geometry::TriMesh;
using geometry::Vec3;

// Spherical coordinates about a centre and an axis: polar angle from `axis`, clock angle from
// `e1` towards `e2` (e1, e2, axis orthonormal).
struct SphericalFrame {
  Vec3 centre = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
  Vec3 e1 = Vec3::UnitX();
  Vec3 e2 = Vec3::UnitY();

  // Clock angles that are whole multiples of 90 deg get exact sines and cosines, so that tool
  // faces at 3, 12, 9 and 6 o'clock are exactly coplanar with the frame's planes (a face off such
  // a plane by 1e-16 rad meets mesh edges lying in it almost tangentially, and rounding the
  // intersection points can then make the Boolean's result self-intersect).
  Vec3 point(double r, double polar_rad, double clock_deg) const {
    double c = std::cos(clock_deg * kDegToRad), s = std::sin(clock_deg * kDegToRad);
    const double quarters = clock_deg / 90.0;
    if (quarters == std::round(quarters)) {
      static constexpr double kCos[4] = {1.0, 0.0, -1.0, 0.0};
      const int q = static_cast<int>(std::fmod(std::fmod(quarters, 4.0) + 4.0, 4.0));
      c = kCos[q];
      s = kCos[(q + 3) % 4];
    }
    return centre + r * (std::cos(polar_rad) * axis + std::sin(polar_rad) * (c * e1 + s * e2));
  }
  double clock_deg(const Vec3& x) const {
    const Vec3 d = x - centre;
    return std::atan2(d.dot(e2), d.dot(e1)) * kRadToDeg;
  }
};

SphericalFrame make_frame(const Vec3& centre, const Vec3& axis, const Vec3& anterior, const Vec3& superior,
                          const char* what) {
  if (!centre.allFinite() || !axis.allFinite() || !anterior.allFinite() || !superior.allFinite()) {
    throw_error(what, ": the centre and axes must be finite");
  }
  if (axis.norm() < 1e-9) throw_error(what, ": the axis is zero");
  SphericalFrame frame;
  frame.centre = centre;
  frame.axis = axis.normalized();
  const Vec3 e1 = anterior - anterior.dot(frame.axis) * frame.axis;
  if (e1.norm() < 1e-6 * std::max(1.0, anterior.norm())) {
    throw_error(what, ": the anterior direction is parallel to the axis");
  }
  frame.e1 = e1.normalized();
  frame.e2 = frame.axis.cross(frame.e1);
  const double side = superior.dot(frame.e2);
  if (std::abs(side) < 1e-3 * std::max(1.0, superior.norm())) {
    throw_error(what, ": the superior direction does not pick a side of the clock face");
  }
  if (side < 0.0) frame.e2 = -frame.e2;
  return frame;
}

// Span of a clock sector in degrees, in (0, 360]; throws for an empty one.
double sector_span_deg(const ClockSector& sector, const char* what) {
  if (!std::isfinite(sector.from_deg) || !std::isfinite(sector.to_deg)) {
    throw_error(what, ": the clock sector must be finite");
  }
  const double raw = sector.to_deg - sector.from_deg;
  if (raw >= 360.0) return 360.0;
  const double span = raw - 360.0 * std::floor(raw / 360.0);  // in [0, 360)
  if (span <= 0.0) throw_error(what, ": the clock sector [", sector.from_deg, ", ", sector.to_deg, "] is empty");
  return span;
}

// Clock angle (deg) of grid column iu of nu over a sector spanning span_deg.
double clock_at(const ClockSector& sector, double span_deg, int iu, int nu) {
  return sector.from_deg + span_deg * iu / nu;
}

// The boundary of the index box [0, nu] x [0, nv] x [0, 1] mapped by `point` (see the header
// comment): u periodic when `periodic_u` (no u faces), the row v = nv collapsed to one vertex
// per w when `v_end_on_axis`. Triangles with a repeated vertex are dropped, unused vertices left
// out, and the result is oriented outward.
TriMesh curved_box(int nu, int nv, bool periodic_u, bool v_end_on_axis,
                   const std::function<Vec3(int, int, int)>& point) {
  const auto key = [&](int iu, int iv, int iw) -> std::int64_t {
    if (periodic_u && iu == nu) iu = 0;
    if (v_end_on_axis && iv == nv) iu = 0;
    return (static_cast<std::int64_t>(iw) * (nv + 1) + iv) * (nu + 1) + iu;
  };
  std::vector<std::int32_t> id(static_cast<std::size_t>(2 * (nu + 1) * (nv + 1)), -1);
  TriMesh mesh;
  const auto vertex = [&](int iu, int iv, int iw) {
    const std::int64_t k = key(iu, iv, iw);
    if (id[k] < 0) {
      if (periodic_u && iu == nu) iu = 0;
      if (v_end_on_axis && iv == nv) iu = 0;
      id[k] = static_cast<std::int32_t>(mesh.vertices.size());
      mesh.vertices.push_back(point(iu, iv, iw));
    }
    return id[k];
  };
  // A quad given counter-clockwise (seen from outside in index space) as two triangles.
  const auto quad = [&](std::array<int, 3> a, std::array<int, 3> b, std::array<int, 3> c,
                        std::array<int, 3> d) {
    const std::int32_t p[4] = {vertex(a[0], a[1], a[2]), vertex(b[0], b[1], b[2]),
                               vertex(c[0], c[1], c[2]), vertex(d[0], d[1], d[2])};
    for (const geometry::Triangle t : {geometry::Triangle{p[0], p[1], p[2]}, geometry::Triangle{p[0], p[2], p[3]}}) {
      if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) mesh.triangles.push_back(t);
    }
  };
  for (int iu = 0; iu < nu; ++iu) {
    for (int iv = 0; iv < nv; ++iv) {
      quad({iu, iv, 1}, {iu + 1, iv, 1}, {iu + 1, iv + 1, 1}, {iu, iv + 1, 1});  // w = 1
      quad({iu, iv, 0}, {iu, iv + 1, 0}, {iu + 1, iv + 1, 0}, {iu + 1, iv, 0});  // w = 0
    }
    quad({iu, nv, 0}, {iu, nv, 1}, {iu + 1, nv, 1}, {iu + 1, nv, 0});  // v = nv
    quad({iu, 0, 0}, {iu + 1, 0, 0}, {iu + 1, 0, 1}, {iu, 0, 1});      // v = 0
  }
  if (!periodic_u) {
    for (int iv = 0; iv < nv; ++iv) {
      quad({nu, iv, 0}, {nu, iv + 1, 0}, {nu, iv + 1, 1}, {nu, iv, 1});  // u = nu
      quad({0, iv, 0}, {0, iv, 1}, {0, iv + 1, 1}, {0, iv + 1, 0});      // u = 0
    }
  }
  if (geometry::signed_volume(mesh) < 0.0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  return mesh;
}

// Angular step (rad) whose grid triangles sag at most `deviation` below a sphere of radius r:
// angular circumradius <= h / sqrt(2), sag r (1 - cos(h / sqrt(2))) <= deviation.
double grid_step_rad(double r, double deviation) {
  return std::sqrt(2.0) * std::acos(1.0 - std::min(1.0, deviation / r));
}

int steps_for(double span_rad, double step_rad) {
  return std::max(1, static_cast<int>(std::ceil(span_rad / step_rad - 1e-9)));
}

std::vector<ClockBinVolume> clock_bins(const TriMesh& removed, const SphericalFrame& frame, double bin_deg) {
  const int n = static_cast<int>(std::ceil(360.0 / bin_deg - 1e-9));
  std::vector<ClockBinVolume> bins(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    bins[k].from_deg = -180.0 + k * bin_deg;
    bins[k].to_deg = std::min(180.0, -180.0 + (k + 1) * bin_deg);
  }
  const Eigen::Matrix3d projector = Eigen::Matrix3d::Identity() - frame.axis * frame.axis.transpose();
  for (std::size_t t = 0; t < removed.num_triangles(); ++t) {
    const auto& tri = removed.triangles[t];
    const Vec3 g = (removed.vertices[tri[0]] + removed.vertices[tri[1]] + removed.vertices[tri[2]]) / 3.0;
    const Vec3 field = 0.5 * projector * (g - frame.centre);
    const double flux = field.dot(0.5 * geometry::triangle_area_normal(removed, t));
    const int k = std::clamp(static_cast<int>(std::floor((frame.clock_deg(g) + 180.0) / bin_deg)), 0, n - 1);
    bins[k].removed_mm3 += flux;
  }
  return bins;
}

struct Cut {
  TriMesh kept, removed;
  double original = 0.0, kept_volume = 0.0, removed_volume = 0.0;
};

Cut cut(const TriMesh& bone, const TriMesh& tool, const char* bone_name, const char* tool_name) {
  BooleanRequest request;
  request.a = &bone;
  request.b = &tool;
  request.a_name = bone_name;
  request.b_name = tool_name;
  request.outputs = {false, true, true};
  BooleanResult booleans = compute_booleans(request);
  Cut out;
  out.original = geometry::signed_volume(bone);
  out.kept = std::move(booleans.difference);
  out.removed = std::move(booleans.intersection);
  out.kept_volume = out.kept.empty() ? 0.0 : geometry::signed_volume(out.kept);
  out.removed_volume = out.removed.empty() ? 0.0 : geometry::signed_volume(out.removed);
  return out;
}

void check_bin(double bin_deg, const char* what) {
  if (!(bin_deg > 0.0 && bin_deg <= 360.0)) throw_error(what, ": clock bin width ", bin_deg, " deg is not in (0, 360]");
}

// Checks of a cam request; returns its frame.
SphericalFrame checked_cam_frame(const CamResectionRequest& r) {
  const char* what = "cam resection";
  const double R = r.head_radius_mm, t = r.tolerance_mm, A = r.target_alpha_deg;
  if (!(R > 0.0 && std::isfinite(R))) throw_error(what, ": head radius ", R, " mm is not positive");
  if (!(t > 0.0 && t < R)) throw_error(what, ": tolerance ", t, " mm is not in (0, head radius)");
  if (!(A > 0.0 && A < 180.0)) throw_error(what, ": target alpha ", A, " deg is not in (0, 180)");
  if (!(r.outer_radius_factor * R > R + t)) {
    throw_error(what, ": outer radius ", r.outer_radius_factor, " R is not beyond R + t");
  }
  check_bin(r.clock_bin_deg, what);
  return make_frame(r.head_centre_mm, r.neck_axis, r.anterior, r.superior, what);
}

}  // namespace

constexpr double kBlendStartBelowDeg = 1.0;

TriMesh make_cam_tool(const CamResectionRequest& request) {
  const SphericalFrame frame = checked_cam_frame(request);
  const double R = request.head_radius_mm, t = request.tolerance_mm;
  const double r_in = R + 0.75 * t;  // vertices; facets sag <= t/4, so the cut lies in [R + t/2, R + 3t/4]
  const double r_out = request.outer_radius_factor * R;
  const double h = grid_step_rad(r_in, 0.25 * t);
  const double span_deg = sector_span_deg(request.sector, "cam resection");
  const double span = span_deg * kDegToRad;
  const bool periodic = span >= 2.0 * std::numbers::pi;
  // With a blend, the sphere part reaches kBlendStartBelowDeg past A: the alpha measurement finds
  // where the contour leaves the sphere by extrapolating the rising ramp back to it, which lands
  // about 1 deg above the ramp's start on these meshes, so starting it 1 deg below A keeps alpha <= A.
  const double polar_a = (request.target_alpha_deg - (request.transition_deg > 0.0 ? kBlendStartBelowDeg : 0.0)) * kDegToRad;
  const double blend = std::clamp(request.transition_deg, 0.0, request.target_alpha_deg - 2.0) * kDegToRad;
  const double polar0 = polar_a - blend;
  // Inner radius: the sphere (+ 3t/4) from A to the pole, the tangent ramp below A.
  const auto inner = [&](double polar) {
    if (polar >= polar_a || blend <= 0.0) return r_in;
    const double f = (polar_a - polar) / blend;
    return r_in + 0.9 * (r_out - r_in) * f * f;
  };
  const int nu = std::max(periodic ? 3 : 1, steps_for(span, h));
  const int nv = steps_for(std::numbers::pi - polar0, h);
  return curved_box(nu, nv, periodic, true, [&](int iu, int iv, int iw) {
    const double polar = iv == nv ? std::numbers::pi : polar0 + (std::numbers::pi - polar0) * iv / nv;
    return frame.point(iw == 0 ? inner(polar) : r_out, polar, clock_at(request.sector, span_deg, iu, nu));
  });
}

CamResection resect_cam(const CamResectionRequest& request) {
  const auto start = SteadyClock::now();
  if (request.femur == nullptr) throw_error("cam resection: the femur mesh is required");
  const SphericalFrame frame = checked_cam_frame(request);
  CamResection out;
  out.tool = make_cam_tool(request);
  Cut c = cut(*request.femur, out.tool, "femur", "cam resection tool");
  out.resected = std::move(c.kept);
  out.removed = std::move(c.removed);
  out.original_volume_mm3 = c.original;
  out.resected_volume_mm3 = c.kept_volume;
  out.removed_volume_mm3 = c.removed_volume;
  out.removed_by_clock = clock_bins(out.removed, frame, request.clock_bin_deg);
  out.seconds = seconds_since(start);
  return out;
}

double rim_polar_deg(const std::vector<RimSample>& rim, double clock_deg) {
  if (rim.empty()) throw_error("rim profile: no samples");
  const auto wrap = [](double a) { return a - 360.0 * std::floor(a / 360.0); };  // [0, 360)
  std::vector<std::pair<double, double>> s;
  s.reserve(rim.size());
  for (const auto& sample : rim) {
    if (!std::isfinite(sample.clock_deg) || !(sample.polar_deg > 0.0 && sample.polar_deg < 180.0)) {
      throw_error("rim profile: sample (", sample.clock_deg, ", ", sample.polar_deg, ") is not a clock angle "
                  "and a polar angle in (0, 180)");
    }
    s.emplace_back(wrap(sample.clock_deg), sample.polar_deg);
  }
  std::sort(s.begin(), s.end());
  if (s.size() == 1) return s.front().second;
  const double x = wrap(clock_deg);
  // The bracketing samples, going round through 360 at the ends.
  auto hi = std::upper_bound(s.begin(), s.end(), std::make_pair(x, -1.0),
                             [](const auto& a, const auto& b) { return a.first < b.first; });
  const auto lo_sample = hi == s.begin() ? s.back() : *(hi - 1);
  const auto hi_sample = hi == s.end() ? s.front() : *hi;
  double x0 = lo_sample.first, x1 = hi_sample.first, xx = x;
  if (x1 <= x0) {  // wrapped interval
    x1 += 360.0;
    if (xx < x0) xx += 360.0;
  }
  if (x1 - x0 <= 0.0) return lo_sample.second;
  const double w = (xx - x0) / (x1 - x0);
  return (1.0 - w) * lo_sample.second + w * hi_sample.second;
}

namespace {

SphericalFrame checked_rim_frame(const RimTrimRequest& r) {
  const char* what = "rim trimming";
  const double R = r.acetabular_radius_mm;
  if (!(R > 0.0 && std::isfinite(R))) throw_error(what, ": acetabular radius ", R, " mm is not positive");
  if (!(r.trim_deg > 0.0 && r.trim_deg < 90.0)) throw_error(what, ": trim ", r.trim_deg, " deg is not in (0, 90)");
  if (!(r.inner_radius_factor > 0.0 && r.outer_radius_factor > r.inner_radius_factor)) {
    throw_error(what, ": radii ", r.inner_radius_factor, " R to ", r.outer_radius_factor, " R are not increasing");
  }
  if (!(r.overreach_deg >= 0.0)) throw_error(what, ": overreach ", r.overreach_deg, " deg is negative");
  if (!(r.facet_tolerance_mm > 0.0)) throw_error(what, ": facet tolerance must be positive");
  if (r.rim.empty()) throw_error(what, ": the rim profile has no samples");
  check_bin(r.clock_bin_deg, what);
  return make_frame(r.acetabular_centre_mm, r.opening_axis, r.anterior, r.superior, what);
}

}  // namespace

TriMesh make_rim_tool(const RimTrimRequest& request) {
  const SphericalFrame frame = checked_rim_frame(request);
  const double R = request.acetabular_radius_mm;
  const double r_in = request.inner_radius_factor * R, r_out = request.outer_radius_factor * R;
  // The cut face is ruled by rays; its chord error across a clock step is largest at r_out.
  const double h = grid_step_rad(r_out, request.facet_tolerance_mm);
  const double span_deg = sector_span_deg(request.sector, "rim trimming");
  const double span = span_deg * kDegToRad;
  const bool periodic = span >= 2.0 * std::numbers::pi;
  const int nu = std::max(periodic ? 3 : 1, steps_for(span, h));
  constexpr double kMinPolarDeg = 1.0;
  std::vector<double> lo(nu + 1), hi(nu + 1);
  double widest = 0.0;
  for (int iu = 0; iu <= nu; ++iu) {
    const double clock = clock_at(request.sector, span_deg, iu, nu);
    const double rim = rim_polar_deg(request.rim, clock);
    hi[iu] = std::min(179.0, rim + request.trim_deg) * kDegToRad;
    lo[iu] = std::max(kMinPolarDeg, rim - request.overreach_deg) * kDegToRad;
    if (!(hi[iu] > lo[iu])) throw_error("rim trimming: empty polar range at clock ", clock, " deg");
    widest = std::max(widest, hi[iu] - lo[iu]);
  }
  const int nv = steps_for(widest, h);
  return curved_box(nu, nv, periodic, false, [&](int iu, int iv, int iw) {
    const double polar = lo[iu] + (hi[iu] - lo[iu]) * iv / nv;
    return frame.point(iw == 0 ? r_in : r_out, polar, clock_at(request.sector, span_deg, iu, nu));
  });
}

RimTrim trim_rim(const RimTrimRequest& request) {
  const auto start = SteadyClock::now();
  if (request.pelvis == nullptr) throw_error("rim trimming: the pelvis mesh is required");
  const SphericalFrame frame = checked_rim_frame(request);
  RimTrim out;
  out.tool = make_rim_tool(request);
  Cut c = cut(*request.pelvis, out.tool, "pelvis", "rim trimming tool");
  out.trimmed = std::move(c.kept);
  out.removed = std::move(c.removed);
  out.original_volume_mm3 = c.original;
  out.trimmed_volume_mm3 = c.kept_volume;
  out.removed_volume_mm3 = c.removed_volume;
  out.removed_by_clock = clock_bins(out.removed, frame, request.clock_bin_deg);
  out.seconds = seconds_since(start);
  return out;
}

}  // namespace hipfai::anatomy
