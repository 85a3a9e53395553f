// hipfai — the joint range finder (thesis §4.2, Fig. 54): exact range of motion about an axis in
// one pass, without stepping.
//
// For every mobile vertex whose circle about the axis crosses the fixed mesh (ring table of
// cylindrical_table.h), the crossing angles follow in closed form (App. C). Rotating the mobile
// mesh anticlockwise (right-hand rule about the axis) by phi, a vertex at theta_v first meets the
// crossing at theta_k after phi = (theta_k - theta_v) mod 2pi; clockwise after
// (theta_v - theta_k) mod 2pi. The range of motion in each direction is the smallest such angle
// over all vertices and crossings: the rotation before the first contact.
//
// Work (the mesh overload). Once per body pair and axis, everything whose (r, z) lies where the
// other body has nothing is dropped (contact/axis_reach.h). The vertex passes then read the
// crossings straight from the tables (the overload of two pose caches reads stored ones), and a
// candidate triangle, or edge pair, is evaluated only if the rotations that bring their angular
// extents together include one shorter than the ranges found so far (offers are strict, so a
// skipped candidate could have changed nothing). Both are exact; options switch them off.
//
// Contact types. A contact between two triangle meshes starts as vertex-on-triangle or
// edge-on-edge. Both vertex-on-triangle types are covered: mobile vertices against fixed
// triangles, and fixed vertices against mobile triangles (the same computation with the roles
// swapped: the mobile rotating anticlockwise is the fixed mesh rotating clockwise relative to it,
// so the swapped pass's clockwise range limits the anticlockwise one and vice versa).
// Edge-edge first contacts (two sharp rims crossing, no vertex touching first; the thesis'
// vertex-only finder over-estimates them by up to the mesh resolution) are found in closed form
// when include_edge_edge is set: in the axis frame, rotating the mobile edge P + s D by theta,
// the two edges' lines are coplanar iff det[R P - Q, R D, E] = 0 for the fixed edge Q + u E, and
// since det[R P, R D, E] = (P x D) . (R^T E) and det[Q, R D, E] = (E x Q) . (R D), this is
// a cos(theta) + b sin(theta) + c = 0 with a, b, c from the edges' coordinates: at most two roots,
// theta = atan2(b, a) +- acos(-c / hypot(a, b)). A root is a contact iff the lines meet inside
// both segments (s, u in [0, 1]); the smallest positive root (and the smallest negative one in
// magnitude) limit the two directions. Pairs are culled by the edges' extents in radius and
// height (rotation keeps both, so edges can only meet where these overlap) on a grid in (r, z),
// the ring table idea applied to edges. Parallel edges (a = b = 0) and contacts at an edge's end
// are left to the vertex passes: an end point on the other edge is a vertex on a closed triangle.
// Edge pairs touching at the start pose (root |theta| <= 1e-12 rad) are ignored, as if moving
// away from them were free; the vertex passes decide resting contacts.
//
// A vertex already on the surface (arc distance <= touching_mm) limits a direction to 0 only if
// moving that way enters the other solid (the crossing's outward normal opposes the motion);
// moving away from a resting contact is free. Unlimited directions report 360 degrees with
// LimitingContact::kind == kNone. The start pose is assumed collision-free; if it is not, the
// ranges are those to the first surface crossing of any vertex.
#pragma once

#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "contact/penetration_result.h"
#include "geometry/tri_mesh.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hipfai::contact {

enum class ContactKind {
  kNone,                         // no contact in this direction within a full turn
  kMobileVertexOnFixedTriangle,
  kFixedVertexOnMobileTriangle,
  kEdgeOnEdge,                   // a mobile edge crosses a fixed edge (include_edge_edge)
};

struct LimitingContact {
  ContactKind kind = ContactKind::kNone;
  std::int32_t vertex = -1;    // of the mobile mesh (kMobileVertex...) or the fixed mesh
  std::int32_t triangle = -1;  // of the other mesh
  // kEdgeOnEdge: the two vertices of the mobile edge and of the fixed edge (vertex/triangle -1).
  std::array<std::int32_t, 2> mobile_edge{-1, -1};
  std::array<std::int32_t, 2> fixed_edge{-1, -1};
};

struct RangeOfMotion {
  QueryStatus status = QueryStatus::kOk;
  std::string message;
  double anticlockwise_deg = 360.0;  // largest free rotation by +angle (right-hand rule)
  double clockwise_deg = 360.0;      // largest free rotation by -angle
  LimitingContact anticlockwise_limit;
  LimitingContact clockwise_limit;
};

struct RangeOfMotionOptions {
  bool include_fixed_vertices = true;  // also fixed vertices against mobile triangles
  bool include_edge_edge = true;       // also edge-edge first contacts (exact, closed form)
  // Drop, once per body pair and axis, every vertex, triangle and edge whose (r, z) about the axis
  // lies where the other body has nothing (contact/axis_reach.h): they meet nothing at any angle,
  // so the ranges and limiting contacts are the same (indices are of the input meshes); every
  // pass then runs on what is left. false: every pass over the whole meshes (the reference).
  bool cull_unreachable = true;
  // Skip a candidate (triangle for a vertex, edge for an edge) when the rotations that bring their
  // angular extents about the axis together are all at least as far as the ranges found so far:
  // it could not limit either direction. false: every candidate evaluated (the reference).
  bool angular_pruning = true;
  CylindricalTableOptions table;
  CylindricalQueryOptions query;
};

// Range of motion of `mobile` (at pose 0) rotating about `axis` through `centre` against `fixed`.
RangeOfMotion range_of_motion(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                              const Vec3& centre, const Vec3& axis,
                              const RangeOfMotionOptions& options = {});

// The same from pre-processed data: `mobile_on_fixed` (mobile vertices, fixed table) and, when
// not null, `fixed_on_mobile` (fixed vertices, table of the mobile mesh at pose 0, same axis).
RangeOfMotion range_of_motion(const CylindricalPoseCache& mobile_on_fixed,
                              const CylindricalPoseCache* fixed_on_mobile, int num_threads = 0);

// One axis of a fan or sphere sweep with its range.
struct AxisRangeOfMotion {
  Vec3 axis = Vec3::UnitZ();
  double angle_deg = 0.0;      // fan: angle of the axis in the plane; sphere: polar angle
  double azimuth_deg = 0.0;    // sphere only
  RangeOfMotion range;
};

// Fig. 56: axes in the plane perpendicular to `plane_normal`, at angles 180 * i / steps degrees
// (i = 0 .. steps-1) from a reference direction of that plane (an axis and its opposite give the
// same ranges with the directions swapped, so half a turn covers every axis). The reference is the
// frame vector e1 of make_axis_frame(centre, plane_normal).
std::vector<AxisRangeOfMotion> range_of_motion_fan(const geometry::TriMesh& fixed,
                                                   const geometry::TriMesh& mobile,
                                                   const Vec3& centre, const Vec3& plane_normal,
                                                   int steps,
                                                   const RangeOfMotionOptions& options = {});

// A grid of axes on the upper hemisphere about `pole`: polar angles 90 * i / polar_steps degrees
// (i = 0 .. polar_steps), azimuths 360 * j / azimuth_steps (one axis at the pole).
std::vector<AxisRangeOfMotion> range_of_motion_sphere(const geometry::TriMesh& fixed,
                                                      const geometry::TriMesh& mobile,
                                                      const Vec3& centre, const Vec3& pole,
                                                      int polar_steps, int azimuth_steps,
                                                      const RangeOfMotionOptions& options = {});

}  // namespace hipfai::contact
