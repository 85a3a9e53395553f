#include "contact/ray_triangle.h"

#include <cmath>
#include <limits>

namespace hipfai::contact {

namespace {

// Strict lexicographic order on coordinates: the canonical order of an edge's end points.
bool lexicographic_less(const Vec3& p, const Vec3& q) {
  if (p.x() != q.x()) return p.x() < q.x();
  if (p.y() != q.y()) return p.y() < q.y();
  return p.z() < q.z();
}

// Exact product a * b as hi + lo (fma gives the rounding error exactly).
void two_product(double a, double b, double& hi, double& lo) {
  hi = a * b;
  lo = std::fma(a, b, -hi);
}

// Adds b to the non-overlapping expansion e[0..n) (increasing magnitude), exactly
// (Shewchuk 1997, Grow-Expansion).
void grow_expansion(double* e, int& n, double b) {
  double q = b;
  for (int i = 0; i < n; ++i) {
    const double sum = q + e[i];
    const double b_virtual = sum - q;
    const double a_virtual = sum - b_virtual;
    e[i] = (q - a_virtual) + (e[i] - b_virtual);
    q = sum;
  }
  e[n++] = q;
}

// Exact sign of d . (p x q) (the orientation predicate): a floating-point filter, then exact
// expansion arithmetic when the filter cannot decide. Exact signs are what make the ray test
// watertight at shared vertices: a ray through a vertex gives exactly zero on all its edges.
int triple_product_sign(const Vec3& d, const Vec3& p, const Vec3& q) {
  const double approx = d.dot(p.cross(q));
  const double permanent =
      std::abs(d.x()) * (std::abs(p.y() * q.z()) + std::abs(p.z() * q.y())) +
      std::abs(d.y()) * (std::abs(p.z() * q.x()) + std::abs(p.x() * q.z())) +
      std::abs(d.z()) * (std::abs(p.x() * q.y()) + std::abs(p.y() * q.x()));
  // The evaluation error is below ~6 ulps of the permanent; 1e-14 leaves a wide margin.
  if (std::abs(approx) > 1e-14 * permanent) return approx > 0.0 ? 1 : -1;
  if (approx == 0.0 && permanent == 0.0) return 0;
  const double terms[6][3] = {{d.x(), p.y(), q.z()},  {-d.x(), p.z(), q.y()},
                              {d.y(), p.z(), q.x()},  {-d.y(), p.x(), q.z()},
                              {d.z(), p.x(), q.y()},  {-d.z(), p.y(), q.x()}};
  double expansion[32];
  int size = 0;
  for (const auto& term : terms) {
    double hi = 0.0, lo = 0.0, h1 = 0.0, l1 = 0.0, h2 = 0.0, l2 = 0.0;
    two_product(term[1], term[2], hi, lo);
    two_product(term[0], hi, h1, l1);
    two_product(term[0], lo, h2, l2);
    for (const double part : {l2, h2, l1, h1}) {
      if (part != 0.0) grow_expansion(expansion, size, part);
    }
  }
  for (int i = size - 1; i >= 0; --i) {
    if (expansion[i] != 0.0) return expansion[i] > 0.0 ? 1 : -1;
  }
  return 0;
}

}  // namespace

int edge_sign(const Vec3& direction, const Vec3& p, const Vec3& q) {
  return triple_product_sign(direction, p, q);
}

double edge_function(const Vec3& direction, const Vec3& p, const Vec3& q) {
  // Evaluating in one fixed order makes e(p, q) == -e(q, p) bit for bit, which is what makes
  // neighbouring triangles agree on which side of their shared edge a ray passes.
  if (lexicographic_less(q, p)) return -direction.dot(q.cross(p));
  return direction.dot(p.cross(q));
}

RayCrossing ray_triangle_crossing(const Vec3& direction, const Vec3& a, const Vec3& b,
                                  const Vec3& c) {
  RayCrossing crossing;
  const Vec3 area_normal = (b - a).cross(c - a);
  if (area_normal.x() == 0.0 && area_normal.y() == 0.0 && area_normal.z() == 0.0) return crossing;
  // The decision uses exact signs; the values only give the point and weights.
  const int s_ab = triple_product_sign(direction, a, b);
  const int s_bc = triple_product_sign(direction, b, c);
  const int s_ca = triple_product_sign(direction, c, a);
  int facing = 0;
  if (s_ab >= 0 && s_bc >= 0 && s_ca >= 0 && (s_ab + s_bc + s_ca) > 0) facing = 1;
  if (s_ab <= 0 && s_bc <= 0 && s_ca <= 0 && (s_ab + s_bc + s_ca) < 0) facing = -1;
  if (facing == 0) return crossing;  // outside, or the ray lies in the triangle's plane
  const double e_ab = edge_function(direction, a, b);
  const double e_bc = edge_function(direction, b, c);
  const double e_ca = edge_function(direction, c, a);
  // d . N with the facing's sign: rounding may flip the float sign only for rays grazing the
  // plane, where the crossing distance is meaningless anyway (treated as no crossing below).
  const double along_normal = direction.dot(area_normal);
  if (along_normal == 0.0 || (along_normal > 0.0) != (facing > 0)) return crossing;
  // det(a, b, c) = a . (b x c) = (A-O).N, so t = (A-O).N / (d.N)  (Eq. 34, unnormalised d).
  const double t = a.dot(b.cross(c)) / along_normal;
  if (!(t > 0.0) || !std::isfinite(t)) return crossing;  // at or behind O
  const double sum = e_ab + e_bc + e_ca;
  crossing.hit = true;
  crossing.t = t;
  crossing.facing = facing;
  if (sum != 0.0) {
    crossing.weight_a = e_bc / sum;
    crossing.weight_b = e_ca / sum;
    crossing.weight_c = e_ab / sum;
  } else {
    crossing.weight_a = crossing.weight_b = crossing.weight_c = 1.0 / 3.0;
  }
  return crossing;
}

double radial_plane_distance(const Vec3& direction, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 normal = (b - a).cross(c - a);
  const double norm = direction.norm();
  const double denominator = normal.dot(direction) / norm;
  if (denominator == 0.0 || norm == 0.0) return std::numeric_limits<double>::quiet_NaN();
  return a.dot(normal) / denominator;
}

}  // namespace hipfai::contact
