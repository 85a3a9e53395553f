#include "geometry/hip_generator.h"

#include "geometry/gmsh_runtime.h"

#include "core/child_process.h"
#include "core/error.h"
#include "geometry/hip_frame.h"
#include "geometry/hip_measure.h"
#include "geometry/mesh_bytes.h"

#include <gmsh.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <optional>
#include <queue>
#include <sstream>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <unordered_map>
#include <utility>

namespace hipfai::geometry {
namespace {

namespace occ = gmsh::model::occ;
using DimTags = gmsh::vectorpair;

// gmsh's own log only on request (HIPFAI_GMSH_VERBOSE=1), to diagnose a failed construction.
bool gmsh_verbose() { return std::getenv("HIPFAI_GMSH_VERBOSE") != nullptr; }

// A fresh model for one construction, in the meshing child (the parent holds lock_gmsh()).
void start_gmsh_model(const std::string& name) {
  gmsh::clear();
  gmsh::model::add(name);
  gmsh::option::setNumber("General.Terminal", gmsh_verbose() ? 1 : 0);
}

// OCC spheres have their poles and seam on the Z axis through the centre; ball() turns them about
// a generic axis, so that the seam does not run into the hip's features (the surface mesher fails
// on seam curves cut into tiny pieces there). The solid itself is unchanged. With
// `other_seam_half` the sphere is first turned half a turn about its own axis: the same poles, the
// seam on the other half of the same great circle.
constexpr std::array<double, 3> kGenericTurnAxis = {0.3, 0.5, 0.81};
constexpr double kGenericTurnRad = 0.9;

DimTags ball(const Vec3& centre, double radius, bool other_seam_half = false) {
  DimTags sphere = {{3, occ::addSphere(centre.x(), centre.y(), centre.z(), radius)}};
  if (other_seam_half) occ::rotate(sphere, centre.x(), centre.y(), centre.z(), 0.0, 0.0, 1.0, std::numbers::pi);
  occ::rotate(sphere, centre.x(), centre.y(), centre.z(), kGenericTurnAxis[0], kGenericTurnAxis[1],
              kGenericTurnAxis[2], kGenericTurnRad);
  return sphere;
}

// The angle (rad), seen from a ball()'s centre, from the direction d to that ball's seam: the half
// great circle from pole to pole through the turned +X (through the turned -X: other_seam_half).
double angle_to_seam(const Vec3& d, bool other_seam_half) {
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(kGenericTurnRad, Vec3(kGenericTurnAxis[0], kGenericTurnAxis[1], kGenericTurnAxis[2]).normalized())
          .toRotationMatrix();
  const Vec3 pole = turn.col(2), normal = turn.col(1);
  const Vec3 seam = other_seam_half ? Vec3(-turn.col(0)) : Vec3(turn.col(0));
  const Vec3 u = d.normalized();
  if (u.dot(seam) >= 0.0) return std::asin(std::min(1.0, std::abs(u.dot(normal))));
  return std::acos(std::min(1.0, std::abs(u.dot(pole))));
}

DimTags cylinder(const Vec3& base, const Vec3& axis, double radius) {
  return {{3, occ::addCylinder(base.x(), base.y(), base.z(), axis.x(), axis.y(), axis.z(), radius)}};
}

DimTags cut(const DimTags& object, const DimTags& tool) {
  DimTags out;
  std::vector<DimTags> map;
  occ::cut(object, tool, out, map);
  return out;
}

DimTags intersect(const DimTags& object, const DimTags& tool) {
  DimTags out;
  std::vector<DimTags> map;
  occ::intersect(object, tool, out, map);
  return out;
}

DimTags fuse(const DimTags& object, const DimTags& tool) {
  DimTags out;
  std::vector<DimTags> map;
  occ::fuse(object, tool, out, map);
  return out;
}

Vec3 unit_perpendicular(const Vec3& axis, const Vec3& hint) {
  return (hint - hint.dot(axis) * axis).normalized();
}

// The angle (rad) seen from the HJC between the centre of the cam's cross-section circle (radius
// rc, centre D = R + h - rc from the HJC) and either point where it crosses the R sphere (law of
// cosines). Swept about the neck axis, the section meets the R sphere along two circles about n:
// its feet, at alpha (far side) and alpha - 2 delta (near side) from n.
double cam_half_angle(const HipParameters& p) {
  const double radius = p.articular_radius_mm;
  const double rc = p.cam_radius_mm;
  const double distance = radius + p.cam_height_mm - rc;
  return std::acos((radius * radius + distance * distance - rc * rc) / (2.0 * radius * distance));
}

// How far (deg) a circle of the head about n (the cartilage margin, the head-neck junction) is kept
// from a foot of the cam. The head ball, the R sphere, the junction plane and the cam's sweep are
// all surfaces of revolution about n: when a foot of the cam falls on one of the head's circles,
// three surfaces meet along one arc and the cam's end balls touch that circle tangentially.
// OpenCASCADE's fuse then gives the cam's end-section edge parameter curves shifted by a whole
// period (2 pi) on the sweep and on the end ball, so gmsh cannot close those periodic faces'
// boundary loops in (u, v) ("Impossible to mesh periodic surface"): alpha =
// femoral_cartilage_edge_deg (45 by default: CE 35 / alpha 45), or alpha - 2 delta =
// normal_alpha_deg (76.39 deg with the default cam). Measured on these hips, the failures need the
// circles within 1e-4 deg of the foot (1e-3 deg apart and more generate, at 2 and 4 mm edges);
// 0.01 deg (4 um on the head) keeps them a hundred times further, far below any surface mesh
// (edges >= 0.2 mm) and the angles' 1 deg.
constexpr double kCircleFromCamFootDeg = 0.01;

// `circle_deg` (an angle from n of a circle of the head), moved away from a foot of the cam it falls
// within kCircleFromCamFootDeg of, on its own side (under the cam when it lies on the foot); it
// moves by at most that distance. Circles away from the feet (every hip whose feet are not near
// them, the study grid's among them) are kept as they are.
double circle_apart_from_cam(const HipParameters& p, double circle_deg) {
  if (p.alpha_deg <= p.normal_alpha_deg) return circle_deg;  // no cam
  const double far_deg = p.alpha_deg;  // the cam covers the angles between its feet
  const double near_deg = p.alpha_deg - 2.0 * cam_half_angle(p) * kRadToDeg;
  if (std::abs(circle_deg - far_deg) < kCircleFromCamFootDeg) {
    return circle_deg > far_deg ? far_deg + kCircleFromCamFootDeg : far_deg - kCircleFromCamFootDeg;
  }
  if (std::abs(circle_deg - near_deg) < kCircleFromCamFootDeg) {
    return circle_deg < near_deg ? near_deg - kCircleFromCamFootDeg : near_deg + kCircleFromCamFootDeg;
  }
  return circle_deg;
}

// The cam (see femur_solids): every point within rc of the arc of section centres, i.e. the
// section circle swept about the neck axis over the clock arc plus a half ball at each end, as one
// OCC solid (a new one on every call: booleans consume their tools).
//
// The half balls meet the sweep along the end sections' circles, where their spheres and the swept
// surface are tangent (the cam is smooth there). Built as three solids and fused, the fuse had to
// intersect those tangent faces, and for isolated doubles alpha (4 of 1000 random alphas in
// [40, 80]; 56.61436601558189 and 73.31368003040552 among them, their neighbours 1e-14 away fine)
// OpenCASCADE returned a cam whose end-section vertices and arcs carried tolerances of 2.9-5.9 mm.
// The femur's next boolean then threw ("BRep_Tool:: TopoDS_Vertex hasn't gp_Pnt") or gave the head
// balls' seams parameter curves shifted by a period (gmsh: "Impossible to mesh periodic surface").
// No boolean is used here: the cam's boundary is made of faces built on shared curves and sewn
// into one shell (2000 random alphas: one valid solid each, tolerances 1e-7 mm).
//   - The begin section is bounded by two sides running from its top T (its point farthest from
//     the neck axis) towards +n and towards -n down to the section's axis u: the circle's arcs
//     through the pole to its bottom B, or, where the section is clipped (below), an arc to the
//     chord's end and the half chord to its middle M.
//   - The swept surface is those curves revolved about the neck axis over the clock arc; their
//     last positions bound the end section.
//   - Each end's half ball is its section's +n side revolved by half a turn about the section's
//     axis u (through T and B or M), away from the sweep: the arc makes the half sphere, the half
//     chord a half disc. Its first curves are the sweep's own; its last ones land on the -n side,
//     the same circles and lines, which sewing merges (no surface is intersected).
// Near the neck axis the section would cross the axis of revolution (small alpha): everything
// closer to the axis than `clip` (half the neck radius) is inside the neck cylinder anyway, so the
// section is clipped there by a chord parallel to n (swept: a cylinder about n), and the half
// balls by the plane through that chord normal to u (the half chord's half turn). What the plane
// removes beyond the cylinder lies within sqrt(clip^2 + half chord^2) of the axis, inside the neck
// (11.9 mm with the default cam, neck radius 13 mm; for larger cams `clip` is lowered to keep it
// so): the femur and its cartilage are the same solids as with the cylinder (volumes and areas
// equal to 1e-8, 12 alphas from 40.01 to 80). Where the section's centre is within 1 mm of `clip`
// (alpha just above normal_alpha_deg with the default cam) the clip is taken 1 mm nearer the axis
// than the centre, as before, when the cylinder ran through the former caps' poles there (at 2 mm,
// alpha 40.0001-40.024 failed or looped: CE 3.8 / alpha 40.024).
DimTags cam_solids(const HipParameters& p) {
  const double radius = p.articular_radius_mm;
  const double rc = p.cam_radius_mm;
  const double distance = radius + p.cam_height_mm - rc;
  const double delta = cam_half_angle(p);
  const double centre_angle = p.alpha_deg * kDegToRad - delta;
  const Vec3 n = neck_axis(p);
  auto centre_at = [&](double clock_deg) {
    const Vec3 u = clock_direction(p, clock_deg);
    return Vec3(distance * (std::cos(centre_angle) * n + std::sin(centre_angle) * u));
  };
  const double sweep = (p.cam_end_deg - p.cam_begin_deg) * kDegToRad;
  if (sweep <= 1e-9) return ball(centre_at(p.cam_begin_deg), rc);
  constexpr double kPoleClearanceMm = 1.0;
  const Vec3 u = clock_direction(p, p.cam_begin_deg);
  const Vec3 c = centre_at(p.cam_begin_deg);
  const double height = c.dot(u);  // distance of the section's centre from the neck axis
  // The plane removes from a half ball, beyond the cylinder, points within
  // sqrt(rc^2 - height^2 + 2 height clip) of the axis: the clip is lowered where that would leave
  // the neck (a cam radius large for the neck: 15 mm on the 13 mm neck), never for the default cam.
  const double within_neck = (p.neck_radius_mm * p.neck_radius_mm + height * height - rc * rc) / (2.0 * height);
  const double clip = std::min(within_neck, std::abs(height - 0.5 * p.neck_radius_mm) < kPoleClearanceMm
                                                ? height - kPoleClearanceMm
                                                : 0.5 * p.neck_radius_mm);
  if (clip < 0.5) {
    throw_error("hip generator: cam_radius_mm = ", rc, " is too large for neck_radius_mm = ", p.neck_radius_mm,
                " at alpha ", p.alpha_deg, " deg: the cam's end balls would reach outside the neck near its axis");
  }
  auto point = [](const Vec3& q) { return occ::addPoint(q.x(), q.y(), q.z()); };
  const int centre_tag = point(c);
  const int top = point(c + rc * u);
  // The begin section's boundary as two sides from T, each ending on the section's axis u.
  std::array<DimTags, 2> sides;  // +n side, -n side
  if (height - rc >= clip) {
    const int bottom = point(c - rc * u);
    for (int k = 0; k < 2; ++k) {
      const int pole = point(c + (k == 0 ? rc : -rc) * n);
      sides[k] = {{1, occ::addCircleArc(top, centre_tag, pole)}, {1, occ::addCircleArc(pole, centre_tag, bottom)}};
    }
  } else {
    const double below = clip - height;  // the chord's offset from the centre along u (negative)
    const double half_chord = std::sqrt(rc * rc - below * below);
    const int middle = point(c + below * u);
    for (int k = 0; k < 2; ++k) {
      const int end = point(c + below * u + (k == 0 ? half_chord : -half_chord) * n);
      sides[k] = {{1, occ::addCircleArc(top, centre_tag, end)}, {1, occ::addLine(end, middle)}};
    }
  }
  occ::remove({{0, centre_tag}});
  // The swept surface.
  const Vec3 turn = clock_direction(p, 0.0).cross(clock_direction(p, 90.0)).normalized();
  DimTags section = sides[0];
  section.insert(section.end(), sides[1].begin(), sides[1].end());
  DimTags swept;
  occ::revolve(section, 0, 0, 0, turn.x(), turn.y(), turn.z(), sweep, swept);
  // revolve lists, per curve: its last position, the surface, the curves its ends swept.
  std::vector<int> faces;
  DimTags end_side;  // the end section's +n side, as the begin's
  for (std::size_t k = 1; k < swept.size(); ++k) {
    if (swept[k].first != 2) continue;
    if (faces.size() < sides[0].size()) end_side.push_back(swept[k - 1]);
    faces.push_back(swept[k].second);
  }
  // The half balls: each end's +n side turned half a turn about its section's axis u, away from
  // the sweep (towards smaller clock angles at the begin, larger at the end).
  for (const auto& [clock_deg, outwards, side] :
       {std::tuple{p.cam_begin_deg, -1.0, sides[0]}, std::tuple{p.cam_end_deg, 1.0, end_side}}) {
    const Vec3 axis = clock_direction(p, clock_deg);
    const Vec3 away = outwards * clock_direction(p, clock_deg + 90.0);
    const Vec3 at = centre_at(clock_deg);
    const double half_turn = axis.cross(n).dot(away) > 0.0 ? std::numbers::pi : -std::numbers::pi;
    DimTags capped;
    occ::revolve(side, at.x(), at.y(), at.z(), axis.x(), axis.y(), axis.z(), half_turn, capped);
    for (const auto& [dim, tag] : capped) {
      if (dim == 2) faces.push_back(tag);
    }
  }
  const int shell = occ::addSurfaceLoop(faces, -1, true);
  const int cam = occ::addVolume({shell});
  DimTags leftovers;
  for (const int face : faces) leftovers.emplace_back(2, face);
  occ::remove(leftovers, true);  // the faces (and their curves and points) sewn into the shell
  return {{3, cam}};
}

// Directions at least `opening` (rad) from the axis a, i.e. the socket side of the rim cone, as a
// solid of size `size`: a half-space for a hemisphere, else a cone about -a or the complement of
// a cone about +a. Applied to `object` (consumed).
DimTags restrict_to_socket(const DimTags& object, const Vec3& a, double opening, double size) {
  const double half_pi = 0.5 * std::numbers::pi;
  if (std::abs(opening - half_pi) < 1e-9) {
    DimTags out;
    std::vector<DimTags> map;
    occ::intersect(object, {{3, occ::addCylinder(0, 0, 0, -size * a.x(), -size * a.y(), -size * a.z(), size)}}, out, map);
    return out;
  }
  DimTags out;
  std::vector<DimTags> map;
  if (opening > half_pi) {
    const double half = std::numbers::pi - opening;  // cone about -a
    const int cone = occ::addCone(0, 0, 0, -size * a.x(), -size * a.y(), -size * a.z(), 0.0, size * std::tan(half));
    occ::intersect(object, {{3, cone}}, out, map);
  } else {
    const int cone = occ::addCone(0, 0, 0, size * a.x(), size * a.y(), size * a.z(), 0.0, size * std::tan(opening));
    occ::cut(object, {{3, cone}}, out, map);
  }
  return out;
}

// The sector of azimuths about the acetabular axis a (from the +Z meridian towards a x it, rad)
// over which the labrum's section (base on the rim cone at `opening`, tip at `tip_angle` from a)
// comes within neck radius + clearance of the neck axis; none when it stays clear.
std::optional<std::pair<double, double>> labrum_neck_sector(const HipParameters& p, const Vec3& a, double opening,
                                                            double tip_angle) {
  const Vec3 n = neck_axis(p);
  const Vec3 e1 = unit_perpendicular(a, Vec3::UnitZ());
  const Vec3 e2 = a.cross(e1);
  const double reach = p.neck_radius_mm + p.labrum_neck_clearance_mm;
  const double radius = p.articular_radius_mm;
  // Samples of the section: the triangle (R, opening), (R + base, opening), (R, tip).
  constexpr int kSamples = 12;
  std::vector<std::pair<double, double>> section;  // (distance from the HJC, angle from a)
  for (int i = 0; i <= kSamples; ++i) {
    for (int j = 0; i + j <= kSamples; ++j) {
      const double u = static_cast<double>(i) / kSamples, v = static_cast<double>(j) / kSamples;
      // Barycentric in the (radial, angular) meridian coordinates of the three corners.
      const Eigen::Vector2d pa(radius * std::sin(opening), radius * std::cos(opening));
      const Eigen::Vector2d pb((radius + p.labrum_base_mm) * std::sin(opening), (radius + p.labrum_base_mm) * std::cos(opening));
      const Eigen::Vector2d pt(radius * std::sin(tip_angle), radius * std::cos(tip_angle));
      const Eigen::Vector2d q = (1.0 - u - v) * pa + u * pb + v * pt;
      section.emplace_back(q.norm(), std::atan2(q.x(), q.y()));
    }
  }
  constexpr int kAzimuths = 1440;
  std::vector<bool> hit(kAzimuths, false);
  for (int k = 0; k < kAzimuths; ++k) {
    const double psi = 2.0 * std::numbers::pi * k / kAzimuths - std::numbers::pi;
    const Vec3 across = std::cos(psi) * e1 + std::sin(psi) * e2;
    for (const auto& [distance, angle] : section) {
      const Vec3 q = distance * (std::cos(angle) * a + std::sin(angle) * across);
      const double along = q.dot(n);
      if (along >= 0.0 && along <= p.neck_length_mm && (q - along * n).norm() < reach) {
        hit[static_cast<std::size_t>(k)] = true;
        break;
      }
    }
  }
  const auto count = std::count(hit.begin(), hit.end(), true);
  if (count == 0) return std::nullopt;
  if (count == kAzimuths) throw_error("hip generator: the labrum lies around the femoral neck all the way round");
  // The longest circular run of hits, widened by one sample on each side.
  int best_start = 0, best_length = 0;
  for (int start = 0; start < kAzimuths; ++start) {
    if (!hit[static_cast<std::size_t>(start)] || hit[static_cast<std::size_t>((start + kAzimuths - 1) % kAzimuths)]) continue;
    int length = 0;
    while (length < kAzimuths && hit[static_cast<std::size_t>((start + length) % kAzimuths)]) ++length;
    if (length > best_length) {
      best_length = length;
      best_start = start;
    }
  }
  const double step = 2.0 * std::numbers::pi / kAzimuths;
  const double begin = -std::numbers::pi + (best_start - 1) * step;
  return std::make_pair(begin, begin + (best_length + 1) * step);
}

// Femur bone and femoral cartilage (see hip_generator.h for the recipe).
std::pair<DimTags, DimTags> femur_solids(const HipParameters& p) {
  const double radius = p.articular_radius_mm;
  const Vec3 n = neck_axis(p);
  // Head ball: centre s n, radius R - t + s, so the pole (-n) is t below the R sphere and the
  // two spheres meet at the cartilage edge angle phi_e from n:
  //   R^2 + s^2 - 2 R s cos(phi_e) = (R - t + s)^2  =>  s = (R^2 - (R-t)^2) / (2 (R - t + R cos phi_e)).
  // The margin and the junction are circles about n; neither may lie on a foot of the cam.
  const double inner = radius - p.femoral_cartilage_mm;
  const double edge = circle_apart_from_cam(p, p.femoral_cartilage_edge_deg) * kDegToRad;
  const double shift = (radius * radius - inner * inner) / (2.0 * (inner + radius * std::cos(edge)));
  const double head_radius = inner + shift;
  const double junction = circle_apart_from_cam(p, std::min(p.alpha_deg, p.normal_alpha_deg)) * kDegToRad;

  // The head's two spheres (head ball, R ball) meet the junction plane and each other on circles
  // about n: between the junction and the margin the bone's head is a band of the R sphere. Where
  // the seam of ball() comes within that band's outer circle of n, as a retroverted neck brings
  // about (femoral version below about -4 deg at CCD 110-146: the seam 35-40 deg from n, through
  // the cut-away neck cap, so that it cuts the band twice), OpenCASCADE's booleans leave faces gmsh
  // cannot mesh ("Impossible to mesh periodic surface"), fail, or do not finish. The femoral spheres
  // then take the seam's other half if that lies farther from n: 58 deg or more over the
  // generator's whole range of neck-shaft angle and version (the poles, where ball() always has
  // them, 57 deg or more). Hips whose seam stays outside the band, the study grid's among them (the
  // default neck: 53 deg), are built as before. (Poles on the neck axis instead, the head's circles
  // then parallels and the seam opposite the cam, failed on 2 of 30 random hips, version -10 to 6 deg.)
  const bool other_seam_half =
      angle_to_seam(n, false) <= std::max(junction, edge) && angle_to_seam(n, true) > angle_to_seam(n, false);
  auto femoral_ball = [&](const Vec3& centre, double r) { return ball(centre, r, other_seam_half); };
  // Bone head: head ball within the R sphere, cut by the plane normal to n through the circle at
  // the junction angle; neck side of that plane is left to the neck cylinder, so the contour
  // leaves the sphere inwards there (a 90 - junction deg kink, easy to measure).
  DimTags head = intersect(femoral_ball(shift * n, head_radius), femoral_ball(Vec3::Zero(), radius));
  head = intersect(head, cylinder(radius * std::cos(junction) * n, -(3.0 * radius) * n, 2.0 * radius));
  DimTags bone = fuse(head, cylinder(Vec3::Zero(), p.neck_length_mm * n, p.neck_radius_mm));
  // Shaft stub along -Z, starting above the end of the neck so the tilted neck end is buried.
  const Vec3 neck_end = p.neck_length_mm * n;
  const double above = p.neck_radius_mm + 2.0;
  bone = fuse(bone, cylinder(neck_end + above * Vec3::UnitZ(),
                             -(above + p.shaft_length_mm) * Vec3::UnitZ(), p.shaft_radius_mm));

  DimTags cartilage_tools = femoral_ball(shift * n, head_radius);
  if (p.alpha_deg > p.normal_alpha_deg) {
    // The cam's cross-section in each clock plane: a circle of radius rc standing h out of the R
    // sphere, centre distance D = R + h - rc from the HJC; its intersection with the R sphere
    // has angular radius delta seen from the HJC (law of cosines). Placing the centre at
    // alpha - delta from n puts the far point of that intersection, where the contour walking
    // from the pole first leaves the sphere, at exactly alpha. The circle is swept about the neck
    // axis over the cam arc, and balls close both ends (the cam tapers over them).
    bone = fuse(bone, cam_solids(p));
    for (const auto& dim_tag : cam_solids(p)) cartilage_tools.push_back(dim_tag);
  }
  // The cartilage lens: R ball minus the head ball (and minus the cam, which replaces it).
  return {bone, cut(femoral_ball(Vec3::Zero(), radius), cartilage_tools)};
}

// The direction in the meridian plane of `towards` (perpendicular to the acetabular axis a) at
// `angle` from a.
Vec3 meridian(const Vec3& a, const Vec3& towards, double angle) {
  return Vec3(std::cos(angle) * a + std::sin(angle) * unit_perpendicular(a, towards));
}

// The pelvis block with the socket of radius R + cartilage, restricted to the socket's side.
DimTags acetabular_bone_solid(const HipParameters& p, const Vec3& a, double opening, double big) {
  const Vec3 block_centre(-p.pelvis_block_x_mm / 4.0, 0.0, 0.1 * p.pelvis_block_z_mm);
  const Vec3 block_min = block_centre - 0.5 * Vec3(p.pelvis_block_x_mm, p.pelvis_block_y_mm,
                                                   p.pelvis_block_z_mm);
  DimTags block = {{3, occ::addBox(block_min.x(), block_min.y(), block_min.z(),
                                   p.pelvis_block_x_mm, p.pelvis_block_y_mm, p.pelvis_block_z_mm)}};
  block = restrict_to_socket(block, a, opening, big);
  return cut(block, ball(Vec3::Zero(), p.articular_radius_mm + p.acetabular_cartilage_mm));
}

// The horseshoe: the socket's shell of cartilage without the fossa, open at the notch where the
// fossa does not reach the rim.
DimTags acetabular_cartilage_solid(const HipParameters& p, const Vec3& a, double opening, double big) {
  const double radius = p.articular_radius_mm;
  const double socket_radius = radius + p.acetabular_cartilage_mm;
  // Inferior rim direction. The acetabular fossa is part of the pelvis, not of the rim: its axis
  // lies 30 deg beyond the inferior rim of the hemispherical socket towards the acetabular pole
  // -a, whatever the rim's depth (a rim that moved with CE would bring the fossa under the
  // loaded dome of a shallow socket).
  const Vec3 inferior_rim = meridian(a, -Vec3::UnitZ(), opening);
  const double fossa_tilt = 30.0 * kDegToRad;
  const double half_pi = 0.5 * std::numbers::pi;
  const Vec3 fossa_axis = meridian(a, -Vec3::UnitZ(), half_pi + fossa_tilt);
  DimTags shell = cut(ball(Vec3::Zero(), socket_radius), ball(Vec3::Zero(), radius));
  shell = restrict_to_socket(shell, a, opening, big);
  const double fossa_radius =
      (radius + 0.5 * p.acetabular_cartilage_mm) * std::sin(p.fossa_half_angle_deg * kDegToRad);
  DimTags acetabular_cartilage =
      cut(shell, cylinder(Vec3::Zero(), (socket_radius + 20.0) * fossa_axis, fossa_radius));
  // The horseshoe is open at the notch: where the fossa does not reach the (deeper) rim, the
  // labrum's notch gap is cut through the cartilage too.
  const double fossa_reach = half_pi + fossa_tilt -
                             std::asin(std::min(1.0, fossa_radius / (radius + 0.5 * p.acetabular_cartilage_mm)));
  if (fossa_reach > opening) {
    acetabular_cartilage = cut(acetabular_cartilage, cylinder(Vec3::Zero(), (socket_radius + 20.0) * inferior_rim,
                                                              0.5 * p.notch_width_mm));
  }
  return acetabular_cartilage;
}

// The wedge between two half-planes through the acetabular axis a, at the azimuths of `sector`.
DimTags neck_wedge(const std::pair<double, double>& sector, const Vec3& a, double big) {
  const Vec3 e1 = unit_perpendicular(a, Vec3::UnitZ());
  const Vec3 e2 = a.cross(e1);
  const Vec3 m0 = std::cos(sector.first) * e1 + std::sin(sector.first) * e2;
  const double extent = big;
  const Vec3 c0 = -extent * a, c1 = -extent * a + extent * m0, c2 = extent * a + extent * m0, c3 = extent * a;
  std::vector<int> corners;
  for (const Vec3& c : {c0, c1, c2, c3}) corners.push_back(occ::addPoint(c.x(), c.y(), c.z()));
  std::vector<int> sides;
  for (int k = 0; k < 4; ++k) sides.push_back(occ::addLine(corners[k], corners[(k + 1) % 4]));
  const int face = occ::addPlaneSurface({occ::addCurveLoop(sides)});
  DimTags wedge_parts;
  occ::revolve({{2, face}}, 0, 0, 0, a.x(), a.y(), a.z(), sector.second - sector.first, wedge_parts);
  DimTags wedge;
  for (const auto& dim_tag : wedge_parts) {
    if (dim_tag.first == 3) wedge.push_back(dim_tag);
  }
  occ::remove({{2, face}}, true);
  return wedge;
}

// Labrum: triangular section in a meridian plane of a, revolved about a: base on the rim cone
// from R to R + base, tip on the R sphere asin(labrum_height / R) nearer the axis than the rim
// (the section of a hemispherical socket, whose tip stands labrum_height above the rim plane,
// turned with the rim); open at the notch.
DimTags labrum_solid(const HipParameters& p, const Vec3& a, double opening, double big) {
  const double radius = p.articular_radius_mm;
  const double tip_angle = opening - std::asin(p.labrum_height_mm / radius);
  const Vec3 pa = radius * meridian(a, Vec3::UnitZ(), opening);
  const Vec3 pb = (radius + p.labrum_base_mm) * meridian(a, Vec3::UnitZ(), opening);
  const Vec3 pt = radius * meridian(a, Vec3::UnitZ(), tip_angle);
  const int origin_tag = occ::addPoint(0, 0, 0);
  const int a_tag = occ::addPoint(pa.x(), pa.y(), pa.z());
  const int b_tag = occ::addPoint(pb.x(), pb.y(), pb.z());
  const int t_tag = occ::addPoint(pt.x(), pt.y(), pt.z());
  const int base_line = occ::addLine(a_tag, b_tag);
  const int outer_line = occ::addLine(b_tag, t_tag);
  const int inner_arc = occ::addCircleArc(t_tag, origin_tag, a_tag);
  const int loop = occ::addCurveLoop({base_line, outer_line, inner_arc});
  const int section = occ::addPlaneSurface({loop});
  DimTags revolved;
  occ::revolve({{2, section}}, 0, 0, 0, a.x(), a.y(), a.z(), 2.0 * std::numbers::pi, revolved);
  occ::remove({{0, origin_tag}});
  DimTags labrum;
  for (const auto& dim_tag : revolved) {
    if (dim_tag.first == 3) labrum.push_back(dim_tag);
  }
  occ::remove({{2, section}}, true);
  const Vec3 inferior_rim = meridian(a, -Vec3::UnitZ(), opening);
  labrum = cut(labrum, cylinder(Vec3::Zero(), (radius + p.labrum_base_mm + 20.0) * inferior_rim,
                                0.5 * p.notch_width_mm));
  // Where the femoral neck passes under the rim in the neutral pose, the labrum stops short of
  // it. A deep socket (CE 30-40 deg, its rim turned towards the neck all around) brings the
  // posteroinferior rim within the neck's cone (the neck leaves the head sphere
  // asin(neck_radius / R) from its axis), and a full-height labrum there would stand inside the
  // bone before any motion. In a hip the labrum ends at the acetabular notch, which the
  // transverse acetabular ligament bridges below the head (Seldes et al. 2001), and is never
  // inside the neck: the labrum is removed over the sector of azimuths (about the acetabular
  // axis) in which any of it comes within the neck radius plus a clearance of the neck axis. The
  // sector's faces are half-planes through the acetabular axis, radial like the rim (a plane
  // cut meshes into hexahedral columns from the HJC). Hips whose rim stays clear of the neck are
  // unchanged.
  if (const auto sector = labrum_neck_sector(p, a, opening, tip_angle)) labrum = cut(labrum, neck_wedge(*sector, a, big));
  // A neck sector that ends just short of the notch leaves a sliver of labrum between the two cuts
  // (2-14 mm^3 on sampled hips with CE 27-28 deg), no labrum but a remnant too short to carry a
  // section: the pieces that hold less than one base width of the section along the rim
  // (labrum_base_mm x the section's triangle, base by height) are removed. A labrum in one piece,
  // every grid hip's, is unchanged.
  if (labrum.size() > 1) {
    const double least_mm3 = p.labrum_base_mm * 0.5 * p.labrum_base_mm * p.labrum_height_mm;
    DimTags kept;
    for (const auto& piece : labrum) {
      double volume = 0.0;
      occ::getMass(piece.first, piece.second, volume);
      if (volume >= least_mm3) {
        kept.push_back(piece);
      } else {
        occ::remove({piece}, true);
      }
    }
    if (!kept.empty()) labrum = kept;
  }
  return labrum;
}

struct TissueSolids {
  std::vector<std::pair<std::string, DimTags>> tissues;
};

// The socket's opening as built (deg from the acetabular axis a to the rim cone). restrict_to_socket
// cuts with a cone of height `big` whose base has radius big tan(half-angle): within 1e-4 deg of a
// hemisphere (CE within about 1e-4 deg of hemisphere_ce_deg) that is 1e8 mm and more, and
// OpenCASCADE's booleans fail ("Intersection operation cannot be performed") or leave periodic
// faces gmsh cannot mesh. A rim cone within kFlatRimRad of the plane is therefore built as the
// plane, for every tissue alike: the rim moves by at most 1e-4 rad, 3 um on the socket and
// 0.006 deg of CE, and cones that far from flat and beyond build and mesh (measured on these hips:
// the failures need CE within 1e-4 deg of the hemisphere's). The hemisphere itself (within 1e-9
// rad, built as the plane already) keeps its computed value, so those hips are unchanged.
double built_socket_opening_deg(const HipParameters& p) {
  constexpr double kFlatRimRad = 1e-4;
  const double opening_deg = socket_opening_deg(p);
  const double off_rad = std::abs(opening_deg - 90.0) * kDegToRad;
  return off_rad >= 1e-9 && off_rad < kFlatRimRad ? 90.0 : opening_deg;
}

// The five tissues as OCC solids in the current model (see hip_generator.h for the recipe), made
// in a fixed order: OpenCASCADE numbers the entities as they are made, and the meshes follow.
TissueSolids build_solids(const HipParameters& p) {
  const double big = 4.0 * (p.pelvis_block_x_mm + p.pelvis_block_y_mm + p.pelvis_block_z_mm);
  const Vec3 a = acetabular_axis(p);
  const double opening = built_socket_opening_deg(p) * kDegToRad;
  TissueSolids solids;
  const auto [bone, femoral_cartilage] = femur_solids(p);
  solids.tissues.emplace_back("femur_bone", bone);
  solids.tissues.emplace_back("femoral_cartilage", femoral_cartilage);
  DimTags acetabular_bone = acetabular_bone_solid(p, a, opening, big);
  DimTags acetabular_cartilage = acetabular_cartilage_solid(p, a, opening, big);
  // A deep socket can reach the femoral neck in the neutral pose: the neck's cylinder, widened by the
  // labrum's clearance, meets the socket's shell at the R sphere where the angle from a to n plus
  // its angular radius there, asin((neck radius + clearance) / R), exceeds the opening. The labrum
  // is cut back over the neck's sector (labrum_solid); the acetabular cartilage and the bone's rim
  // are cut back from the neck by that cylinder, the same modelling choice (in a hip the rim is not
  // inside the neck at rest). Uncut, they stood up to 4.7 mm inside the femur bone (deep sockets
  // with an anteverted or varus neck: 6 of 60 random hips with the neck varied, CE 33-44). The
  // study grid's hips stay clear (CE 40 at the default neck: 1.6 deg) and are unchanged.
  const Vec3 n = neck_axis(p);
  const double neck_clear_mm = p.neck_radius_mm + p.labrum_neck_clearance_mm;
  const double past_rim = std::acos(std::clamp(a.dot(n), -1.0, 1.0)) +
                          std::asin(std::min(1.0, neck_clear_mm / p.articular_radius_mm)) - opening;
  if (past_rim > 0.0) {
    acetabular_bone = cut(acetabular_bone, cylinder(Vec3::Zero(), p.neck_length_mm * n, neck_clear_mm));
    acetabular_cartilage = cut(acetabular_cartilage, cylinder(Vec3::Zero(), p.neck_length_mm * n, neck_clear_mm));
  }
  const DimTags labrum = labrum_solid(p, a, opening, big);
  solids.tissues.emplace_back("acetabular_bone", acetabular_bone);
  solids.tissues.emplace_back("acetabular_cartilage", acetabular_cartilage);
  solids.tissues.emplace_back("labrum", labrum);
  occ::synchronize();
  for (const auto& [name, dim_tags] : solids.tissues) {
    if (dim_tags.empty()) throw_error("hip generator: ", name, ": OpenCASCADE produced no solid");
  }
  return solids;
}

void set_mesh_options(double edge_mm) {
  gmsh::option::setNumber("Mesh.MeshSizeMax", edge_mm);
  gmsh::option::setNumber("Mesh.MeshSizeMin", 0.1 * edge_mm);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
  gmsh::option::setNumber("Mesh.Algorithm", 6);  // Frontal-Delaunay: well-shaped triangles
  gmsh::option::setNumber("General.NumThreads", 1);
}

// Runs gmsh::model::mesh::generate(dim) and returns its error messages (empty on success). The
// mesher reports errors from inside OpenMP regions, where a thrown exception would terminate the
// process, so errors are logged (AbortOnError 0) and collected instead of thrown.
std::string generate_logging_errors(int dim) {
  gmsh::option::setNumber("General.AbortOnError", 0);
  gmsh::logger::start();
  gmsh::model::mesh::generate(dim);
  std::vector<std::string> log;
  gmsh::logger::get(log);
  gmsh::logger::stop();
  gmsh::option::setNumber("General.AbortOnError", 2);
  std::string errors;
  for (const auto& line : log) {
    if (line.rfind("Error", 0) == 0) errors += (errors.empty() ? "" : "; ") + line;
  }
  return errors;
}

// Longest triangle edge of the current surface mesh (mm).
double longest_surface_edge() {
  std::vector<std::size_t> tags;
  std::vector<double> coords, parametric;
  gmsh::model::mesh::getNodes(tags, coords, parametric, -1, -1, true, false);
  std::unordered_map<std::size_t, std::size_t> slot;
  for (std::size_t i = 0; i < tags.size(); ++i) slot.emplace(tags[i], i);
  auto at = [&](std::size_t tag) {
    const double* xyz = &coords[3 * slot.at(tag)];
    return Vec3(xyz[0], xyz[1], xyz[2]);
  };
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> element_tags, node_tags;
  gmsh::model::mesh::getElements(types, element_tags, node_tags, 2, -1);
  double longest = 0.0;
  for (std::size_t k = 0; k < types.size(); ++k) {
    if (types[k] != 2) continue;
    const auto& nodes = node_tags[k];
    for (std::size_t i = 0; i + 2 < nodes.size(); i += 3) {
      for (int c = 0; c < 3; ++c) {
        longest = std::max(longest, (at(nodes[i + static_cast<std::size_t>(c)]) -
                                     at(nodes[i + static_cast<std::size_t>((c + 1) % 3)])).norm());
      }
    }
  }
  return longest;
}

// Surface mesh of every entity. Frontal-Delaunay gives the best triangles but can fail on the
// small seam curves OCC leaves on spheres at coarse sizes; MeshAdapt and Delaunay are the fallbacks.
// A mesh with a triangle edge over four target edges (a triangle spanning a spherical face whose
// parametrisation the mesher mishandled; seen on socket caps) counts as a failure too.
constexpr std::array<int, 3> kSurfaceAlgorithms{6, 1, 5};

// What the meshing child tells its parent, in order: one record per algorithm it starts, one per
// algorithm that fails (its errors), then the tissues, a fatal error, or nothing (every algorithm
// failed). A record is a type byte, a 64-bit length and that many bytes.
enum class Record : char {
  kStarting = 'A',   // payload: the index into kSurfaceAlgorithms
  kFailed = 'F',     // payload: the algorithm's errors
  kTissues = 'T',    // payload: count, then (name, mesh bytes) per tissue
  kError = 'E',      // payload: a hipfai::Error's message
  kGmshError = 'G',  // payload: what gmsh threw outside the mesher's log
};

void send(int fd, Record type, const std::string& payload) {
  std::string bytes(1, static_cast<char>(type));
  const auto size = static_cast<std::uint64_t>(payload.size());
  bytes.append(reinterpret_cast<const char*>(&size), sizeof size);
  bytes += payload;
  if (!write_all(fd, bytes)) ::_exit(3);
}

// Meshes the surfaces with the algorithms from kSurfaceAlgorithms[first] on; true when one
// succeeded, false when all failed (each failure sent to `fd`).
bool mesh_surfaces(double edge_mm, std::size_t first, int fd) {
  for (std::size_t k = first; k < kSurfaceAlgorithms.size(); ++k) {
    const int algorithm = kSurfaceAlgorithms[k];
    send(fd, Record::kStarting, std::to_string(k));
    set_mesh_options(edge_mm);
    gmsh::option::setNumber("Mesh.Algorithm", algorithm);
    std::string errors = generate_logging_errors(2);
    if (errors.empty()) {
      const double longest = longest_surface_edge();
      if (longest <= 4.0 * edge_mm) return true;
      errors = "algorithm " + std::to_string(algorithm) + ": a triangle edge of " + std::to_string(longest) +
               " mm for a target of " + std::to_string(edge_mm) + " mm";
    }
    send(fd, Record::kFailed, errors);
    gmsh::model::mesh::clear();
  }
  return false;
}

// Makes neighbouring triangles traverse shared edges in opposite directions (breadth-first from
// one triangle per component), then flips a component whose enclosed volume is negative.
void orient_outward(TriMesh& mesh) {
  const std::size_t count = mesh.triangles.size();
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> edge_triangles;
  auto key = [](std::int32_t u, std::int32_t v) {
    const auto lo = static_cast<std::uint64_t>(std::min(u, v));
    const auto hi = static_cast<std::uint64_t>(std::max(u, v));
    return (lo << 32) | hi;
  };
  for (std::size_t t = 0; t < count; ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) edge_triangles[key(tri[k], tri[(k + 1) % 3])].push_back(t);
  }
  auto has_directed = [](const Triangle& tri, std::int32_t u, std::int32_t v) {
    for (int k = 0; k < 3; ++k) {
      if (tri[k] == u && tri[(k + 1) % 3] == v) return true;
    }
    return false;
  };
  std::vector<int> component(count, -1);
  int components = 0;
  for (std::size_t seed = 0; seed < count; ++seed) {
    if (component[seed] >= 0) continue;
    std::queue<std::size_t> queue;
    queue.push(seed);
    component[seed] = components;
    while (!queue.empty()) {
      const std::size_t t = queue.front();
      queue.pop();
      const Triangle tri = mesh.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const std::int32_t u = tri[k];
        const std::int32_t v = tri[(k + 1) % 3];
        for (std::size_t other : edge_triangles[key(u, v)]) {
          if (other == t || component[other] >= 0) continue;
          // A consistent neighbour traverses the edge as v -> u.
          if (has_directed(mesh.triangles[other], u, v)) std::swap(mesh.triangles[other][1], mesh.triangles[other][2]);
          component[other] = components;
          queue.push(other);
        }
      }
    }
    ++components;
  }
  // Signed volume per component (divergence theorem), flip the negative ones.
  std::vector<double> volume(static_cast<std::size_t>(components), 0.0);
  for (std::size_t t = 0; t < count; ++t) {
    const auto& tri = mesh.triangles[t];
    volume[static_cast<std::size_t>(component[t])] +=
        mesh.vertices[static_cast<std::size_t>(tri[0])].dot(
            mesh.vertices[static_cast<std::size_t>(tri[1])].cross(mesh.vertices[static_cast<std::size_t>(tri[2])])) / 6.0;
  }
  for (std::size_t t = 0; t < count; ++t) {
    if (volume[static_cast<std::size_t>(component[t])] < 0.0) std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
  }
}

// The surface triangles of `volumes` as one TriMesh (nodes shared between its surfaces).
struct NodeTable {
  std::unordered_map<std::size_t, std::size_t> slot;  // node tag -> index into coords / 3
  std::vector<double> coords;
};

NodeTable all_nodes() {
  NodeTable table;
  std::vector<std::size_t> tags;
  std::vector<double> parametric;
  gmsh::model::mesh::getNodes(tags, table.coords, parametric, -1, -1, true, false);
  for (std::size_t i = 0; i < tags.size(); ++i) table.slot.emplace(tags[i], i);
  return table;
}

TriMesh extract_surface(const DimTags& volumes, const std::string& name, const NodeTable& nodes_table) {
  DimTags surfaces;
  gmsh::model::getBoundary(volumes, surfaces, true, false, false);
  TriMesh mesh;
  std::unordered_map<std::size_t, std::int32_t> index_of;
  for (const auto& [dim, tag] : surfaces) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> element_tags, node_tags;
    gmsh::model::mesh::getElements(types, element_tags, node_tags, dim, std::abs(tag));
    for (std::size_t k = 0; k < types.size(); ++k) {
      if (types[k] != 2) throw_error("hip generator: ", name, ": unexpected element type ", types[k]);
      const auto& nodes = node_tags[k];
      for (std::size_t i = 0; i + 2 < nodes.size(); i += 3) {
        Triangle tri{};
        for (int c = 0; c < 3; ++c) {
          const std::size_t node = nodes[i + static_cast<std::size_t>(c)];
          auto [it, inserted] = index_of.try_emplace(node, static_cast<std::int32_t>(mesh.vertices.size()));
          if (inserted) {
            const auto found = nodes_table.slot.find(node);
            if (found == nodes_table.slot.end()) throw_error("hip generator: ", name, ": unknown mesh node");
            const double* xyz = &nodes_table.coords[3 * found->second];
            mesh.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
          }
          tri[static_cast<std::size_t>(c)] = it->second;
        }
        mesh.triangles.push_back(tri);
      }
    }
  }
  if (mesh.empty()) throw_error("hip generator: ", name, ": the surface mesh is empty");
  orient_outward(mesh);
  return mesh;
}

// The meshing child: builds the solids, meshes them (algorithms from `first` on) and sends the
// tissues, or the reason there are none.
void build_and_mesh(const HipParameters& parameters, std::size_t first, int fd) {
  start_gmsh_model("hip");
  try {
    const TissueSolids solids = build_solids(parameters);
    if (!mesh_surfaces(parameters.edge_mm, first, fd)) return;
    const NodeTable table = all_nodes();
    std::string tissues;
    const auto count = static_cast<std::uint64_t>(solids.tissues.size());
    tissues.append(reinterpret_cast<const char*>(&count), sizeof count);
    for (const auto& [name, volumes] : solids.tissues) {
      const auto length = static_cast<std::uint64_t>(name.size());
      tissues.append(reinterpret_cast<const char*>(&length), sizeof length);
      tissues += name;
      append_mesh_bytes(tissues, extract_surface(volumes, name, table));
    }
    send(fd, Record::kTissues, tissues);
  } catch (const Error& e) {
    send(fd, Record::kError, e.what());
  } catch (const std::exception& e) {
    send(fd, Record::kGmshError, e.what());
  } catch (const std::string& message) {  // the gmsh API throws its last error as a string
    send(fd, Record::kGmshError, message);
  }
}

// --- the mesher's own process image ---------------------------------------------------------
// gmsh and OpenCASCADE order some of their entities by address (hash maps of shapes and mesh
// vertices), so a mesh can depend on where the meshing process' memory lies: with the address
// space randomised on every run, and, in a forked child, on the heap the parent leaves behind.
// One hip of an estimator sample meshed with 443 or 446 femur vertices, about one run in forty.
// So the forked child execs a fresh image of the same program with address randomisation off
// (exec_fresh_image), which meshes at the same addresses every time: measured, one hip generated
// twice in a process differed in one run of six with the fresh image at random addresses, in none
// of twelve with randomisation off. The request travels in the environment (the parameters' bytes
// in hex: the same program reads them), the answer through the inherited pipe.
constexpr const char* kMesherVariable = "HIPFAI_HIP_MESHER";
static_assert(std::is_trivially_copyable_v<HipParameters>);

std::string mesher_request(const HipParameters& parameters, std::size_t first, int fd) {
  std::ostringstream out;
  out << fd << ' ' << first << ' ';
  const auto* bytes = reinterpret_cast<const unsigned char*>(&parameters);
  constexpr char kHex[] = "0123456789abcdef";
  for (std::size_t i = 0; i < sizeof parameters; ++i) out << kHex[bytes[i] >> 4] << kHex[bytes[i] & 15];
  return out.str();
}

// In the fresh image, before main: meshes the request of kMesherVariable and exits; false (and
// nothing done) in any other process.
bool mesh_if_requested() {
  const char* request = std::getenv(kMesherVariable);
  if (request == nullptr) return false;
  std::istringstream in(request);
  int fd = -1;
  std::size_t first = 0;
  std::string hex;
  HipParameters parameters;
  if (!(in >> fd >> first >> hex) || fd < 0 || first >= kSurfaceAlgorithms.size() || hex.size() != 2 * sizeof parameters) {
    ::_exit(4);
  }
  auto* bytes = reinterpret_cast<unsigned char*>(&parameters);
  for (std::size_t i = 0; i < sizeof parameters; ++i) {
    bytes[i] = static_cast<unsigned char>(std::stoi(hex.substr(2 * i, 2), nullptr, 16));
  }
  gmsh::initialize();
  build_and_mesh(parameters, first, fd);
  ::close(fd);
  ::_exit(0);  // no static destructors: gmsh is left as it is, as in a forked child
}

[[maybe_unused]] const bool kMeshedAsRequested = mesh_if_requested();

std::uint64_t take_u64(std::string_view& in, const std::string& what) {
  std::uint64_t value = 0;
  if (in.size() < sizeof value) throw_error(what, ": truncated answer from the meshing process");
  std::memcpy(&value, in.data(), sizeof value);
  in.remove_prefix(sizeof value);
  return value;
}

// One record of the child's answer: its type and payload; nothing when the rest of the answer is
// cut short (the child crashed while writing it).
struct ChildRecord {
  Record type;
  std::string_view payload;
};

std::optional<ChildRecord> take_record(std::string_view& in) {
  if (in.size() < 1 + sizeof(std::uint64_t)) return std::nullopt;
  const auto type = static_cast<Record>(in.front());
  std::uint64_t length = 0;
  std::memcpy(&length, in.data() + 1, sizeof length);
  if (in.size() - 1 - sizeof length < length) return std::nullopt;
  const std::string_view payload = in.substr(1 + sizeof length, length);
  in.remove_prefix(1 + sizeof length + length);
  return ChildRecord{type, payload};
}

std::map<std::string, TriMesh> read_tissues(std::string_view in, const std::string& what) {
  std::map<std::string, TriMesh> tissues;
  const std::uint64_t count = take_u64(in, what);
  for (std::uint64_t k = 0; k < count; ++k) {
    const std::uint64_t length = take_u64(in, what);
    if (in.size() < length) throw_error(what, ": truncated answer from the meshing process");
    std::string name(in.substr(0, length));
    in.remove_prefix(length);
    tissues.emplace(name, read_mesh_bytes(in, what + ": " + name));
  }
  return tissues;
}

}  // namespace

HipGeneratorResult generate_hip(const HipParameters& parameters) {
  validate_hip_parameters(parameters);
  const auto start = std::chrono::steady_clock::now();
  HipGeneratorResult result;
  std::ostringstream label;
  label << "hip generator (ce " << parameters.ce_deg << ", alpha " << parameters.alpha_deg << ")";
  const std::string what = label.str();
  // gmsh meshes in a forked child: a crash inside the mesher (Debian's gmsh 4.8 frees a point twice
  // in BDS_Mesh::del_point after failing on a periodic spherical face) ends the child, and the next
  // algorithm is tried in a new one. The lock keeps every other thread out of gmsh while the child
  // is forked, so the child's copy of gmsh is whole.
  const auto gmsh_lock = lock_gmsh();
  ChildRequest request;
  request.silence_output = !gmsh_verbose();
  // A time limit per child, since gmsh can also loop for ever (seen on a 1.5 mm hip whose 2 mm
  // twin crashes): a hip takes 2-5 s at 2 mm and its time grows as the triangle count, so the limit
  // is 40x that, scaled the same way; the limit ends only that algorithm's try.
  const double scale = std::max(1.0, (2.0 / parameters.edge_mm) * (2.0 / parameters.edge_mm));
  request.seconds = static_cast<unsigned>(std::ceil(std::min(200.0 * scale, 86400.0)));
  std::string failures;
  auto add_failure = [&failures](const std::string& failure) {
    failures += (failures.empty() ? "" : " | ") + failure;
  };
  std::size_t first = 0;
  for (;;) {
    const ChildOutcome outcome = run_in_child(
        [&](int fd) {
          exec_fresh_image(kMesherVariable, mesher_request(parameters, first, fd), fd);
          build_and_mesh(parameters, first, fd);  // the exec failed: mesh from the inherited heap
        },
        request, what + ": cannot start the meshing process");
    std::string_view answer = outcome.answer;
    std::optional<std::size_t> started;
    while (const std::optional<ChildRecord> record = take_record(answer)) {
      const std::string_view payload = record->payload;
      switch (record->type) {
        case Record::kStarting: started = std::stoul(std::string(payload)); break;
        case Record::kFailed: add_failure(std::string(payload)); break;
        case Record::kTissues: if (outcome.ok) result.model.tissues = read_tissues(payload, what); break;
        case Record::kError: if (outcome.ok) throw Error(std::string(payload)); break;
        case Record::kGmshError: if (outcome.ok) throw_error(what, ": gmsh failed: ", payload); break;
      }
    }
    if (outcome.ok) {
      if (result.model.tissues.empty()) throw_error(what, ": gmsh failed: ", failures);
      result.model.surface_algorithm = kSurfaceAlgorithms[started.value_or(first)];
      result.model.mesher_failures = failures;
      break;
    }
    if (!started) throw_error(what, ": gmsh ", outcome.failure(request.seconds), " building the solids");
    add_failure("algorithm " + std::to_string(kSurfaceAlgorithms[*started]) + ": gmsh " + outcome.failure(request.seconds));
    first = *started + 1;
    if (first == kSurfaceAlgorithms.size()) throw_error(what, ": gmsh failed: ", failures);
  }
  HipModel& model = result.model;
  model.parameters = parameters;
  model.hjc_mm = Vec3::Zero();
  model.axes = HipFrameAxes{};
  model.neck_axis = neck_axis(parameters);
  model.superior = Vec3::UnitZ();
  model.lateral = Vec3::UnitX();
  model.acetabular_axis = acetabular_axis(parameters);
  model.socket_opening_deg = built_socket_opening_deg(parameters);
  // The clinical angles measured back on the meshes (never from the parameters above).
  const auto ce = measure_ce_angle({&model.tissue("acetabular_bone"), &model.tissue("acetabular_cartilage")},
                                   model.hjc_mm, model.lateral, model.superior);
  const auto alpha = measure_alpha_angle({&model.tissue("femur_bone"), &model.tissue("femoral_cartilage")},
                                         model.hjc_mm, model.neck_axis, model.superior, Vec3::UnitY());
  if (ce.status == MeasureStatus::kOk) model.measured_ce_deg = ce.ce_deg;
  if (alpha.status == MeasureStatus::kOk) model.measured_alpha_notzli_deg = alpha.alpha_deg;
  if (alpha.max_alpha_deg >= 0.0) {
    model.measured_alpha_max_deg = alpha.max_alpha_deg;
    model.measured_alpha_max_clock_deg = alpha.max_plane_deg;
  }
  model.alpha_profile = alpha.profile;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.status = HipGeneratorResult::Status::kOk;
  return result;
}

}  // namespace hipfai::geometry
