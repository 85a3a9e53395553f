// hipfai — exact ray/line–triangle primitives for radial collision queries (thesis App. F).
//
// Every radial query (radial segmenting, its oracle, ray-based sampling) reduces to one question:
// does the ray from the centre O in direction d cross triangle ABC, where, and which way does the
// triangle face? All inputs here are RELATIVE to O (pass A - O, B - O, C - O), so the same vertex
// gives bit-identical numbers in every triangle that uses it.
//
// The test is the edge-function (scalar triple product) form of the barycentric test of
// Schneider & Eberly 2003 that the thesis uses (Eq. 34-35), chosen because it can be made
// WATERTIGHT: the hit decision uses the EXACT sign of
//   e(P, Q) = d . (P x Q)  for the directed edge P -> Q
// (a floating-point filter with an exact expansion fallback, Shewchuk 1997), so the triangles
// sharing an edge see exactly opposite signs and a ray through a shared vertex sees exactly zero
// on every edge at that vertex. A ray through a shared edge or vertex therefore crosses at least
// one of the triangles around it (never falls through a crack); it may cross several, and callers
// must pick one (the crossing rule of radial_segmenting.h). The float values (evaluated in a
// canonical vertex order, so bit-antisymmetric) only give the weights.
//
// With e_ab, e_bc, e_ca the three edge functions and s = e_ab + e_bc + e_ca = d . N
// (N = (B-A) x (C-A), the outward area normal):
//   - the LINE through O along d meets the triangle iff the exact signs are all >= 0 and not all
//     zero, or all <= 0 and not all zero (edges and vertices count: the test is inclusive);
//   - barycentric weights of the crossing point are (e_bc, e_ca, e_ab) / s for (A, B, C);
//   - the crossing is at O + t d with t = det(A, B, C) / (d.N)  (= (A-O).N / (d.N), thesis
//     Eq. 34 with an unnormalised d);
//   - the RAY crosses iff additionally t > 0; a crossing at t <= 0 lies at or behind O.
//   - sign(s) is the facing: s > 0 means the outward normal points along d, i.e. the ray EXITS the
//     solid there; s < 0 means it ENTERS.
// A ray lying in the triangle's plane (s == 0) or a zero-area triangle (N == 0) never crosses,
// nor does a ray so close to the plane that the float d.N disagrees in sign with the exact facing.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace hipfai::contact {

using Vec3 = Eigen::Vector3d;

// max(|x|, |y|, |z|): the scale of a vector in the error bounds of the float filters.
inline double max_abs_component(const Vec3& v) { return v.cwiseAbs().maxCoeff(); }

struct RayCrossing {
  bool hit = false;       // the RAY (t > 0) meets the closed triangle
  double t = 0.0;         // crossing point = O + t * d (t in units of |d|); 0 when !hit
  int facing = 0;         // +1 ray exits the solid (N.d > 0), -1 ray enters (N.d < 0), 0 when !hit
  double weight_a = 0.0;  // barycentric weights of the crossing point (sum to 1)
  double weight_b = 0.0;
  double weight_c = 0.0;
};

// Exact sign (-1, 0, +1) of d . (p x q), the orientation predicate the hit test decides with.
int edge_sign(const Vec3& direction, const Vec3& p, const Vec3& q);

// Edge function d . (p x q) evaluated with p, q in canonical order (antisymmetric in p, q exactly).
double edge_function(const Vec3& direction, const Vec3& p, const Vec3& q);

// Ray from O along `direction` (any non-zero length) against the triangle with vertices a, b, c
// given relative to O. See the header comment for the exact semantics.
RayCrossing ray_triangle_crossing(const Vec3& direction, const Vec3& a, const Vec3& b,
                                  const Vec3& c);

// The rest of ray_triangle_crossing once the exact edge signs are known to be all >= 0 (facing
// +1) or all <= 0 (facing -1), not all zero: hit, t and facing as ray_triangle_crossing reports
// them (bit for bit), weights left zero. For callers that proved the signs with a filter.
RayCrossing line_crossing_with_facing(const Vec3& direction, const Vec3& a, const Vec3& b, const Vec3& c,
                                      int facing);

// The same tail given the triangle's area normal N = (b - a) x (c - a) and det(a, b, c) =
// a . (b x c) computed beforehand with those expressions (as line_crossing_with_facing does).
// (Inline: the radial query calls it once per clear hit.)
inline RayCrossing plane_crossing_with_facing(const Vec3& direction, const Vec3& area_normal, double det, int facing) {
  RayCrossing crossing;
  if (area_normal.x() == 0.0 && area_normal.y() == 0.0 && area_normal.z() == 0.0) return crossing;
  // d . N with the facing's sign: rounding may flip the float sign only for rays grazing the
  // plane, where the crossing distance is meaningless anyway (treated as no crossing below).
  const double along_normal = direction.dot(area_normal);
  if (along_normal == 0.0 || (along_normal > 0.0) != (facing > 0)) return crossing;
  // det(a, b, c) = a . (b x c) = (A-O).N, so t = (A-O).N / (d.N)  (Eq. 34, unnormalised d).
  const double t = det / along_normal;
  if (!(t > 0.0) || !std::isfinite(t)) return crossing;  // at or behind O
  crossing.hit = true;
  crossing.t = t;
  crossing.facing = facing;
  return crossing;
}

// Thesis Eq. 34: distance from O to the triangle's plane along the unit direction of `direction`
// (a, b, c relative to O), or NaN if the line is parallel to the plane or the triangle has zero
// area. Signed: negative when the plane is met behind O. Kept for documentation and tests; the
// queries use ray_triangle_crossing (same value as t * |direction|, watertight).
double radial_plane_distance(const Vec3& direction, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace hipfai::contact
