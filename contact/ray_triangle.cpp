#include "contact/ray_triangle.h"

#include <algorithm>
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

// Exact sign of d . (p x q) (the orientation predicate) given its float evaluation `approx`:
// a floating-point filter, then exact expansion arithmetic when the filter cannot decide. Exact
// signs are what make the ray test watertight at shared vertices: a ray through a vertex gives
// exactly zero on all its edges. `scale` = max|d_i| max|p_i| max|q_i| bounds each of the six
// products, so the float evaluation errs by less than ~6 ulps x 6 scale < 1e-14 x 6 scale.
int filtered_sign(const Vec3& d, const Vec3& p, const Vec3& q, double approx, double scale) {
  if (std::abs(approx) > 6e-14 * scale) return approx > 0.0 ? 1 : -1;
  if (scale == 0.0) return 0;  // a zero vector: the product is exactly zero
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

// Edge function in canonical order: its float value (bit-antisymmetric) and exact sign.
int signed_edge(const Vec3& d, const Vec3& p, const Vec3& q, double scale, double& value) {
  const bool swap = lexicographic_less(q, p);
  const Vec3& first = swap ? q : p;
  const Vec3& second = swap ? p : q;
  const double raw = d.dot(first.cross(second));
  const int sign = filtered_sign(d, first, second, raw, scale);
  value = swap ? -raw : raw;
  return swap ? -sign : sign;
}

}  // namespace

int edge_sign(const Vec3& direction, const Vec3& p, const Vec3& q) {
  double value = 0.0;
  return signed_edge(direction, p, q, max_abs_component(direction) * max_abs_component(p) * max_abs_component(q), value);
}

double edge_function(const Vec3& direction, const Vec3& p, const Vec3& q) {
  // Evaluating in one fixed order makes e(p, q) == -e(q, p) bit for bit, which is what makes
  // neighbouring triangles agree on which side of their shared edge a ray passes.
  if (lexicographic_less(q, p)) return -direction.dot(q.cross(p));
  return direction.dot(p.cross(q));
}

RayCrossing line_crossing_with_facing(const Vec3& direction, const Vec3& a, const Vec3& b, const Vec3& c,
                                      int facing) {
  return plane_crossing_with_facing(direction, (b - a).cross(c - a), a.dot(b.cross(c)), facing);
}

RayCrossing ray_triangle_crossing(const Vec3& direction, const Vec3& a, const Vec3& b,
                                  const Vec3& c) {
  RayCrossing crossing;
  // The decision uses exact signs; the values only give the point and weights. Opposite signs
  // on two edges already mean a miss, the common case, so it is tested first.
  double e_ab = 0.0, e_bc = 0.0, e_ca = 0.0;
  const double m_d = max_abs_component(direction), m_a = max_abs_component(a), m_b = max_abs_component(b), m_c = max_abs_component(c);
  const int s_ab = signed_edge(direction, a, b, m_d * m_a * m_b, e_ab);
  const int s_bc = signed_edge(direction, b, c, m_d * m_b * m_c, e_bc);
  if (s_ab * s_bc < 0) return crossing;
  const int s_ca = signed_edge(direction, c, a, m_d * m_c * m_a, e_ca);
  int facing = 0;
  if (s_ab >= 0 && s_bc >= 0 && s_ca >= 0 && (s_ab + s_bc + s_ca) > 0) facing = 1;
  if (s_ab <= 0 && s_bc <= 0 && s_ca <= 0 && (s_ab + s_bc + s_ca) < 0) facing = -1;
  if (facing == 0) return crossing;  // outside, or the ray lies in the triangle's plane
  crossing = line_crossing_with_facing(direction, a, b, c, facing);
  if (!crossing.hit) return crossing;
  const double sum = e_ab + e_bc + e_ca;
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
