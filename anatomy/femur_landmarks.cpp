// hipfai — landmarks, axes and angles of a femur found on its surface alone (method: header).
#include "anatomy/femur_landmarks.h"

#include "core/error.h"
#include "core/literature.h"
#include "geometry/hip_frame.h"
#include "geometry/hjc_regions.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace hipfai::anatomy {
namespace {

using geometry::TriMesh;
using geometry::Vec3;

// One closed (or, on an open surface, open) polyline where a plane cuts the surface.
struct SectionLoop {
  double area_mm2 = 0.0;            // enclosed area (shoelace, closing the polyline if open)
  Vec3 centroid_mm = Vec3::Zero();  // area centroid
  bool closed = false;              // every crossing point had two neighbours
  bool contains_origin = false;     // encloses the plane's reference point
  std::vector<Vec3> points;         // the polyline, mm
};

// Two unit vectors completing `normal` to a right-handed orthonormal basis.
void plane_basis(const Vec3& normal, Vec3& e1, Vec3& e2) {
  const Vec3 helper = std::abs(normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = normal.cross(helper).normalized();
  e2 = normal.cross(e1);
}

// The loops where the plane through `point` with unit normal `normal` cuts `mesh`. Crossing
// points are keyed by the mesh edge they lie on, so the loops follow the surface's connectivity
// (no tolerance on coordinates). A vertex exactly on the plane counts as above it.
std::vector<SectionLoop> section_loops(const TriMesh& mesh, const Vec3& point, const Vec3& normal) {
  const std::size_t nv = mesh.num_vertices();
  std::vector<double> s(nv);
  for (std::size_t v = 0; v < nv; ++v) s[v] = (mesh.vertices[v] - point).dot(normal);
  Vec3 e1, e2;
  plane_basis(normal, e1, e2);
  std::unordered_map<std::uint64_t, std::int32_t> slot;
  std::vector<Eigen::Vector2d> xy;
  std::vector<std::array<std::int32_t, 2>> link;
  auto crossing = [&](std::int32_t a, std::int32_t b) {
    const auto lo = static_cast<std::uint64_t>(std::min(a, b)),
               hi = static_cast<std::uint64_t>(std::max(a, b));
    auto [it, inserted] = slot.try_emplace((lo << 32) | hi, static_cast<std::int32_t>(xy.size()));
    if (inserted) {
      const double sa = s[lo], sb = s[hi];
      const Vec3 q = mesh.vertices[lo] + (sa / (sa - sb)) * (mesh.vertices[hi] - mesh.vertices[lo]);
      xy.emplace_back((q - point).dot(e1), (q - point).dot(e2));
      link.push_back({-1, -1});
    }
    return it->second;
  };
  auto connect = [&](std::int32_t i, std::int32_t j) {
    auto& li = link[static_cast<std::size_t>(i)];
    (li[0] < 0 ? li[0] : li[1]) = j;
  };
  for (const auto& t : mesh.triangles) {
    const bool above[3] = {s[static_cast<std::size_t>(t[0])] >= 0.0,
                           s[static_cast<std::size_t>(t[1])] >= 0.0,
                           s[static_cast<std::size_t>(t[2])] >= 0.0};
    if (above[0] == above[1] && above[1] == above[2]) continue;
    std::int32_t ends[2];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      if (above[k] != above[(k + 1) % 3])
        ends[n++] =
            crossing(t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)]);
    }
    connect(ends[0], ends[1]);
    connect(ends[1], ends[0]);
  }
  std::vector<SectionLoop> loops;
  std::vector<char> used(xy.size(), 0);
  auto walk = [&](std::int32_t start) {
    std::vector<std::int32_t> chain{start};
    used[static_cast<std::size_t>(start)] = 1;
    std::int32_t previous = -1, current = start;
    bool closed = false;
    for (;;) {
      const auto& l = link[static_cast<std::size_t>(current)];
      std::int32_t next = l[0] != previous ? l[0] : l[1];
      if (l[0] == l[1]) next = l[0] == previous ? -1 : l[0];
      if (next < 0) break;
      if (next == start) {
        closed = true;
        break;
      }
      if (used[static_cast<std::size_t>(next)]) break;
      used[static_cast<std::size_t>(next)] = 1;
      chain.push_back(next);
      previous = current;
      current = next;
    }
    SectionLoop loop;
    loop.closed = closed && chain.size() >= 3;
    for (const auto i : chain) {
      const Eigen::Vector2d& p = xy[static_cast<std::size_t>(i)];
      loop.points.push_back(point + p.x() * e1 + p.y() * e2);
    }
    double area2 = 0.0, cx = 0.0, cy = 0.0;
    bool inside = false;
    for (std::size_t i = 0; i < chain.size(); ++i) {
      const Eigen::Vector2d& p = xy[static_cast<std::size_t>(chain[i])];
      const Eigen::Vector2d& q = xy[static_cast<std::size_t>(chain[(i + 1) % chain.size()])];
      const double cross = p.x() * q.y() - q.x() * p.y();
      area2 += cross;
      cx += (p.x() + q.x()) * cross;
      cy += (p.y() + q.y()) * cross;
      if ((p.y() > 0.0) != (q.y() > 0.0) &&
          0.0 < p.x() + (q.x() - p.x()) * (0.0 - p.y()) / (q.y() - p.y()))
        inside = !inside;
    }
    if (area2 == 0.0) return;
    loop.area_mm2 = std::abs(area2) / 2.0;
    loop.centroid_mm = point + (cx / (3.0 * area2)) * e1 + (cy / (3.0 * area2)) * e2;
    loop.contains_origin = inside;
    loops.push_back(loop);
  };
  // Open chains first (from their ends), then the closed loops.
  for (std::size_t i = 0; i < xy.size(); ++i) {
    if (!used[i] && (link[i][0] < 0 || link[i][1] < 0)) walk(static_cast<std::int32_t>(i));
  }
  for (std::size_t i = 0; i < xy.size(); ++i) {
    if (!used[i]) walk(static_cast<std::int32_t>(i));
  }
  return loops;
}

// The outermost closed loop around the plane's reference point, or null.
const SectionLoop* loop_around(const std::vector<SectionLoop>& loops) {
  const SectionLoop* best = nullptr;
  for (const auto& loop : loops) {
    if (loop.closed && loop.contains_origin && (best == nullptr || loop.area_mm2 > best->area_mm2))
      best = &loop;
  }
  return best;
}

// The largest closed loop, or null.
const SectionLoop* largest_loop(const std::vector<SectionLoop>& loops) {
  const SectionLoop* best = nullptr;
  for (const auto& loop : loops) {
    if (loop.closed && (best == nullptr || loop.area_mm2 > best->area_mm2)) best = &loop;
  }
  return best;
}

// Principal direction (largest spread) of points about `centre`, unit, sign arbitrary.
Vec3 principal_direction(const std::vector<Vec3>& points, const Vec3& centre) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) scatter += (p - centre) * (p - centre).transpose();
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(2);
}

Vec3 mean_of(const std::vector<Vec3>& points) {
  Vec3 m = Vec3::Zero();
  for (const Vec3& p : points) m += p;
  return m / static_cast<double>(std::max<std::size_t>(1, points.size()));
}

// `v` made perpendicular to unit `axis`, unit length (zero when parallel).
Vec3 perpendicular_part(const Vec3& v, const Vec3& axis) {
  const Vec3 p = v - v.dot(axis) * axis;
  const double n = p.norm();
  return n > 1e-12 ? Vec3(p / n) : Vec3::Zero();
}

double angle_deg(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * geometry::kRadToDeg;
}

struct Neck {
  Vec3 axis;
  Vec3 point;
  double area = 0.0;
  int sections = 0;
  int iterations = 0;
};

// Centre line of the narrowest neck sections (header), from the head sphere (c, R).
// Cross-sections of the bone near the head perpendicular to `axis`, at t = 0.5 R .. 2.5 R from c
// in 0.05 R steps: each one's area (-1: none, or mostly on the head's sphere) and centroid, and
// the last step with a section.
constexpr int kNeckSteps = 40;

struct NeckSections {
  std::vector<double> area = std::vector<double>(kNeckSteps + 1, -1.0);
  std::vector<Vec3> centroid = std::vector<Vec3>(kNeckSteps + 1, Vec3::Zero());
  int last = -1;
};

NeckSections neck_sections(const TriMesh& near, const Vec3& c, double r, const Vec3& axis, double head_band) {
  NeckSections sections;
  for (int i = 0; i <= kNeckSteps; ++i) {
    const double t = (0.5 + 2.0 * i / kNeckSteps) * r;
    const auto loops = section_loops(near, c + t * axis, axis);
    if (const SectionLoop* loop = loop_around(loops)) {
      // A section mostly on the head's sphere is the head, not the neck.
      std::size_t on_head = 0;
      for (const Vec3& q : loop->points)
        on_head += std::abs((q - c).norm() - r) <= head_band ? 1 : 0;
      if (2 * on_head > loop->points.size()) continue;
      sections.area[static_cast<std::size_t>(i)] = loop->area_mm2;
      sections.centroid[static_cast<std::size_t>(i)] = loop->centroid_mm;
      sections.last = i;
    }
  }
  return sections;
}

// The narrow neck: the steps of the contiguous run of sections within 10 % of the smallest area.
// Throws when there is no section, or the bone does not widen again beyond the narrowest.
std::vector<int> narrow_neck(const NeckSections& sections, double r, const std::string& what) {
  const std::vector<double>& area = sections.area;
  int narrowest = -1;
  for (int i = 0; i <= kNeckSteps; ++i) {
    if (area[static_cast<std::size_t>(i)] > 0.0 &&
        (narrowest < 0 ||
         area[static_cast<std::size_t>(i)] < area[static_cast<std::size_t>(narrowest)]))
      narrowest = i;
  }
  if (narrowest < 0)
    throw_error(
        what,
        ": no femoral neck found: no bone section around the neck direction beyond the head");
  const double a_min = area[static_cast<std::size_t>(narrowest)];
  // A neck is narrower than the head and the bone widens again beyond it (trochanters, shaft);
  // a sphere alone narrows to its pole and ends.
  if (std::sqrt(a_min / std::numbers::pi) >= r || sections.last == narrowest ||
      area[static_cast<std::size_t>(sections.last)] < 1.1 * a_min) {
    throw_error(what,
                ": no femoral neck found: the bone does not widen again beyond its narrowest "
                "section past the head");
  }
  int lo = narrowest, hi = narrowest;
  while (lo > 0 && area[static_cast<std::size_t>(lo - 1)] > 0.0 &&
         area[static_cast<std::size_t>(lo - 1)] <= 1.1 * a_min)
    --lo;
  while (hi < kNeckSteps && area[static_cast<std::size_t>(hi + 1)] > 0.0 &&
         area[static_cast<std::size_t>(hi + 1)] <= 1.1 * a_min)
    ++hi;
  std::vector<int> used;
  for (int i = lo; i <= hi; ++i) used.push_back(i);
  return used;
}

// Line through c fitted to the centroids of the `used` sections, then again without the outliers
// (centroids farther from it than 3 times the median distance: a section reaching into the flare
// of the neck's base, where a trochanter or the calcar pulls the centroid off the neck's line),
// which are dropped from `used`; oriented as `previous`.
Vec3 neck_line(const std::vector<Vec3>& centroid, const Vec3& c, double r, const Vec3& previous,
               std::vector<int>& used) {
  Vec3 axis = previous;
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const int i : used) {
      const Vec3 q = centroid[static_cast<std::size_t>(i)] - c;
      scatter += q * q.transpose();
    }
    axis = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(2);
    if (axis.dot(previous) < 0.0) axis = -axis;
    if (pass == 1) break;
    std::vector<double> residual;
    for (const int i : used)
      residual.push_back((centroid[static_cast<std::size_t>(i)] - c).cross(axis).norm());
    std::vector<double> sorted = residual;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                     sorted.end());
    const double limit = std::max(3.0 * sorted[sorted.size() / 2], 1e-6 * r);
    std::vector<int> kept;
    for (std::size_t k = 0; k < used.size(); ++k)
      if (residual[k] <= limit) kept.push_back(used[k]);
    used.swap(kept);
  }
  return axis;
}

Neck find_neck(const TriMesh& femur, const Vec3& c, double r, double head_band,
               const std::string& what) {
  // The bone near the head: sections up to 2.5 R out stay within 3.5 R of c where it matters.
  const TriMesh near =
      geometry::submesh_where(femur, [&](const Vec3& p) { return (p - c).norm() < 3.5 * r; });
  std::vector<Vec3> shell;
  for (const Vec3& p : femur.vertices) {
    const double d = (p - c).norm();
    if (d > 1.2 * r && d < 2.0 * r) shell.push_back(p);
  }
  if (shell.size() < 10) {
    throw_error(what, ": no femoral neck found: no bone between 1.2 and 2 head radii (", r,
                " mm) from the head centre");
  }
  Neck neck;
  neck.axis = (mean_of(shell) - c).normalized();
  constexpr int kMaxIterations = 30;
  for (int iteration = 1; iteration <= kMaxIterations; ++iteration) {
    const NeckSections sections = neck_sections(near, c, r, neck.axis, head_band);
    std::vector<int> used = narrow_neck(sections, r, what);
    const Vec3 axis = neck_line(sections.centroid, c, r, neck.axis, used);
    int narrow_kept = used.front();
    for (const int i : used)
      if (sections.area[static_cast<std::size_t>(i)] < sections.area[static_cast<std::size_t>(narrow_kept)])
        narrow_kept = i;
    const double change = angle_deg(axis, neck.axis);
    neck.axis = axis;
    neck.point = sections.centroid[static_cast<std::size_t>(narrow_kept)];
    neck.area = sections.area[static_cast<std::size_t>(narrow_kept)];
    neck.sections = static_cast<int>(used.size());
    neck.iterations = iteration;
    if (change < 1e-9) break;
  }
  return neck;
}

struct Shaft {
  Vec3 axis;
  Vec3 point;
  double from = 0.0, to = 0.0;  // below the head centre, mm
  int sections = 0;
  double length = 0.0;
  double diameter = 0.0;
};

// Range along `axis` (s = p . axis) of the vertices.
void extent_along(const TriMesh& mesh, const Vec3& axis, double& s_min, double& s_max) {
  s_min = std::numeric_limits<double>::infinity();
  s_max = -s_min;
  for (const Vec3& p : mesh.vertices) {
    const double s = p.dot(axis);
    s_min = std::min(s_min, s);
    s_max = std::max(s_max, s);
  }
}

// Width of the vertices with s < s_below along their largest spread perpendicular to `axis`,
// and that direction (unit, perpendicular to axis).
double distal_width(const TriMesh& mesh, const Vec3& axis, double s_below, Vec3* direction,
                    std::vector<Vec3>* region) {
  std::vector<Vec3> points;
  for (const Vec3& p : mesh.vertices) {
    if (p.dot(axis) < s_below) points.push_back(p - p.dot(axis) * axis);
  }
  if (points.size() < 3) return 0.0;
  const Vec3 e = perpendicular_part(principal_direction(points, mean_of(points)), axis);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec3& p : points) {
    lo = std::min(lo, p.dot(e));
    hi = std::max(hi, p.dot(e));
  }
  if (direction != nullptr) *direction = e;
  if (region != nullptr) {
    region->clear();
    for (const Vec3& p : mesh.vertices)
      if (p.dot(axis) < s_below) region->push_back(p);
  }
  return hi - lo;
}

// The head sphere made independent of where the search started: the vertices within
// max(min_band, 2.5 rms) of the sphere whose normals face away from its centre (within
// facing_deg) are fitted again, until that set no longer changes. find_femoral_head's band and
// patch depend on its Hough cell grid (fixed in space) and, with a hint, on the part of the mesh
// searched; the settled set depends only on the surface.
geometry::SphereFit settle_head(const TriMesh& femur, geometry::SphereFit sphere,
                                const geometry::HeadRegionOptions& options) {
  const std::vector<Vec3> normals = geometry::vertex_normals(femur);
  const double cos_facing = std::cos(options.facing_deg * geometry::kDegToRad);
  std::vector<char> previous;
  for (int round = 0; round < 50; ++round) {
    const double band = std::max(options.min_band_mm, 2.5 * sphere.rms_mm);
    std::vector<char> keep(femur.num_vertices(), 0);
    std::vector<Vec3> points;
    for (std::size_t v = 0; v < femur.num_vertices(); ++v) {
      const Vec3 d = femur.vertices[v] - sphere.center_mm;
      const double distance = d.norm();
      if (!(distance > 0.0) || std::abs(distance - sphere.radius_mm) > band) continue;
      if (normals[v].dot(d) < cos_facing * distance) continue;
      keep[v] = 1;
      points.push_back(femur.vertices[v]);
    }
    if (keep == previous) break;
    const geometry::SphereFit next = geometry::fit_sphere(points);
    if (!next.ok()) break;
    sphere = next;
    previous.swap(keep);
  }
  return sphere;
}

// The head sphere: searched near the hint when there is one (else on the whole femur), then
// settled (settle_head).
geometry::SphereFit find_head(const TriMesh& femur, const FemurLandmarksRequest& request,
                              const geometry::HeadRegionOptions& head_options) {
  const std::string& what = request.what;
  geometry::SurfaceRegion head;
  if (request.head_centre_hint_mm) {
    const Vec3 hint = *request.head_centre_hint_mm;
    const double reach = head_options.max_radius_mm + 25.0;
    const TriMesh near =
        geometry::submesh_where(femur, [&](const Vec3& p) { return (p - hint).norm() < reach; });
    if (near.empty())
      throw_error(what, ": no femoral head found: no bone within ", reach,
                  " mm of the head-centre hint");
    head = geometry::find_femoral_head(near, nullptr, head_options, what);
  } else {
    head = geometry::find_femoral_head(femur, nullptr, head_options, what);
  }
  return settle_head(femur, head.sphere, head_options);
}

// The first guess of the shaft axis: the principal direction of the bone beyond 2 head radii
// from the head centre c, pointing towards the head.
Vec3 initial_shaft_axis(const TriMesh& femur, const Vec3& c, double r, const std::string& what) {
  std::vector<Vec3> far;
  for (const Vec3& p : femur.vertices)
    if ((p - c).norm() > 2.0 * r) far.push_back(p);
  if (far.size() < 10)
    throw_error(what, ": no femoral shaft found: the bone ends within 2 head radii (", r,
                " mm) of the head centre");
  Vec3 axis = principal_direction(far, mean_of(far));
  if ((c - mean_of(far)).dot(axis) < 0.0) axis = -axis;
  return axis;
}

// Whole femur: long, and a distal end much wider than the shaft (the condyles). When not, why
// not, in `reason`.
bool has_distal_end(const TriMesh& femur, const Vec3& axis, double r, std::string& reason) {
  double s_min, s_max;
  extent_along(femur, axis, s_min, s_max);
  const double length = s_max - s_min;
  const auto mid = section_loops(femur, axis * (s_min + 0.5 * length), axis);
  const SectionLoop* mid_loop = largest_loop(mid);
  const double diameter = mid_loop ? 2.0 * std::sqrt(mid_loop->area_mm2 / std::numbers::pi) : 0.0;
  const double width = distal_width(femur, axis, s_min + 0.15 * length, nullptr, nullptr);
  std::ostringstream why;
  if (length < 8.0 * r) {
    why << "the bone is " << std::lround(length) << " mm long along its shaft, under 8 head radii ("
        << std::lround(8.0 * r) << " mm): a proximal femur";
  } else if (!(width > 2.0 * diameter)) {
    why << "its distal end is " << std::lround(width) << " mm wide, not over twice the shaft's "
        << std::lround(diameter) << " mm diameter: no condyles";
  }
  reason = why.str();
  return reason.empty();
}

// The shaft's closed cross-sections along `axis` between lo and hi (s = p . axis): area,
// centroid and height below the head centre of each section's largest loop.
struct ShaftSections {
  std::vector<double> areas;
  std::vector<Vec3> centroids;
  std::vector<double> heights;
};

ShaftSections shaft_sections(const TriMesh& femur, const Vec3& axis, const Vec3& c, double lo, double hi) {
  constexpr int kShaftSections = 30;
  const double s_c = c.dot(axis);
  ShaftSections sections;
  for (int i = 0; i <= kShaftSections; ++i) {
    const double s = lo + (hi - lo) * i / kShaftSections;
    const auto loops = section_loops(femur, axis * s + (c - s_c * axis), axis);
    if (const SectionLoop* loop = largest_loop(loops)) {
      sections.areas.push_back(loop->area_mm2);
      sections.centroids.push_back(loop->centroid_mm);
      sections.heights.push_back(s_c - s);
    }
  }
  return sections;
}

// No flare: only the sections within 25 % of the smallest.
void keep_narrowest(ShaftSections& sections) {
  if (sections.areas.empty()) return;
  const double a_min = *std::min_element(sections.areas.begin(), sections.areas.end());
  ShaftSections kept;
  for (std::size_t i = 0; i < sections.areas.size(); ++i) {
    if (sections.areas[i] <= 1.25 * a_min) {
      kept.areas.push_back(sections.areas[i]);
      kept.centroids.push_back(sections.centroids[i]);
      kept.heights.push_back(sections.heights[i]);
    }
  }
  sections = std::move(kept);
}

// One round of the shaft fit: the sections along `axis` over the diaphysis (a whole femur) or
// between the lesser trochanter's level and the head (a proximal one), and the line through
// their centroids.
Shaft fit_shaft(const TriMesh& femur, const Vec3& axis, const Vec3& c, double r, bool distal,
                const std::string& what) {
  double s_min, s_max;
  extent_along(femur, axis, s_min, s_max);
  const double length = s_max - s_min;
  const double s_c = c.dot(axis);
  double lo, hi;
  if (distal) {
    lo = s_min + literature::kDiaphysisBeginFraction * length;
    hi = s_min + literature::kDiaphysisEndFraction * length;
  } else {
    lo = s_min + 0.1 * (s_c - s_min);
    hi = s_c - 1.5 * r;
  }
  if (!(hi > lo)) {
    throw_error(what, ": no femoral shaft found: the bone ends ", std::lround(s_c - s_min),
                " mm below the head centre, within 1.5 head radii of it");
  }
  ShaftSections sections = shaft_sections(femur, axis, c, lo, hi);
  if (!distal) keep_narrowest(sections);
  if (sections.centroids.size() < 3)
    throw_error(what, ": no femoral shaft found: fewer than 3 closed shaft sections");
  const Vec3 m = mean_of(sections.centroids);
  Vec3 next = principal_direction(sections.centroids, m);
  if ((c - m).dot(next) < 0.0) next = -next;
  double mean_area = 0.0;
  for (double a : sections.areas) mean_area += a / static_cast<double>(sections.areas.size());
  Shaft shaft;
  shaft.axis = next;
  shaft.point = m;
  shaft.from = *std::min_element(sections.heights.begin(), sections.heights.end());
  shaft.to = *std::max_element(sections.heights.begin(), sections.heights.end());
  shaft.sections = static_cast<int>(sections.centroids.size());
  shaft.diameter = 2.0 * std::sqrt(mean_area / std::numbers::pi);
  return shaft;
}

// The shaft: its axis refitted through its sections' centroids a few rounds; whether the femur is
// whole (in the first round, along the first guess) goes to `out`.
Shaft find_shaft(const TriMesh& femur, const Vec3& c, double r, const std::string& what, FemurLandmarks& out) {
  constexpr int kShaftRounds = 4;
  Vec3 axis = initial_shaft_axis(femur, c, r, what);
  const bool distal = has_distal_end(femur, axis, r, out.distal_missing_reason);
  Shaft shaft;
  for (int round = 0; round < kShaftRounds; ++round) {
    shaft = fit_shaft(femur, axis, c, r, distal, what);
    axis = shaft.axis;
  }
  double s_min, s_max;
  extent_along(femur, shaft.axis, s_min, s_max);
  shaft.length = s_max - s_min;
  return shaft;
}

// The posterior condylar line: the bitangent from behind of the medial and lateral halves of the
// distal region, found by bisection on its tilt; its two contact points.
std::pair<Vec3, Vec3> posterior_condyles(const std::vector<Vec3>& region, const Vec3& knee, const Vec3& posterior,
                                         const Vec3& medial_dir) {
  auto support = [&](double theta, bool medial_half, Vec3* where) {
    const Vec3 n = std::cos(theta) * posterior + std::sin(theta) * medial_dir;
    double best = -std::numeric_limits<double>::infinity();
    for (const Vec3& p : region) {
      const double x = (p - knee).dot(medial_dir);
      if ((x > 0.0) != medial_half) continue;
      const double h = (p - knee).dot(n);
      if (h > best) {
        best = h;
        if (where) *where = p;
      }
    }
    return best;
  };
  double t_lo = -std::numbers::pi / 3.0, t_hi = std::numbers::pi / 3.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (t_lo + t_hi);
    (support(mid, true, nullptr) - support(mid, false, nullptr) < 0.0 ? t_lo : t_hi) = mid;
  }
  Vec3 medial_pc = Vec3::Zero(), lateral_pc = Vec3::Zero();
  const double theta = 0.5 * (t_lo + t_hi);
  support(theta, true, &medial_pc);
  support(theta, false, &lateral_pc);
  return {medial_pc, lateral_pc};
}

// The femoral frame's axes as found: superior and lateral always, anterior when known.
struct FemurAxes {
  Vec3 superior, lateral;
  std::optional<Vec3> anterior;
};

// A whole femur's distal landmarks (epicondyles, knee centre, posterior condyles), its mechanical
// axis and version into `out`; the frame's axes from them.
FemurAxes distal_femur(const TriMesh& femur, const Vec3& c, const Shaft& shaft, FemurLandmarks& out) {
  double s_min, s_max;
  extent_along(femur, shaft.axis, s_min, s_max);
  Vec3 e;
  std::vector<Vec3> region;
  distal_width(femur, shaft.axis, s_min + 0.15 * shaft.length, &e, &region);
  // Medial: the side of the head.
  if ((c - shaft.point).dot(e) < 0.0) e = -e;
  const auto [lo_it, hi_it] =
      std::minmax_element(region.begin(), region.end(),
                          [&](const Vec3& a, const Vec3& b) { return a.dot(e) < b.dot(e); });
  const Vec3 medial_epi = *hi_it, lateral_epi = *lo_it;
  const Vec3 knee = 0.5 * (medial_epi + lateral_epi);
  const Vec3 mech = (c - knee).normalized();
  const Vec3 medial_dir = perpendicular_part(medial_epi - lateral_epi, mech);
  Vec3 posterior = mech.cross(medial_dir);
  // Posterior: the condyles stand out from the shaft line more behind than in front.
  const Vec3 x0 = shaft.point + (knee - shaft.point).dot(shaft.axis) * shaft.axis;
  double ahead = 0.0, behind = 0.0;
  for (const Vec3& p : region) {
    const double y = (p - x0).dot(posterior);
    behind = std::max(behind, y);
    ahead = std::max(ahead, -y);
  }
  if (ahead > behind) posterior = -posterior;
  const auto [medial_pc, lateral_pc] = posterior_condyles(region, knee, posterior, medial_dir);
  out.knee_centre_mm = knee;
  out.medial_epicondyle_mm = medial_epi;
  out.lateral_epicondyle_mm = lateral_epi;
  out.medial_posterior_condyle_mm = medial_pc;
  out.lateral_posterior_condyle_mm = lateral_pc;
  out.mechanical_axis = mech;
  // Version in the plane perpendicular to the mechanical axis.
  const Vec3 to_head = -out.neck_axis;
  const Vec3 condylar = perpendicular_part(medial_pc - lateral_pc, mech);
  Vec3 ahead_dir = mech.cross(condylar);
  if (ahead_dir.dot(posterior) > 0.0) ahead_dir = -ahead_dir;
  const Vec3 head_t = to_head - to_head.dot(mech) * mech;
  out.version_deg = std::atan2(head_t.dot(ahead_dir), head_t.dot(condylar)) * geometry::kRadToDeg;
  out.side_method = "from the femur: the condyles are posterior and the head medial";
  return {mech, -medial_dir, -posterior};
}

// A proximal femur's axes: the shaft and the neck (lateral of the head), anterior only from the
// request's hint.
FemurAxes proximal_femur(const FemurLandmarksRequest& request, const Shaft& shaft, FemurLandmarks& out) {
  // Lateral: away from the head, perpendicular to the shaft.
  FemurAxes axes{shaft.axis, perpendicular_part(out.neck_axis, shaft.axis), std::nullopt};
  out.version_missing_reason = "no distal femur (" + out.distal_missing_reason + "): no posterior condylar line";
  if (request.anterior_hint) {
    const Vec3 a = perpendicular_part(*request.anterior_hint, shaft.axis);
    if (a.isZero()) {
      out.side_method = "unknown: the anterior hint is along the shaft";
    } else {
      axes.anterior = a;
      out.side_method = "from the anterior hint and the neck (lateral of the head), no distal femur";
    }
  } else {
    out.side_method = "unknown: no distal femur and no anterior hint";
  }
  return axes;
}

}  // namespace

FemurLandmarks find_femur_landmarks(const FemurLandmarksRequest& request) {
  const std::string& what = request.what;
  if (request.femur == nullptr) throw_error(what, ": no mesh given");
  const TriMesh& femur = *request.femur;
  geometry::validate_mesh(femur, what);
  FemurLandmarks out;

  const geometry::HeadRegionOptions head_options;
  const geometry::SphereFit sphere = find_head(femur, request, head_options);
  const Vec3 c = sphere.center_mm;
  const double r = sphere.radius_mm;
  out.head_centre_mm = c;
  out.head_radius_mm = r;
  out.head_fit_rms_mm = sphere.rms_mm;
  out.head_vertices = sphere.points;

  const Neck neck =
      find_neck(femur, c, r, std::max(head_options.min_band_mm, 2.5 * sphere.rms_mm), what);
  out.neck_axis = neck.axis;
  out.neck_point_mm = neck.point;
  out.neck_section_area_mm2 = neck.area;
  out.neck_sections = neck.sections;
  out.neck_iterations = neck.iterations;

  const Shaft shaft = find_shaft(femur, c, r, what, out);
  out.shaft_axis = shaft.axis;
  out.shaft_point_mm = shaft.point;
  out.shaft_from_mm = shaft.from;
  out.shaft_to_mm = shaft.to;
  out.shaft_sections = shaft.sections;
  out.length_mm = shaft.length;
  out.shaft_diameter_mm = shaft.diameter;
  out.neck_shaft_angle_deg = angle_deg(-out.neck_axis, -shaft.axis);

  out.has_distal = out.distal_missing_reason.empty();
  const FemurAxes axes = out.has_distal ? distal_femur(femur, c, shaft, out) : proximal_femur(request, shaft, out);
  if (axes.anterior) {
    out.side = axes.anterior->cross(axes.superior).dot(axes.lateral) > 0.0 ? Side::kRight : Side::kLeft;
    AnatomicalFrame frame;
    frame.origin_mm = c;
    frame.superior = axes.superior;
    frame.right = perpendicular_part(*out.side == Side::kRight ? axes.lateral : Vec3(-axes.lateral), axes.superior);
    frame.anterior = axes.superior.cross(frame.right);
    out.frame = frame;
  }
  return out;
}

}  // namespace hipfai::anatomy
