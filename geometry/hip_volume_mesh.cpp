#include "geometry/hip_volume_mesh.h"

#include "geometry/gmsh_runtime.h"
#include "geometry/mesh_parts.h"
#include "geometry/mesh_io_common.h"
#include "geometry/mesh_io_msh.h"
#include "geometry/planar_quad_mesh.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <gmsh.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <numbers>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace hipfai::geometry {
namespace {

// ---------------------------------------------------------------------------------------------
// Construction (see the header): every tissue is a single radial interval [r_near, r_far] along
// each ray from the HJC through it. The rays through the tissue form its "shadow" on the unit
// sphere; the faces through which the rays leave on the articular side project one to one onto
// that shadow, so their boundary loops bound it. The shadow is mapped to a plane by a
// stereographic projection (conformal: a size field undoes its scale, and quads keep their
// shape on the sphere), quad-meshed there by gmsh, mapped back, and every node becomes a column
// of `layers` hexahedra between the tissue's two faces along its ray.

struct TissueRecipe {
  const char* name;
  VolumeTag volume;
  bool articular_outer;      // the articular face is the far one from the HJC (femoral side)
  SurfaceTag articular;      // articular-side faces whose columns all hit the articular surface
  SurfaceTag far;            // the opposite face
  bool rim_side_bonded;      // side faces lying in the acetabular rim plane are kLabrumBonded
};

constexpr std::array<TissueRecipe, 3> kRecipes{{
    {"femoral_cartilage", VolumeTag::kFemoralCartilage, true,
     SurfaceTag::kFemoralCartilageArticular, SurfaceTag::kFemoralCartilageBonded, false},
    {"acetabular_cartilage", VolumeTag::kAcetabularCartilage, false,
     SurfaceTag::kAcetabularCartilageArticular, SurfaceTag::kAcetabularCartilageBonded, false},
    {"labrum", VolumeTag::kLabrum, false, SurfaceTag::kLabrumArticular, SurfaceTag::kFree, true},
}};

// Faces this close to containing the ray direction (|n . d| below it) have no extent in the
// shadow (the rim-plane faces through the HJC): they bound neither side.
constexpr double kGrazingCosine = 1e-4;
// Length scale of the rim-cone membership tolerance (1e-6 of it), of the order of the joint.
constexpr double kRimToleranceScaleMm = 25.0;
// A face whose normal is within 45 deg of the ray counts as "radial" (the articular sphere, the
// bone shells), steeper ones are side walls (fossa, notch): columns hitting a wall are not
// articular.
constexpr double kRadialCosine = 0.7071067811865476;
// Barycentric slack of the ray-triangle test (relative): rays through a shared edge or vertex
// must hit at least one of its triangles.
constexpr double kBarycentricSlack = 1e-9;
// Slack for rays along the rim cone against faces looking at the HJC: a boundary chord of a
// sphere sits within about e / (8 r) of the cone in barycentric terms (1 % at 2 mm on 25 mm).
constexpr double kRimRaySlack = 0.05;

const Vec3& vertex(const TriMesh& mesh, std::int32_t index) {
  return mesh.vertices[static_cast<std::size_t>(index)];
}

// --- ray casting --------------------------------------------------------------------------------

// Per-triangle data for rays from the HJC: a cone of directions bounding the triangle culls
// most tests.
struct RayCaster {
  const TriMesh* mesh = nullptr;
  Vec3 origin = Vec3::Zero();
  std::vector<Vec3> cone_axis;
  std::vector<double> cone_cos;
  std::vector<Vec3> unit_normal;

  std::vector<bool> ignored;  // side faces the rays graze (the rim cone), never crossed

  RayCaster(const TriMesh& tissue, const Vec3& hjc, std::vector<bool> ignore = {})
      : mesh(&tissue), origin(hjc), ignored(std::move(ignore)) {
    ignored.resize(tissue.triangles.size(), false);
    const std::size_t count = tissue.triangles.size();
    cone_axis.resize(count);
    cone_cos.resize(count);
    unit_normal.resize(count);
    for (std::size_t t = 0; t < count; ++t) {
      const auto& tri = tissue.triangles[t];
      Vec3 axis = Vec3::Zero();
      for (int k = 0; k < 3; ++k) axis += (vertex(tissue, tri[k]) - hjc).normalized();
      axis.normalize();
      double widest = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double cosine = std::clamp(axis.dot((vertex(tissue, tri[k]) - hjc).normalized()), -1.0, 1.0);
        widest = std::max(widest, std::acos(cosine));
      }
      cone_axis[t] = axis;
      cone_cos[t] = std::cos(std::min(std::numbers::pi, widest + 1e-6));
      unit_normal[t] = triangle_unit_normal(tissue, t);
    }
  }

  struct Interval {
    bool hit = false;
    double near_mm = std::numeric_limits<double>::infinity();
    double far_mm = -std::numeric_limits<double>::infinity();
    double near_radial = 0.0;  // largest |n . d| among the faces hit at near_mm / far_mm
    double far_radial = 0.0;
  };

  // First and last crossing of the ray origin + t d (d unit) with the surface. `radial_slack`:
  // barycentric slack for faces that look at the HJC (|n . d| >= kRadialCosine), whose hits are
  // interpolated on the surface the triangles sample; larger than kBarycentricSlack only for rays
  // along a rim, which may pass just outside the chords of a sphere's boundary edge.
  Interval cast(const Vec3& direction, double radial_slack = kBarycentricSlack) const {
    Interval interval;
    std::vector<std::pair<double, double>> hits;  // (t, n . d)
    for (std::size_t t = 0; t < cone_axis.size(); ++t) {
      if (ignored[t] || direction.dot(cone_axis[t]) < cone_cos[t]) continue;
      const auto& tri = mesh->triangles[t];
      const Vec3 a = vertex(*mesh, tri[0]) - origin;
      const Vec3 e1 = vertex(*mesh, tri[1]) - origin - a;
      const Vec3 e2 = vertex(*mesh, tri[2]) - origin - a;
      // Moeller-Trumbore with the slack above.
      const Vec3 p = direction.cross(e2);
      const double det = e1.dot(p);
      if (std::abs(det) < 1e-14 * e1.norm() * e2.norm()) continue;  // ray in the triangle's plane
      const double facing = unit_normal[t].dot(direction);
      const double slack = std::abs(facing) >= kRadialCosine ? radial_slack : kBarycentricSlack;
      const Vec3 s = -a;
      const double u = s.dot(p) / det;
      if (u < -slack || u > 1.0 + slack) continue;
      const Vec3 q = s.cross(e1);
      const double v = direction.dot(q) / det;
      if (v < -slack || u + v > 1.0 + slack) continue;
      double distance = e2.dot(q) / det;
      if (distance <= 0.0) continue;
      // On a face that looks at the HJC, the node goes where the surface the triangles sample
      // is, not onto the chord: the vertices' distances from the HJC interpolated with the hit's
      // barycentric coordinates (for rays from the HJC these are those of the central
      // projection, so the interpolation is continuous across shared edges). Exact for a sphere
      // about the HJC — the articular and bone spheres of the generated hips, whose faceted
      // triangles dip e^2 / (6 r) below them (27 um at 2 mm on 25 mm: a quarter of the head's
      // travel under load, and a gap error that refining the FE mesh would not remove). Side
      // walls keep the planar hit.
      if (std::abs(facing) >= kRadialCosine) {
        distance = (1.0 - u - v) * a.norm() + u * (a + e1).norm() + v * (a + e2).norm();
      }
      hits.emplace_back(distance, facing);
    }
    if (hits.empty()) return interval;
    interval.hit = true;
    for (const auto& [distance, facing] : hits) {
      interval.near_mm = std::min(interval.near_mm, distance);
      interval.far_mm = std::max(interval.far_mm, distance);
    }
    // Crossings at the same point (a shared edge) within rounding: the most radial face wins, so
    // a column on the rim of the articular face still counts as articular.
    const double same = 1e-9 * interval.far_mm;
    for (const auto& [distance, facing] : hits) {
      if (distance <= interval.near_mm + same && facing < 0.0) interval.near_radial = std::max(interval.near_radial, -facing);
      if (distance >= interval.far_mm - same && facing > 0.0) interval.far_radial = std::max(interval.far_radial, facing);
    }
    return interval;
  }
};

// --- the shadow's boundary -------------------------------------------------------------------

// Boundary loops (vertex indices, closed implicitly) of the triangles in `selected`.
std::vector<std::vector<std::int32_t>> boundary_loops(const TriMesh& mesh,
                                                      const std::vector<std::size_t>& selected,
                                                      const std::string& name) {
  auto key = [](std::int32_t u, std::int32_t v) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(u)) << 32) | static_cast<std::uint32_t>(v);
  };
  std::unordered_set<std::uint64_t> directed;
  for (std::size_t t : selected) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) directed.insert(key(tri[k], tri[(k + 1) % 3]));
  }
  std::unordered_multimap<std::int32_t, std::int32_t> next;
  for (std::size_t t : selected) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::int32_t u = tri[k];
      const std::int32_t v = tri[(k + 1) % 3];
      if (!directed.contains(key(v, u))) next.emplace(u, v);
    }
  }
  std::vector<std::vector<std::int32_t>> loops;
  while (!next.empty()) {
    const std::int32_t start = next.begin()->first;
    std::vector<std::int32_t> loop{start};
    std::int32_t at = start;
    while (true) {
      const auto it = next.find(at);
      if (it == next.end()) throw_error("hip volume mesh: ", name, ": the articular face has an open boundary");
      at = it->second;
      next.erase(it);
      if (at == start) break;
      loop.push_back(at);
    }
    if (loop.size() >= 3) loops.push_back(std::move(loop));
  }
  if (loops.empty()) throw_error("hip volume mesh: ", name, ": the articular face has no boundary");
  return loops;
}

// Stereographic projection of directions about `centre` onto the tangent plane, scaled to the
// sphere of radius `radius_mm` (lengths near the centre are true lengths on that sphere).
struct Stereographic {
  Vec3 centre, u, v;
  double radius_mm = 1.0;

  Eigen::Vector2d project(const Vec3& direction) const {
    const double denominator = 1.0 + direction.dot(centre);
    return 2.0 * radius_mm * Eigen::Vector2d(direction.dot(u), direction.dot(v)) / denominator;
  }
  Vec3 unproject(const Eigen::Vector2d& point) const {
    const Eigen::Vector2d q = point / (2.0 * radius_mm);
    const double s = q.squaredNorm();
    return ((2.0 * q.x()) * u + (2.0 * q.y()) * v + (1.0 - s) * centre) / (1.0 + s);
  }
};

// Centre of projection: among the mean direction and the principal directions of the shadow
// (a ring-shaped shadow such as the labrum's is centred on its axis, not on its mean), the one
// with the smallest largest angle to the shadow, which keeps the projection's scale lowest.
Stereographic choose_projection(const std::vector<Vec3>& directions, double radius_mm,
                                const std::string& name) {
  Vec3 mean = Vec3::Zero();
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  for (const Vec3& d : directions) {
    mean += d;
    moment += d * d.transpose();
  }
  std::vector<Vec3> candidates;
  if (mean.norm() > 1e-9) candidates.push_back(mean.normalized());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(moment);
  for (int k = 0; k < 3; ++k) {
    candidates.push_back(solver.eigenvectors().col(k));
    candidates.push_back(-solver.eigenvectors().col(k));
  }
  Vec3 best = candidates.front();
  double best_cos = -2.0;
  for (const Vec3& c : candidates) {
    double lowest = 1.0;
    for (const Vec3& d : directions) lowest = std::min(lowest, c.dot(d));
    if (lowest > best_cos) {
      best_cos = lowest;
      best = c;
    }
  }
  // Beyond 150 deg from the centre the projection stretches lengths more than 15-fold.
  const double limit_cos = std::cos(150.0 * std::numbers::pi / 180.0);
  if (best_cos < limit_cos) {
    // None of the candidates will do (a wide tissue seen from one side, e.g. a segmented head's
    // cartilage): the centre of the smallest cap holding every direction, approached by moving
    // towards the farthest direction with shrinking steps (Badoiu and Clarkson's iteration).
    Vec3 centre = best;
    for (int k = 1; k <= 2000; ++k) {
      const Vec3* farthest = &directions.front();
      for (const Vec3& d : directions) {
        if (centre.dot(d) < centre.dot(*farthest)) farthest = &d;
      }
      const Vec3 moved = centre + (*farthest - centre) / (k + 1.0);
      if (moved.norm() < 1e-12) break;  // the farthest direction opposite the centre: no cap to find
      centre = moved.normalized();
      double lowest = 1.0;
      for (const Vec3& d : directions) lowest = std::min(lowest, centre.dot(d));
      if (lowest > best_cos) {
        best_cos = lowest;
        best = centre;
      }
    }
  }
  if (best_cos < limit_cos) {
    throw_error("hip volume mesh: ", name, ": the tissue surrounds the HJC (no projection centre within 150 deg of all of it: ",
                std::acos(best_cos) * 180.0 / std::numbers::pi, " deg at best)");
  }
  Stereographic projection;
  projection.centre = best;
  const Vec3 hint = std::abs(best.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  projection.u = (hint - hint.dot(best) * best).normalized();
  projection.v = best.cross(projection.u);
  projection.radius_mm = radius_mm;
  return projection;
}

// A closed polyline by arc length: arc[k] at vertex k (arc[n] = the whole loop), and the point at
// any arc length (periodic).
struct ArcLengthLoop {
  const std::vector<Vec3>& points;
  std::vector<double> arc;
  explicit ArcLengthLoop(const std::vector<Vec3>& loop) : points(loop), arc(loop.size() + 1, 0.0) {
    const std::size_t n = loop.size();
    for (std::size_t k = 0; k < n; ++k) arc[k + 1] = arc[k] + (loop[(k + 1) % n] - loop[k]).norm();
  }
  double perimeter() const { return arc.back(); }
  Vec3 at(double position) const {
    const std::size_t n = points.size();
    position = std::fmod(std::fmod(position, perimeter()) + perimeter(), perimeter());
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), position) - arc.begin()) - 1;
    const std::size_t edge = std::min(k, n - 1);
    const double length = arc[edge + 1] - arc[edge];
    const double fraction = length > 0.0 ? (position - arc[edge]) / length : 0.0;
    return Vec3(points[edge] + fraction * (points[(edge + 1) % n] - points[edge]));
  }
};

// The loop averaged over `window_mm` of arc length about each of its vertices (a moving average
// along the curve): a zigzag shorter than the window is flattened to its middle line.
std::vector<Vec3> smooth_loop(const std::vector<Vec3>& points, double window_mm) {
  const ArcLengthLoop loop(points);
  if (!(loop.perimeter() > 0.0)) return points;
  const double half = 0.5 * std::min(window_mm, 0.25 * loop.perimeter());
  constexpr int kSamples = 16;
  std::vector<Vec3> smoothed(points.size(), Vec3::Zero());
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k <= kSamples; ++k) smoothed[i] += loop.at(loop.arc[i] - half + 2.0 * half * k / kSamples);
    smoothed[i] /= kSamples + 1;
  }
  return smoothed;
}

// Resamples a closed polyline at about `spacing_mm` (arc length), keeping its sharp corners,
// with an even number of points so that the enclosed domain can be meshed with quadrangles only.
// The new points lie on the polyline's edges: rays from the HJC through them meet the surface
// (for a smoothed loop, smooth_loop, they lie near it: the columns cast their own rays).
std::vector<Vec3> resample_loop(const std::vector<Vec3>& points, double spacing_mm) {
  const std::size_t n = points.size();
  const ArcLengthLoop loop(points);
  const std::vector<double>& arc = loop.arc;
  const double perimeter = loop.perimeter();
  auto point_at = [&](double position) { return loop.at(position); };
  // Corners: where the curve turns more than 40 deg over half a spacing on either side. Measured
  // over that stretch, a faceted smooth curve (a few degrees per edge) or a jagged one (the
  // selection of faces along a side wall) does not count; where two surfaces meet (the cam circle
  // and the cartilage edge, the labrum's tip and its notch face) it does. One corner per stretch.
  constexpr double kCornerRad = 40.0 * std::numbers::pi / 180.0;
  const double reach = std::min(0.5 * spacing_mm, 0.25 * perimeter);
  std::vector<double> turning(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 before = points[i] - point_at(arc[i] - reach);
    const Vec3 after = point_at(arc[i] + reach) - points[i];
    turning[i] = std::acos(std::clamp(before.normalized().dot(after.normalized()), -1.0, 1.0));
  }
  std::vector<std::size_t> corners;
  for (std::size_t i = 0; i < n; ++i) {
    if (turning[i] <= kCornerRad) continue;
    bool largest = true;
    for (std::size_t j = 0; j < n && largest; ++j) {
      const double gap = std::abs(arc[j] - arc[i]);
      const double distance = std::min(gap, perimeter - gap);
      if (j != i && distance < reach && (turning[j] > turning[i] || (turning[j] == turning[i] && j < i))) largest = false;
    }
    if (largest) corners.push_back(i);
  }
  if (corners.empty()) corners.push_back(0);
  // Pieces between consecutive corners: arc lengths and segment counts.
  struct Piece {
    std::size_t first = 0, edges = 0;
    double length = 0.0;
    std::size_t segments = 1;
  };
  std::vector<Piece> pieces;
  for (std::size_t c = 0; c < corners.size(); ++c) {
    Piece piece;
    piece.first = corners[c];
    const std::size_t last = c + 1 < corners.size() ? corners[c + 1] : corners[0] + n;
    piece.edges = last - piece.first;
    for (std::size_t k = piece.first; k < last; ++k) piece.length += (points[(k + 1) % n] - points[k % n]).norm();
    piece.segments = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(piece.length / spacing_mm)));
    pieces.push_back(piece);
  }
  std::size_t total = 0;
  for (const auto& piece : pieces) total += piece.segments;
  if (total < 4) {
    pieces.front().segments += 4 - total;
    total = 4;
  }
  if (total % 2 == 1) {
    // The piece whose segments deviate most from the spacing takes one more.
    std::size_t worst = 0;
    double worst_ratio = 0.0;
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      const double ratio = pieces[k].length / spacing_mm / static_cast<double>(pieces[k].segments);
      if (ratio > worst_ratio) {
        worst_ratio = ratio;
        worst = k;
      }
    }
    ++pieces[worst].segments;
  }
  std::vector<Vec3> resampled;
  for (const auto& piece : pieces) {
    std::size_t edge = 0;
    double walked = 0.0;  // arc length at the start of `edge`
    for (std::size_t s = 0; s < piece.segments; ++s) {
      const double target = piece.length * static_cast<double>(s) / static_cast<double>(piece.segments);
      while (edge + 1 < piece.edges) {
        const double length = (points[(piece.first + edge + 1) % n] - points[(piece.first + edge) % n]).norm();
        if (walked + length > target) break;
        walked += length;
        ++edge;
      }
      const Vec3& a = points[(piece.first + edge) % n];
      const Vec3& b = points[(piece.first + edge + 1) % n];
      const double length = (b - a).norm();
      const double fraction = length > 0.0 ? std::clamp((target - walked) / length, 0.0, 1.0) : 0.0;
      resampled.push_back(a + fraction * (b - a));
    }
  }
  return resampled;
}

// --- gmsh ----------------------------------------------------------------------------------

// gmsh's runtime is process-wide and shared with the hip generator (geometry/gmsh_runtime.h).
// Every option changed here is restored on exit, so the generator's surface meshes are
// not recombined into quads after a volume mesh.
class GmshQuadSession {
 public:
  GmshQuadSession() : lock_(lock_gmsh()) {
    for (const char* name : kOptions) {
      double value = 0.0;
      gmsh::option::getNumber(name, value);
      saved_.emplace_back(name, value);
    }
    gmsh::clear();
    gmsh::model::add("hipfai-hip-volume");
  }
  ~GmshQuadSession() {
    try {
      gmsh::clear();
      for (const auto& [name, value] : saved_) gmsh::option::setNumber(name, value);
    } catch (...) {
    }
  }
  GmshQuadSession(const GmshQuadSession&) = delete;
  GmshQuadSession& operator=(const GmshQuadSession&) = delete;

  static constexpr std::array<const char*, 13> kOptions{
      "General.Terminal", "General.NumThreads", "General.AbortOnError", "Mesh.Algorithm", "Mesh.RecombineAll",
      "Mesh.RecombinationAlgorithm", "Mesh.SubdivisionAlgorithm", "Mesh.MeshSizeExtendFromBoundary",
      "Mesh.MeshSizeFromPoints", "Mesh.MeshSizeFromCurvature", "Mesh.MeshSizeMin", "Mesh.MeshSizeMax",
      "Mesh.Smoothing"};

 private:
  std::unique_lock<std::mutex> lock_;
  std::vector<std::pair<std::string, double>> saved_;
};

// Quad mesh of the plane domain bounded by `loops` (the first is the outer one), with mesh size
// size_mm * (1 + |p|^2 / (4 radius^2)) — the stereographic scale — so edges come out near
// size_mm on the sphere.
// One way of asking gmsh for quadrangles: triangulation algorithm, recombination algorithm, the
// boundary spacing relative to the edge length, and whether every element is split into
// quadrangles afterwards. Blossom recombination needs a perfect matching of the triangles, which
// a sharp corner of the domain (the horns of the horseshoe) can prevent; another boundary
// spacing usually has one. Subdivision (the triangles' ears along the outline flipped, then
// every triangle split into three quads, see planar_quad_mesh.h) is all-quad always, at the
// price of more nodes and less regular quads: the last resort.
struct QuadAttempt {
  int algorithm;
  int recombination;
  double spacing;
  bool subdivide;
};
// Frontal-Delaunay (6), Delaunay (5), MeshAdapt (1), each recombined by Blossom (1). The
// frontal-quad algorithm (8) crashes in gmsh 4.8 with a background size field
// (MElementOctree::find from backgroundMesh::getAngle).
constexpr std::array<QuadAttempt, 12> kQuadAttempts{{{6, 1, 1.0, false}, {5, 1, 1.0, false},
                                                     {6, 1, 0.93, false}, {5, 1, 0.93, false},
                                                     {6, 1, 1.07, false}, {5, 1, 1.07, false},
                                                     {6, 1, 0.87, false}, {5, 1, 0.87, false},
                                                     {6, 1, 1.15, false}, {5, 1, 1.15, false},
                                                     {6, 1, 2.0, true}, {5, 1, 2.0, true}}};

PlanarQuadMesh mesh_plane_domain(const std::vector<std::vector<Eigen::Vector2d>>& loops, double size_mm,
                                 double radius_mm, const QuadAttempt& attempt) {
  const bool subdivide = attempt.subdivide;
  namespace geo = gmsh::model::geo;
  GmshQuadSession session;
  gmsh::option::setNumber("General.Terminal", std::getenv("HIPFAI_GMSH_VERBOSE") != nullptr ? 1 : 0);
  std::vector<int> curve_loops;
  std::vector<int> lines;
  for (const auto& loop : loops) {
    std::vector<int> points;
    for (const auto& p : loop) points.push_back(geo::addPoint(p.x(), p.y(), 0.0, size_mm));
    std::vector<int> loop_lines;
    for (std::size_t i = 0; i < points.size(); ++i) {
      loop_lines.push_back(geo::addLine(points[i], points[(i + 1) % points.size()]));
    }
    lines.insert(lines.end(), loop_lines.begin(), loop_lines.end());
    curve_loops.push_back(geo::addCurveLoop(loop_lines));
  }
  geo::addPlaneSurface(curve_loops);
  geo::synchronize();
  // Without subdivision the loop points are the boundary nodes (an even number per loop).
  if (!subdivide) {
    for (int line : lines) gmsh::model::mesh::setTransfiniteCurve(line, 2);
  }
  const double scale = subdivide ? 2.0 : 1.0;  // subdivision halves every edge
  std::ostringstream expression;
  expression.precision(17);
  expression << scale * size_mm << "*(1+(x*x+y*y)/" << 4.0 * radius_mm * radius_mm << ")";
  const int field = gmsh::model::mesh::field::add("MathEval");
  gmsh::model::mesh::field::setString(field, "F", expression.str());
  gmsh::model::mesh::field::setAsBackgroundMesh(field);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.MeshSizeMin", 0.0);
  gmsh::option::setNumber("Mesh.MeshSizeMax", 1e22);
  gmsh::option::setNumber("General.NumThreads", 1);
  gmsh::option::setNumber("Mesh.Algorithm", attempt.algorithm);
  gmsh::option::setNumber("Mesh.RecombineAll", subdivide ? 0 : 1);
  gmsh::option::setNumber("Mesh.RecombinationAlgorithm", attempt.recombination);
  gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", 0);
  gmsh::option::setNumber("Mesh.Smoothing", 5);
  // The mesher reports errors from inside OpenMP regions, where a thrown exception would end the
  // process: let it log them; a failed attempt shows as missing or non-quad elements.
  gmsh::option::setNumber("General.AbortOnError", 0);
  try {
    gmsh::model::mesh::generate(2);
  } catch (const std::exception&) {
    return {};  // the next attempt may succeed
  }

  PlanarTriMesh triangulation;
  PlanarQuadMesh result;
  std::vector<std::size_t> tags;
  std::vector<double> coords, parametric;
  gmsh::model::mesh::getNodes(tags, coords, parametric, -1, -1, true, false);
  std::unordered_map<std::size_t, std::int32_t> index_of;
  for (std::size_t i = 0; i < tags.size(); ++i) {
    index_of.emplace(tags[i], static_cast<std::int32_t>(result.nodes.size()));
    result.nodes.emplace_back(coords[3 * i], coords[3 * i + 1]);
  }
  result.on_boundary.assign(result.nodes.size(), false);
  for (int dim : {0, 1}) {
    std::vector<std::size_t> boundary_tags;
    gmsh::model::mesh::getNodes(boundary_tags, coords, parametric, dim, -1, true, false);
    for (std::size_t tag : boundary_tags) result.on_boundary[static_cast<std::size_t>(index_of.at(tag))] = true;
  }
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> element_tags, node_tags;
  gmsh::model::mesh::getElements(types, element_tags, node_tags, 2, -1);
  for (std::size_t k = 0; k < types.size(); ++k) {
    if (subdivide && types[k] == 2) {
      for (std::size_t i = 0; i + 2 < node_tags[k].size(); i += 3) {
        std::array<std::int32_t, 3> triangle{};
        for (std::size_t c = 0; c < 3; ++c) triangle[c] = index_of.at(node_tags[k][i + c]);
        triangulation.triangles.push_back(triangle);
      }
      continue;
    }
    if (types[k] != 3 || subdivide) {
      if (element_tags[k].empty()) continue;
      result.quads.clear();  // triangles left: the caller retries with subdivision
      return result;
    }
    for (std::size_t i = 0; i + 3 < node_tags[k].size(); i += 4) {
      std::array<std::int32_t, 4> quad{};
      for (int c = 0; c < 4; ++c) quad[static_cast<std::size_t>(c)] = index_of.at(node_tags[k][i + static_cast<std::size_t>(c)]);
      // Signed area: the loops' orientation decides gmsh's, make every quad counter-clockwise.
      double area = 0.0;
      for (int c = 0; c < 4; ++c) {
        const auto& p = result.nodes[static_cast<std::size_t>(quad[static_cast<std::size_t>(c)])];
        const auto& q = result.nodes[static_cast<std::size_t>(quad[static_cast<std::size_t>((c + 1) % 4)])];
        area += p.x() * q.y() - q.x() * p.y();
      }
      if (area < 0.0) std::swap(quad[1], quad[3]);
      result.quads.push_back(quad);
    }
  }
  if (!subdivide) return result;
  triangulation.nodes = std::move(result.nodes);
  triangulation.on_boundary = std::move(result.on_boundary);
  for (auto& triangle : triangulation.triangles) {
    const Eigen::Vector2d& a = triangulation.nodes[static_cast<std::size_t>(triangle[0])];
    const Eigen::Vector2d u = triangulation.nodes[static_cast<std::size_t>(triangle[1])] - a;
    const Eigen::Vector2d w = triangulation.nodes[static_cast<std::size_t>(triangle[2])] - a;
    if (u.x() * w.y() - u.y() * w.x() < 0.0) std::swap(triangle[1], triangle[2]);
  }
  flip_flat_boundary_ears(triangulation);
  return split_into_quads(triangulation);
}

// Closest point to the line through the HJC along `direction` on the polyline edges of `loops`.
// The rim cone {d : d . axis = |d| cos_angle} through the HJC (a plane when cos_angle = 0).
struct RimCone {
  Vec3 axis = Vec3::UnitX();
  double cos_angle = 0.0;
  bool contains(const Vec3& d) const { return std::abs(d.normalized().dot(axis) - cos_angle) < 1e-9; }
  // The direction of `d` turned within its meridian plane onto the cone.
  Vec3 onto(const Vec3& d) const {
    const Vec3 across = d - d.dot(axis) * axis;
    if (across.norm() == 0.0) return d;
    const double sin_angle = std::sqrt(std::max(0.0, 1.0 - cos_angle * cos_angle));
    return d.norm() * (cos_angle * axis + sin_angle * across.normalized());
  }
};

// The point of the loops nearest to the ray along `direction`. With `rim`: a point on a loop
// segment whose two ends lie on the rim cone (a chord of the rim circle) is moved onto the cone,
// so the columns of the rim lie on the rim face exactly, as they do on a plane rim.
Vec3 snap_to_boundary(const std::vector<std::vector<Vec3>>& loops, const Vec3& direction,
                      const RimCone* rim = nullptr) {
  Vec3 best = Vec3::Zero();
  bool best_on_rim = false;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const auto& loop : loops) {
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Vec3& a = loop[i];
      const Vec3 edge = loop[(i + 1) % loop.size()] - a;
      // Distance to the line: |P (a + l edge)| with P = I - d d^T; minimise over l in [0, 1].
      const Vec3 pa = a - a.dot(direction) * direction;
      const Vec3 pe = edge - edge.dot(direction) * direction;
      const double denominator = pe.squaredNorm();
      const double l = denominator > 0.0 ? std::clamp(-pa.dot(pe) / denominator, 0.0, 1.0) : 0.0;
      const Vec3 point = a + l * edge;
      if (point.dot(direction) <= 0.0) continue;
      const double distance = (pa + l * pe).norm();
      if (distance < best_distance) {
        best_distance = distance;
        best = point;
        best_on_rim = rim != nullptr && rim->contains(a) && rim->contains(a + edge);
      }
    }
  }
  return best_on_rim ? rim->onto(best) : best;
}

// Quad mesh of the shadow bounded by `loops_3d` (relative to the HJC) in the projection plane:
// the first of kQuadAttempts good enough, else the best of the all-quad ones.
PlanarQuadMesh quad_mesh_shadow(const std::vector<std::vector<Vec3>>& loops_3d, const Stereographic& projection,
                                double edge_mm, const std::string& name) {
  // Loops resampled at the spacing and projected, outer loop first.
  auto plane_loops = [&](double spacing_mm) {
    std::vector<std::vector<Eigen::Vector2d>> plane;
    std::vector<double> areas;
    for (const auto& points : loops_3d) {
      std::vector<Eigen::Vector2d> loop;
      for (const Vec3& point : resample_loop(points, spacing_mm)) loop.push_back(projection.project(point.normalized()));
      double area = 0.0;
      for (std::size_t i = 0; i < loop.size(); ++i) {
        const auto& p = loop[i];
        const auto& q = loop[(i + 1) % loop.size()];
        area += 0.5 * (p.x() * q.y() - q.x() * p.y());
      }
      plane.push_back(std::move(loop));
      areas.push_back(std::abs(area));
    }
    const auto outer = std::max_element(areas.begin(), areas.end()) - areas.begin();
    std::swap(plane[0], plane[static_cast<std::size_t>(outer)]);
    return plane;
  };
  PlanarQuadMesh plane;
  double plane_quality = -std::numeric_limits<double>::infinity();
  int successes = 0;
  for (const auto& attempt : kQuadAttempts) {
    // Subdivision only when recombination never gave all quads.
    if (attempt.subdivide && successes > 0) break;
    const double spacing_mm = attempt.spacing * edge_mm;
    PlanarQuadMesh candidate = mesh_plane_domain(plane_loops(spacing_mm), edge_mm, projection.radius_mm, attempt);
    if (candidate.quads.empty()) continue;
    ++successes;
    open_flat_boundary_corners(candidate);
    const double quality = planar_quality(candidate);
    if (quality > plane_quality) {
      plane_quality = quality;
      plane = std::move(candidate);
    }
    // Corner angles within 30..150 deg are good enough; otherwise the best of a few meshes
    // (each costs seconds at 1 mm edges).
    if (plane_quality >= 0.5 || successes >= 4) break;
  }
  if (plane.quads.empty()) throw_error("hip volume mesh: ", name, ": gmsh could not mesh the articular face with quadrangles");

  return plane;
}

// --- one tissue ------------------------------------------------------------------------------

// The tissue's faces on the rim cone. They are radial (the cone's apex is the HJC), but their
// flat triangles only approximate the cone, so their facing is not exactly zero and rays along
// the rim graze them: they are recognised by their vertices, belong to neither side, and rays
// ignore them (as they ignore a plane rim through the HJC, which contains the rays).
std::vector<bool> rim_cone_faces(const TriMesh& tissue, const Vec3& hjc, const RimCone& rim) {
  const double rim_tolerance = 1e-6 * kRimToleranceScaleMm;
  std::vector<bool> rim_face(tissue.triangles.size(), false);
  for (std::size_t t = 0; t < tissue.triangles.size(); ++t) {
    bool on_cone = true;
    for (std::int32_t i : tissue.triangles[t]) {
      const Vec3 d = vertex(tissue, i) - hjc;
      on_cone = on_cone && std::abs(d.dot(rim.axis) - d.norm() * rim.cos_angle) <= rim_tolerance;
    }
    rim_face[t] = on_cone;
  }
  return rim_face;
}

// The rim face developed into the plane: per rim triangle, its vertices' distances from the
// HJC and azimuths about the rim axis.
struct DevelopedRim {
  Vec3 azimuth_x, azimuth_y;
  std::vector<std::array<std::pair<double, double>, 3>> triangles;  // (distance, azimuth)

  DevelopedRim(const TriMesh& tissue, const std::vector<bool>& rim_face, const Vec3& hjc, const Vec3& rim_axis)
      : azimuth_x((std::abs(rim_axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(rim_axis).normalized()),
        azimuth_y(rim_axis.cross(azimuth_x)) {
    for (std::size_t t = 0; t < tissue.triangles.size(); ++t) {
      if (!rim_face[t]) continue;
      std::array<std::pair<double, double>, 3> corners;
      for (std::size_t c = 0; c < 3; ++c) {
        const Vec3 d = vertex(tissue, tissue.triangles[t][c]) - hjc;
        corners[c] = {d.norm(), azimuth(d)};
      }
      triangles.push_back(corners);
    }
  }

  double azimuth(const Vec3& d) const { return std::atan2(d.dot(azimuth_y), d.dot(azimuth_x)); }

  // Distances at which the generator of the rim cone along `direction` enters and leaves the
  // rim face (none when it misses every rim triangle).
  std::optional<std::pair<double, double>> extent(const Vec3& direction) const {
    const double at = azimuth(direction);
    double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
    for (const auto& corners : triangles) {
      for (std::size_t c = 0; c < 3; ++c) {
        const auto& [r0, phi0] = corners[c];
        const auto& [r1, phi1] = corners[(c + 1) % 3];
        // Azimuths relative to the ray's, in (-pi, pi].
        const double a0 = std::remainder(phi0 - at, 2.0 * std::numbers::pi);
        const double a1 = std::remainder(phi1 - at, 2.0 * std::numbers::pi);
        if (std::abs(a0 - a1) > std::numbers::pi) continue;  // across the back of the cone
        if ((a0 > 0.0) == (a1 > 0.0) && a0 != 0.0 && a1 != 0.0) continue;
        const double f = a0 == a1 ? 0.0 : a0 / (a0 - a1);
        const double r = r0 + f * (r1 - r0);
        lowest = std::min(lowest, r);
        highest = std::max(highest, r);
      }
    }
    if (!(highest > lowest)) return std::nullopt;
    return std::make_pair(lowest, highest);
  }
};

// Faces through which the rays leave the tissue on its articular side.
std::vector<std::size_t> articular_side_faces(const TissueRecipe& recipe, const TriMesh& tissue, const RayCaster& caster,
                                              const std::vector<bool>& rim_face, const Vec3& hjc,
                                              const std::string& name) {
  std::vector<std::size_t> articular_side;
  for (std::size_t t = 0; t < tissue.triangles.size(); ++t) {
    const auto& tri = tissue.triangles[t];
    if (rim_face[t]) continue;
    const Vec3 centroid = (vertex(tissue, tri[0]) + vertex(tissue, tri[1]) + vertex(tissue, tri[2])) / 3.0;
    const double facing = caster.unit_normal[t].dot((centroid - hjc).normalized());
    if (recipe.articular_outer ? facing > kGrazingCosine : facing < -kGrazingCosine) articular_side.push_back(t);
  }
  if (articular_side.empty()) throw_error("hip volume mesh: ", name, ": no face of the tissue faces the joint");
  return articular_side;
}

// The projection of the articular side's shadow, at the mean distance of its vertices.
Stereographic shadow_projection(const TriMesh& tissue, const std::vector<std::size_t>& articular_side,
                                const Vec3& hjc, const std::string& name) {
  std::vector<Vec3> shadow;
  double radius_sum = 0.0;
  for (std::size_t t : articular_side) {
    for (std::int32_t i : tissue.triangles[t]) {
      shadow.push_back((vertex(tissue, i) - hjc).normalized());
      radius_sum += (vertex(tissue, i) - hjc).norm();
    }
  }
  return choose_projection(shadow, radius_sum / static_cast<double>(shadow.size()), name);
}

// Boundary loops in 3D, relative to the HJC.
std::vector<std::vector<Vec3>> loops_from_hjc(const TriMesh& tissue, const std::vector<std::vector<std::int32_t>>& loops,
                                              const Vec3& hjc) {
  std::vector<std::vector<Vec3>> loops_3d;
  for (const auto& loop : loops) {
    std::vector<Vec3> points;
    for (std::int32_t i : loop) points.push_back(vertex(tissue, i) - hjc);
    loops_3d.push_back(std::move(points));
  }
  return loops_3d;
}

// One column: its ray from the HJC and the extent of the tissue along it.
struct Column {
  Vec3 direction;
  double inner = 0.0;
  double outer = 0.0;
  bool articular = false;  // the ray hits the articular surface (not a side wall)
};

// What the columns of one tissue are cast against.
struct ColumnCaster {
  const TissueRecipe& recipe;
  const RayCaster& caster;
  const RimCone& rim_cone;
  const DevelopedRim& rim;
  const std::vector<std::vector<Vec3>>& loops_3d;  // relative to the HJC
  bool zigzag_outline;
  double min_thickness_mm;
  const std::string& name;

  // The ray of a plane node: boundary nodes snapped onto the outline (unless it zigzags), and
  // nodes whose ray misses the tissue moved onto the outline.
  RayCaster::Interval ray(Vec3& direction, bool on_boundary) const {
    if (on_boundary && !zigzag_outline) direction = snap_to_boundary(loops_3d, direction, &rim_cone).normalized();
    auto interval = caster.cast(direction);
    if (!interval.hit) {
      // Just outside a concave stretch of the boundary: move onto it.
      direction = snap_to_boundary(loops_3d, direction, &rim_cone).normalized();
      interval = caster.cast(direction);
    }
    if (!interval.hit && rim_cone.contains(direction)) interval = caster.cast(direction, kRimRaySlack);
    if (!interval.hit) {
      throw_error("hip volume mesh: ", name, ": the ray from the HJC along (", direction.x(), ", ",
                  direction.y(), ", ", direction.z(), ") misses the tissue");
    }
    return interval;
  }

  Column column(const Vec3& node_direction, bool on_boundary) const {
    Column result{node_direction};
    auto interval = ray(result.direction, on_boundary);
    const Vec3& direction = result.direction;
    // A ray along the rim cone (a boundary column of the rim face) runs IN the rim face, whose
    // flat triangles only approximate the cone: cast letting it hit the faces that look at the
    // HJC a little beyond their edges (their distance is interpolated on the sphere, so the node
    // still lands on it), and take the column's extent from the rim face itself, developed into
    // the plane (distance from the HJC, azimuth about the axis), where it is exact.
    double inner = interval.near_mm;
    double outer = interval.far_mm;
    if (rim_cone.contains(direction)) {
      const auto again = caster.cast(direction, kRimRaySlack);
      if (again.hit) interval = again;
      inner = interval.near_mm;
      outer = interval.far_mm;
      if (const auto extent = rim.extent(direction)) {
        inner = extent->first;
        outer = extent->second;
      }
    }
    const double articular_radial = recipe.articular_outer ? interval.far_radial : interval.near_radial;
    const double far_radial = recipe.articular_outer ? interval.near_radial : interval.far_radial;
    result.articular = articular_radial >= kRadialCosine;
    // Tapered edges: keep the articular face where it is and push the far face away — unless the
    // ray meets a side wall on the articular side (the fossa's silhouette) and the bone on the
    // far side: then the bonded face stays on the bone.
    if (outer - inner < min_thickness_mm) {
      const bool keep_articular = result.articular || far_radial < kRadialCosine;
      if (recipe.articular_outer == keep_articular) {
        inner = outer - min_thickness_mm;
      } else {
        outer = inner + min_thickness_mm;
      }
    }
    result.inner = inner;
    result.outer = outer;
    return result;
  }
};

// A boundary node that only one quad uses lies between two boundary edges of that quad, so its
// corner there is the outline's own: near 180 deg where the outline is smooth, more where it is
// concave. The plane mesh keeps it below 180 deg, but the hexahedra's edges are the chords
// between the columns' directions, not the plane's straight edges: far from the projection
// centre (the horns of the horseshoe, ~110 deg away, scale ~3) chord and plane angles differ by
// ~12 deg over one edge, and a boundary node of a subdivided mesh snapped onto a concave outline
// (the labrum's tip) turns its quad the same way. Past 180 deg the node's hexahedra invert, and
// a tapered edge's columns (inner face pushed out to the minimum thickness next to a full one)
// tilt them further. A corner flatter than kFlatCornerRad is opened to kOpenedCornerRad. (The
// study grid's flattest such corner is 177.9 deg, the labrum at coarse, CE 30: left as it is.)
constexpr double kFlatCornerRad = 178.0 * std::numbers::pi / 180.0;
constexpr double kOpenedCornerRad = 170.0 * std::numbers::pi / 180.0;

// Corner angle of the spherical quad at direction `at`, from the chord towards `next` to the
// chord towards `previous` counter-clockwise seen from outside, in [0, 2 pi).
double sphere_corner_angle(const Vec3& at, const Vec3& next, const Vec3& previous) {
  const Vec3 to_next = next - next.dot(at) * at;
  const Vec3 to_previous = previous - previous.dot(at) * at;
  const double angle = std::atan2(to_next.cross(to_previous).dot(at), to_next.dot(to_previous));
  return angle < 0.0 ? angle + 2.0 * std::numbers::pi : angle;
}

// Turns the column of every boundary node used by one quad only whose corner on the sphere is
// flatter than kFlatCornerRad away from the quad's opposite corner, just far enough to bring the
// corner to kOpenedCornerRad (0.1-0.4 mm on the hips measured; never more than the diagonal).
// The column keeps the extent found along its own ray, so the mesh stands that much out of the
// tissue's outline there, as the minimum thickness already blunts the tapered edges it lies on.
// The other columns are left as they are.
void blunt_flat_boundary_corners(const PlanarQuadMesh& plane, std::vector<Column>& columns) {
  std::vector<int> uses(plane.nodes.size(), 0);
  for (const auto& quad : plane.quads) {
    for (std::int32_t v : quad) ++uses[static_cast<std::size_t>(v)];
  }
  const auto direction_of = [&](const std::array<std::int32_t, 4>& quad, std::size_t c) {
    return columns[static_cast<std::size_t>(quad[c % 4])].direction;
  };
  for (const auto& quad : plane.quads) {
    for (std::size_t c = 0; c < 4; ++c) {
      const auto node = static_cast<std::size_t>(quad[c]);
      if (!plane.on_boundary[node] || uses[node] != 1) continue;
      const Vec3 at = direction_of(quad, c);
      const Vec3 next = direction_of(quad, c + 1);
      const Vec3 previous = direction_of(quad, c + 3);
      const Vec3 away = at - direction_of(quad, c + 2);
      if (sphere_corner_angle(at, next, previous) <= kFlatCornerRad) continue;
      const auto turned = [&](double s) { return Vec3((at + s * away).normalized()); };
      if (sphere_corner_angle(turned(1.0), next, previous) > kOpenedCornerRad) continue;
      // The angle falls as the column turns outwards: the smallest turn that brings it to the bound.
      double low = 0.0, high = 1.0;
      for (int k = 0; k < 50; ++k) {
        const double middle = 0.5 * (low + high);
        (sphere_corner_angle(turned(middle), next, previous) > kOpenedCornerRad ? low : high) = middle;
      }
      columns[node].direction = turned(high);
    }
  }
}

// The quads around each plane node, with the node's corner in each.
using CornersOfNodes = std::vector<std::vector<std::pair<std::size_t, std::size_t>>>;

// The node's own largest corner on the sphere (`own`) or the largest of every corner of its
// quads, with the node's column along `at`.
double largest_corner_around(const PlanarQuadMesh& plane, const CornersOfNodes& corners, const std::vector<Column>& columns,
                             std::size_t node, const Vec3& at, bool own) {
  double largest = 0.0;
  for (const auto& [q, corner] : corners[node]) {
    const auto& quad = plane.quads[q];
    const auto direction = [&](std::size_t c) {
      const auto v = static_cast<std::size_t>(quad[c % 4]);
      return v == node ? at : columns[v].direction;
    };
    for (std::size_t c = own ? corner : 0; c < (own ? corner + 1 : 4); ++c) {
      largest = std::max(largest, sphere_corner_angle(direction(c), direction(c + 1), direction(c + 3)));
    }
  }
  return largest;
}

// An interior node with a corner flatter than kFlatCornerRad (a sliver beside the snapped outline
// of a subdivided mesh, e.g. at the labrum's end) moves to the mean direction of its neighbours
// along the quads' edges when that lowers the largest corner of its quads, and its column is
// cast there. The other nodes are left as they are.
void smooth_folded_interior_nodes(const ColumnCaster& caster, const PlanarQuadMesh& plane, std::vector<Column>& columns) {
  CornersOfNodes corners(plane.nodes.size());
  std::vector<std::set<std::size_t>> neighbours(plane.nodes.size());
  for (std::size_t q = 0; q < plane.quads.size(); ++q) {
    const auto& quad = plane.quads[q];
    for (std::size_t c = 0; c < 4; ++c) {
      const auto node = static_cast<std::size_t>(quad[c]);
      corners[node].emplace_back(q, c);
      neighbours[node].insert(static_cast<std::size_t>(quad[(c + 1) % 4]));
      neighbours[node].insert(static_cast<std::size_t>(quad[(c + 3) % 4]));
    }
  }
  for (std::size_t node = 0; node < plane.nodes.size(); ++node) {
    if (plane.on_boundary[node] || corners[node].empty()) continue;
    const Vec3 at = columns[node].direction;
    if (largest_corner_around(plane, corners, columns, node, at, true) <= kFlatCornerRad) continue;
    Vec3 mean = Vec3::Zero();
    for (std::size_t v : neighbours[node]) mean += columns[v].direction;
    const Vec3 moved = mean.normalized();
    if (largest_corner_around(plane, corners, columns, node, moved, false) <
        largest_corner_around(plane, corners, columns, node, at, false)) {
      columns[node] = caster.column(moved, false);
    }
  }
}

// One column per plane node, layers + 1 vertices from the inner to the outer face appended to
// out.vertices; per node, whether its column is articular.
std::vector<bool> add_columns(const ColumnCaster& caster, const PlanarQuadMesh& plane, const Stereographic& projection,
                              const Vec3& hjc, std::size_t layers, HexMesh& out) {
  std::vector<Column> columns;
  columns.reserve(plane.nodes.size());
  for (std::size_t node = 0; node < plane.nodes.size(); ++node) {
    columns.push_back(caster.column(projection.unproject(plane.nodes[node]).normalized(), plane.on_boundary[node]));
  }
  blunt_flat_boundary_corners(plane, columns);
  smooth_folded_interior_nodes(caster, plane, columns);
  std::vector<bool> articular_column(plane.nodes.size(), false);
  for (std::size_t node = 0; node < plane.nodes.size(); ++node) {
    const Column& column = columns[node];
    articular_column[node] = column.articular;
    for (std::size_t layer = 0; layer <= layers; ++layer) {
      const double r = column.inner + (column.outer - column.inner) * static_cast<double>(layer) /
                                          static_cast<double>(layers);
      out.vertices.push_back(hjc + r * column.direction);
    }
  }
  return articular_column;
}

// Plane edges used by one quad: the domain boundary, where the columns' side faces are.
std::map<std::pair<std::int32_t, std::int32_t>, int> plane_edge_uses(const PlanarQuadMesh& plane) {
  std::map<std::pair<std::int32_t, std::int32_t>, int> edge_uses;
  for (const auto& quad : plane.quads) {
    for (std::size_t c = 0; c < 4; ++c) {
      const auto a = quad[c];
      const auto b = quad[(c + 1) % 4];
      ++edge_uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  return edge_uses;
}

// The tag of a column stack's side face on the domain boundary.
struct SideFaceTagger {
  const TissueRecipe& recipe;
  bool synthesised;
  Vec3 hjc;
  const RimCone& rim_cone;
  double rim_tolerance_mm;

  // `inner`: the quad's four inner vertices; the side face is along its edge c, c + 1.
  SurfaceTag tag(const HexMesh& out, const std::array<std::int32_t, 4>& inner, std::size_t c,
                 const std::array<std::int32_t, 4>& side) const {
    if (recipe.rim_side_bonded && synthesised) {
      return faces_away_from_rim_axis(out, inner, c) ? SurfaceTag::kLabrumBonded : SurfaceTag::kFree;
    }
    if (recipe.rim_side_bonded) {
      bool on_rim = true;
      for (std::int32_t v : side) {
        const Vec3 d = out.vertices[static_cast<std::size_t>(v)] - hjc;
        on_rim = on_rim && std::abs(d.dot(rim_cone.axis) - d.norm() * rim_cone.cos_angle) < rim_tolerance_mm;
      }
      if (on_rim) return SurfaceTag::kLabrumBonded;
    }
    return SurfaceTag::kFree;
  }

  // A synthesised labrum's base lies along the rays at the measured rim, which is no cone: its
  // side faces are those facing away from the acetabular axis (the shadow's outer edge), not the
  // end caps (facing along the rim) nor the tip (towards the axis).
  bool faces_away_from_rim_axis(const HexMesh& out, const std::array<std::int32_t, 4>& inner, std::size_t c) const {
    const auto direction_of = [&](std::int32_t v) {
      return Vec3((out.vertices[static_cast<std::size_t>(v)] - hjc).normalized());
    };
    const Vec3 middle = (direction_of(inner[c % 4]) + direction_of(inner[(c + 1) % 4])).normalized();
    Vec3 centre = Vec3::Zero();
    for (std::size_t k = 0; k < 4; ++k) centre += direction_of(inner[k]);
    Vec3 outward = middle - centre.normalized();
    outward -= outward.dot(middle) * middle;
    Vec3 away = rim_cone.axis.dot(middle) * middle - rim_cone.axis;  // polar angle increasing
    return outward.norm() > 0.0 && away.norm() > 0.0 && outward.normalized().dot(away.normalized()) > kRadialCosine;
  }
};

// The hexahedra of the columns and their boundary faces: the inner and outer face of every
// quad's stack, and the side faces along the domain boundary.
void add_hexes(const TissueRecipe& recipe, const PlanarQuadMesh& plane, const std::vector<bool>& articular_column,
               std::int32_t first_vertex, std::size_t layers, const SideFaceTagger& sides, HexMesh& out) {
  const auto edge_uses = plane_edge_uses(plane);
  for (const auto& quad : plane.quads) {
    auto at = [&](std::size_t c, std::size_t layer) {
      return first_vertex + static_cast<std::int32_t>(static_cast<std::size_t>(quad[c % 4]) * (layers + 1) + layer);
    };
    for (std::size_t layer = 0; layer < layers; ++layer) {
      out.hexes.push_back({at(0, layer), at(1, layer), at(2, layer), at(3, layer), at(0, layer + 1),
                           at(1, layer + 1), at(2, layer + 1), at(3, layer + 1)});
      out.hex_tags.push_back(recipe.volume);
    }
    bool all_articular = true;
    for (std::size_t c = 0; c < 4; ++c) all_articular = all_articular && articular_column[static_cast<std::size_t>(quad[c])];
    const SurfaceTag articular_tag = all_articular ? recipe.articular : SurfaceTag::kFree;
    // Inner face seen from the HJC side (outward = towards the HJC), outer face seen from outside.
    out.quads.push_back({at(0, 0), at(3, 0), at(2, 0), at(1, 0)});
    out.quad_tags.push_back(recipe.articular_outer ? recipe.far : articular_tag);
    out.quads.push_back({at(0, layers), at(1, layers), at(2, layers), at(3, layers)});
    out.quad_tags.push_back(recipe.articular_outer ? articular_tag : recipe.far);
    const std::array<std::int32_t, 4> inner{at(0, 0), at(1, 0), at(2, 0), at(3, 0)};
    for (std::size_t c = 0; c < 4; ++c) {
      const auto a = quad[c];
      const auto b = quad[(c + 1) % 4];
      if (edge_uses.at({std::min(a, b), std::max(a, b)}) != 1) continue;
      for (std::size_t layer = 0; layer < layers; ++layer) {
        const std::array<std::int32_t, 4> side{at(c, layer), at(c + 1, layer), at(c + 1, layer + 1), at(c, layer + 1)};
        out.quads.push_back(side);
        out.quad_tags.push_back(sides.tag(out, inner, c, side));
      }
    }
  }
}

// rim_axis, rim_cos: the acetabular rim cone through the HJC, {d : d . rim_axis = |d| rim_cos}
// (a plane when rim_cos = 0); the labrum's base lies on it.
void mesh_tissue(const TissueRecipe& recipe, const TriMesh& tissue, const Vec3& hjc, const Vec3& rim_axis,
                 double rim_cos, SoftTissueSource source, const HipVolumeOptions& options, HexMesh& out) {
  // Synthesised layers follow a segmented bone's triangles, so their outlines zigzag at the bone's
  // edge length: the outline is smoothed for the quad mesh and a boundary node is snapped onto it
  // only when its own ray misses the tissue (snapping every node onto a zigzag folds the quads
  // beside it). A synthesised labrum is a sweep with a smooth outline and sharp corners (its end
  // caps): meshed as a generated one, only its bonded side found otherwise (SideFaceTagger).
  const bool synthesised = source == SoftTissueSource::kSynthesised;
  const bool zigzag_outline = synthesised && recipe.volume != VolumeTag::kLabrum;
  const std::string name = recipe.name;  // the tissue validated by the caller

  const RimCone rim_cone{rim_axis, rim_cos};
  const std::vector<bool> rim_face = rim_cone_faces(tissue, hjc, rim_cone);
  const RayCaster caster(tissue, hjc, rim_face);
  const DevelopedRim rim(tissue, rim_face, hjc, rim_axis);

  const auto articular_side = articular_side_faces(recipe, tissue, caster, rim_face, hjc, name);
  const auto loops = boundary_loops(tissue, articular_side, name);
  const Stereographic projection = shadow_projection(tissue, articular_side, hjc, name);
  const std::vector<std::vector<Vec3>> loops_3d = loops_from_hjc(tissue, loops, hjc);
  std::vector<std::vector<Vec3>> domain_loops = loops_3d;
  if (zigzag_outline) {
    for (auto& loop : domain_loops) loop = smooth_loop(loop, options.edge_mm);
  }
  const PlanarQuadMesh plane = quad_mesh_shadow(domain_loops, projection, options.edge_mm, name);

  const std::size_t layers = static_cast<std::size_t>(options.layers);
  const auto first_vertex = static_cast<std::int32_t>(out.vertices.size());
  const ColumnCaster columns{recipe, caster, rim_cone, rim, loops_3d, zigzag_outline, options.min_thickness_mm, name};
  const std::vector<bool> articular_column = add_columns(columns, plane, projection, hjc, layers, out);
  const SideFaceTagger sides{recipe, synthesised, hjc, rim_cone, 1e-6 * projection.radius_mm};
  add_hexes(recipe, plane, articular_column, first_vertex, layers, sides, out);
}

// Scaled Jacobian of a hexahedron: the smallest, over its 8 corners, determinant of the three
// unit edge vectors leaving the corner (in right-handed order for gmsh's numbering).
double hex_scaled_jacobian(const HexMesh& mesh, const std::array<std::int32_t, 8>& hex) {
  static constexpr std::array<std::array<int, 4>, 8> kCorners{{{0, 1, 3, 4}, {1, 2, 0, 5}, {2, 3, 1, 6}, {3, 0, 2, 7},
                                                              {4, 7, 5, 0}, {5, 4, 6, 1}, {6, 5, 7, 2}, {7, 6, 4, 3}}};
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& corner : kCorners) {
    auto at = [&](int k) { return mesh.vertices[static_cast<std::size_t>(hex[static_cast<std::size_t>(corner[static_cast<std::size_t>(k)])])]; };
    const Vec3 e1 = at(1) - at(0);
    const Vec3 e2 = at(2) - at(0);
    const Vec3 e3 = at(3) - at(0);
    const double lengths = e1.norm() * e2.norm() * e3.norm();
    lowest = std::min(lowest, lengths > 0.0 ? e1.cross(e2).dot(e3) / lengths : -1.0);
  }
  return lowest;
}

}  // namespace

const char* to_string(VolumeTag tag) {
  switch (tag) {
    case VolumeTag::kFemoralCartilage: return "femoral_cartilage";
    case VolumeTag::kAcetabularCartilage: return "acetabular_cartilage";
    case VolumeTag::kLabrum: return "labrum";
  }
  return "unknown";
}

const char* to_string(SurfaceTag tag) {
  switch (tag) {
    case SurfaceTag::kFree: return "free";
    case SurfaceTag::kFemoralCartilageArticular: return "femoral_cartilage_articular";
    case SurfaceTag::kFemoralCartilageBonded: return "femoral_cartilage_bonded";
    case SurfaceTag::kAcetabularCartilageArticular: return "acetabular_cartilage_articular";
    case SurfaceTag::kAcetabularCartilageBonded: return "acetabular_cartilage_bonded";
    case SurfaceTag::kLabrumArticular: return "labrum_articular";
    case SurfaceTag::kLabrumBonded: return "labrum_bonded";
  }
  return "unknown";
}

double min_scaled_jacobian(const HexMesh& mesh) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& hex : mesh.hexes) lowest = std::min(lowest, hex_scaled_jacobian(mesh, hex));
  return lowest;
}

HipVolumeMesh build_hip_volume_mesh(const HipModel& model, const HipVolumeOptions& options) {
  if (!(options.edge_mm > 0.0) || !std::isfinite(options.edge_mm)) {
    throw_error("hip volume mesh: edge_mm = ", options.edge_mm, " must be positive");
  }
  if (options.layers < 1) throw_error("hip volume mesh: layers = ", options.layers, " must be at least 1");
  if (!(options.min_thickness_mm > 0.0)) {
    throw_error("hip volume mesh: min_thickness_mm = ", options.min_thickness_mm, " must be positive");
  }
  if (options.labrum_edge_mm < 0.0 || !std::isfinite(options.labrum_edge_mm) || options.labrum_layers < 0) {
    throw_error("hip volume mesh: labrum_edge_mm = ", options.labrum_edge_mm, " and labrum_layers = ",
                options.labrum_layers, " must not be negative (0: as the cartilage)");
  }
  HipVolumeMesh result;
  result.options = options;
  result.min_scaled_jacobian = std::numeric_limits<double>::infinity();
  for (const auto& recipe : kRecipes) {
    HipVolumeOptions tissue_options = options;
    if (recipe.volume == VolumeTag::kLabrum) {
      if (options.labrum_edge_mm > 0.0) tissue_options.edge_mm = options.labrum_edge_mm;
      if (options.labrum_layers > 0) tissue_options.layers = options.labrum_layers;
    }
    const std::size_t first_hex = result.mesh.hexes.size();
    // A tissue in pieces (a labrum open at the notch and over the neck) is meshed piece by piece:
    // one shadow holds one piece.
    const TriMesh& tissue = model.tissue(recipe.name);
    validate_mesh(tissue, recipe.name);
    const std::vector<TriMesh> pieces = connected_parts(tissue);
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      TissueRecipe piece_recipe = recipe;
      const std::string piece_name =
          pieces.size() == 1 ? std::string(recipe.name)
                             : std::string(recipe.name) + " (piece " + std::to_string(k + 1) + " of " +
                                   std::to_string(pieces.size()) + ")";
      piece_recipe.name = piece_name.c_str();
      mesh_tissue(piece_recipe, pieces[k], model.hjc_mm, model.acetabular_axis.normalized(),
                  std::cos(model.socket_opening_deg * kDegToRad), model.soft_tissue, tissue_options, result.mesh);
    }
    std::size_t inverted = 0;
    double lowest = std::numeric_limits<double>::infinity();
    Vec3 where = Vec3::Zero();
    for (std::size_t h = first_hex; h < result.mesh.hexes.size(); ++h) {
      const double q = hex_scaled_jacobian(result.mesh, result.mesh.hexes[h]);
      result.min_scaled_jacobian = std::min(result.min_scaled_jacobian, q);
      if (q > 0.0) continue;
      ++inverted;
      if (q < lowest) {
        lowest = q;
        where = result.mesh.vertices[static_cast<std::size_t>(result.mesh.hexes[h][0])];
      }
    }
    if (inverted > 0) {
      throw_error("hip volume mesh: ", recipe.name, ": ", inverted, " inverted hexahedra (lowest scaled Jacobian ",
                  lowest, ", e.g. at [", where.x(), ", ", where.y(), ", ", where.z(), "] mm)");
    }
  }
  return result;
}

// --- MSH 2.2 (through geometry/mesh_io_msh.h, the tree's one MSH reader and writer) ----------

void write_hex_msh(const HexMesh& mesh, const std::filesystem::path& file) {
  if (mesh.hex_tags.size() != mesh.hexes.size() || mesh.quad_tags.size() != mesh.quads.size()) {
    throw_error(file.string(), ": hex mesh has ", mesh.hexes.size(), " hexahedra with ", mesh.hex_tags.size(),
                " tags and ", mesh.quads.size(), " quadrangles with ", mesh.quad_tags.size(), " tags");
  }
  std::error_code error;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), error);
  mesh_io::MshMesh msh;
  std::set<int> volume_tags, surface_tags;
  for (VolumeTag tag : mesh.hex_tags) volume_tags.insert(static_cast<int>(tag));
  for (SurfaceTag tag : mesh.quad_tags) surface_tags.insert(static_cast<int>(tag));
  for (int tag : surface_tags) msh.physical_names.push_back({2, tag, to_string(static_cast<SurfaceTag>(tag))});
  for (int tag : volume_tags) msh.physical_names.push_back({3, tag, to_string(static_cast<VolumeTag>(tag))});
  msh.nodes = mesh.vertices;
  msh.elements.reserve(mesh.quads.size() + mesh.hexes.size());
  // Physical and elementary tag the same: one gmsh entity per tag.
  for (std::size_t i = 0; i < mesh.quads.size(); ++i) {
    mesh_io::MshElement element;
    element.type = mesh_io::MshElementType::kQuadrangle;
    element.physical = element.elementary = static_cast<int>(mesh.quad_tags[i]);
    std::copy(mesh.quads[i].begin(), mesh.quads[i].end(), element.nodes.begin());
    msh.elements.push_back(element);
  }
  for (std::size_t i = 0; i < mesh.hexes.size(); ++i) {
    mesh_io::MshElement element;
    element.type = mesh_io::MshElementType::kHexahedron;
    element.physical = element.elementary = static_cast<int>(mesh.hex_tags[i]);
    element.nodes = mesh.hexes[i];
    msh.elements.push_back(element);
  }
  write_file_atomically(file, mesh_io::format_msh(msh));
}

namespace {

bool is_volume_tag(int tag) { return tag >= 1 && tag <= 3; }

bool is_surface_tag(int tag) {
  return tag == 10 || tag == 11 || tag == 12 || tag == 21 || tag == 22 || tag == 31 || tag == 32;
}

}  // namespace

HexMesh read_hex_msh(const std::filesystem::path& file) {
  const std::string where = file.string();
  const mesh_io::MshMesh msh = mesh_io::parse_msh(where, mesh_io::read_file_bytes(file));
  HexMesh mesh;
  mesh.vertices = msh.nodes;
  for (const mesh_io::MshElement& element : msh.elements) {
    if (element.type == mesh_io::MshElementType::kHexahedron) {
      if (!is_volume_tag(element.physical)) {
        throw_error(where, ": hexahedron ", element.id, " has unknown physical tag ", element.physical);
      }
      mesh.hexes.push_back(element.nodes);
      mesh.hex_tags.push_back(static_cast<VolumeTag>(element.physical));
    } else if (element.type == mesh_io::MshElementType::kQuadrangle) {
      if (!is_surface_tag(element.physical)) {
        throw_error(where, ": quadrangle ", element.id, " has unknown physical tag ", element.physical);
      }
      mesh.quads.push_back({element.nodes[0], element.nodes[1], element.nodes[2], element.nodes[3]});
      mesh.quad_tags.push_back(static_cast<SurfaceTag>(element.physical));
    } else {
      throw_error(where, ": element ", element.id, " has type ", static_cast<int>(element.type),
                  " (only quadrangles 3 and hexahedra 5)");
    }
  }
  return mesh;
}

}  // namespace hipfai::geometry
