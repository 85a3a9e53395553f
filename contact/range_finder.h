// hipfai — the joint range finder (thesis §4.2, Fig. 54): exact range of motion about an axis in
// one pass, without stepping.
//
// For every mobile vertex whose circle about the axis crosses the fixed mesh (ring table of
// cylindrical_table.h), all crossing angles are known (CylindricalPoseCache). Rotating the mobile
// mesh anticlockwise (right-hand rule about the axis) by phi, a vertex at theta_v first meets the
// crossing at theta_k after phi = (theta_k - theta_v) mod 2pi; clockwise after
// (theta_v - theta_k) mod 2pi. The range of motion in each direction is the smallest such angle
// over all vertices and crossings: the rotation before the first contact.
//
// Contact types. A contact between two triangle meshes starts as vertex-on-triangle or
// edge-on-edge. Both vertex-on-triangle types are covered: mobile vertices against fixed
// triangles, and fixed vertices against mobile triangles (the same computation with the roles
// swapped: the mobile rotating anticlockwise is the fixed mesh rotating clockwise relative to it,
// so the swapped pass's clockwise range limits the anticlockwise one and vice versa). Edge-edge
// first contacts are not detected; the over-estimate they can cause is bounded by how far an edge
// can move before one of its vertices touches, i.e. by the mesh resolution (as in the thesis).
//
// A vertex already on the surface (arc distance <= touching_mm) limits a direction to 0 only if
// moving that way enters the other solid (the crossing's outward normal opposes the motion);
// moving away from a resting contact is free. Unlimited directions report 360 degrees with
// LimitingContact::kind == kNone. The start pose is assumed collision-free; if it is not, the
// ranges are those to the first surface crossing of any vertex.
#pragma once

#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "contact/penetration.h"
#include "geometry/tri_mesh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hipfai::contact {

enum class ContactKind {
  kNone,                         // no contact in this direction within a full turn
  kMobileVertexOnFixedTriangle,
  kFixedVertexOnMobileTriangle,
};

struct LimitingContact {
  ContactKind kind = ContactKind::kNone;
  std::int32_t vertex = -1;    // of the mobile mesh (kMobileVertex...) or the fixed mesh
  std::int32_t triangle = -1;  // of the other mesh
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
