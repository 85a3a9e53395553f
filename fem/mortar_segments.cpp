#include "fem/mortar_segments.h"

#include <deal.II/base/quadrature_lib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hipfai::fem {

namespace {

using Point2 = std::array<double, 2>;

// Sutherland-Hodgman: keeps the part of `polygon` where coordinate `axis` is >= bound (sign +1)
// or <= bound (sign -1). The clip window is convex, so the subject may have either orientation.
std::vector<Point2> clip(const std::vector<Point2>& polygon, unsigned axis, double bound, double sign) {
  std::vector<Point2> out;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Point2& a = polygon[i];
    const Point2& b = polygon[(i + 1) % n];
    const double da = sign * (a[axis] - bound), db = sign * (b[axis] - bound);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) {
      const double f = da / (da - db);
      out.push_back({a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])});
    }
  }
  return out;
}

bool boxes_overlap(const FacePatch& a, const FacePatch& b, double pad) {
  for (unsigned d = 0; d < 3; ++d) {
    if (a.box_max[d] + pad < b.box_min[d] || b.box_max[d] + pad < a.box_min[d]) return false;
  }
  return true;
}

}  // namespace

bool is_bilinear(const FacePatch& face) {
  const dealii::Point<3> v0 = face.vertex(0), v1 = face.vertex(1), v2 = face.vertex(2), v3 = face.vertex(3);
  const double size = v0.distance(v2) + v1.distance(v3);
  constexpr unsigned k = FacePatch::kDegree;
  for (unsigned j = 0; j <= k; ++j) {
    for (unsigned i = 0; i <= k; ++i) {
      const double s = double(i) / k, t = double(j) / k;
      dealii::Point<3> x;
      dealii::Tensor<1, 3> ds, dt;
      face.evaluate(s, t, x, ds, dt);
      const dealii::Point<3> bilinear((1 - s) * (1 - t) * v0 + s * (1 - t) * v1 + s * t * v2 +
                                      (1 - s) * t * v3);
      if (x.distance(bilinear) > 1e-12 * size) return false;
    }
  }
  return true;
}

MortarSegmenter::MortarSegmenter(const std::vector<FacePatch>& master_faces,
                                 MortarSegmentOptions options)
    : master_faces_(master_faces), options_(options) {
  for (const FacePatch& face : master_faces_) master_straight_.push_back(is_bilinear(face));
  const dealii::QGauss<1> gauss(options_.gauss_points);
  for (unsigned q = 0; q < gauss.size(); ++q) {
    gauss_x_.push_back(gauss.point(q)[0]);
    gauss_w_.push_back(gauss.weight(q));
  }
}

namespace {

// The tangent plane of a slave face at its centre, and the face's extent in it.
//
// A master point y contributes to the slave face only through a foot f on the face (its
// closest point, or the slave normal line through f meeting y), at most about the search radius
// R away: y = f + lambda n(f). In the tangent plane (unit normal n0) y then lies
// |lambda| |n(f) - (n(f) . n0) n0| <= |lambda| sin(theta) from f, theta the largest angle
// between n0 and the face's normals. So a master face whose plane box lies clear of the slave
// face's plane box, widened by that offset, has no point that can contribute. Bounds are taken
// from the patches' interpolation points, widened for what a patch may bulge between them,
// and the offset uses 1.5 R and 1.5 theta: generous margins (the test compares the segmented
// points with and without this cull, bit for bit, on generated hips).
struct TangentPlane {
  dealii::Point<3> centre;
  dealii::Tensor<1, 3> u, v;
  std::array<double, 2> low{}, high{};  // the slave face's box in (u, v), widened

  std::array<double, 2> coordinates(const dealii::Point<3>& x) const {
    const dealii::Tensor<1, 3> d = x - centre;
    return {d * u, d * v};
  }
};

double sample_diameter(const FacePatch& face) {
  const std::vector<dealii::Point<3>>& points = face.samples();
  return points.front().distance(points.back()) +
         points[FacePatch::kDegree].distance(points[points.size() - 1 - FacePatch::kDegree]);
}

TangentPlane tangent_plane(const FacePatch& slave, const dealii::Tensor<1, 3>& normal,
                           double search_radius_mm) {
  TangentPlane plane;
  dealii::Tensor<1, 3> ds, dt;
  slave.evaluate(0.5, 0.5, plane.centre, ds, dt);
  plane.u = ds - (ds * normal) * normal;
  plane.u /= plane.u.norm();
  plane.v = dealii::cross_product_3d(normal, plane.u);
  plane.low = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  plane.high = {-plane.low[0], -plane.low[1]};
  double min_cos = 1.0;
  constexpr unsigned int k = FacePatch::kDegree;
  for (unsigned int j = 0; j <= k; ++j) {
    for (unsigned int i = 0; i <= k; ++i) {
      const auto c = plane.coordinates(slave.samples()[j * (k + 1) + i]);
      for (unsigned int a = 0; a < 2; ++a) {
        plane.low[a] = std::min(plane.low[a], c[a]);
        plane.high[a] = std::max(plane.high[a], c[a]);
      }
      min_cos = std::min(min_cos, slave.normal(double(i) / k, double(j) / k) * normal);
    }
  }
  const double theta = std::acos(std::clamp(min_cos, -1.0, 1.0));
  const double offset = 1.5 * search_radius_mm * std::sin(std::min(1.5 * theta, 0.5 * M_PI));
  const double widen = offset + 0.1 * sample_diameter(slave);
  for (unsigned int a = 0; a < 2; ++a) {
    plane.low[a] -= widen;
    plane.high[a] += widen;
  }
  return plane;
}

bool clear_of(const TangentPlane& plane, const FacePatch& master) {
  std::array<double, 2> low = {std::numeric_limits<double>::infinity(),
                               std::numeric_limits<double>::infinity()};
  std::array<double, 2> high = {-low[0], -low[1]};
  for (const dealii::Point<3>& x : master.samples()) {
    const auto c = plane.coordinates(x);
    for (unsigned int a = 0; a < 2; ++a) {
      low[a] = std::min(low[a], c[a]);
      high[a] = std::max(high[a], c[a]);
    }
  }
  const double widen = 0.1 * sample_diameter(master);
  for (unsigned int a = 0; a < 2; ++a) {
    if (high[a] + widen < plane.low[a] || low[a] - widen > plane.high[a]) return true;
  }
  return false;
}

}  // namespace

namespace {

// The part of a polygon (in the slave face's parameters) inside the face's square [0,1]^2.
std::vector<Point2> clipped_to_face(std::vector<Point2> polygon) {
  polygon = clip(polygon, 0, 0.0, 1.0);
  if (polygon.size() >= 3) polygon = clip(polygon, 0, 1.0, -1.0);
  if (polygon.size() >= 3) polygon = clip(polygon, 1, 0.0, 1.0);
  if (polygon.size() >= 3) polygon = clip(polygon, 1, 1.0, -1.0);
  return polygon;
}

double signed_area(const std::vector<Point2>& polygon) {
  double area = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Point2& a = polygon[i];
    const Point2& b = polygon[(i + 1) % polygon.size()];
    area += 0.5 * (a[0] * b[1] - b[0] * a[1]);
  }
  return area;
}

}  // namespace

std::vector<MortarPoint> MortarSegmenter::integrate(const FacePatch& slave) const {
  std::vector<MortarPoint> points;
  const dealii::Tensor<1, 3> slave_normal = slave.normal(0.5, 0.5);
  const bool slave_straight = is_bilinear(slave);
  const TangentPlane plane = tangent_plane(slave, slave_normal, options_.search_radius_mm);
  for (std::size_t m = 0; m < master_faces_.size(); ++m) {
    const FacePatch& master = master_faces_[m];
    if (!boxes_overlap(slave, master, options_.search_radius_mm)) continue;
    // Only faces that face each other can touch.
    if (master.normal(0.5, 0.5) * slave_normal >= 0.0) continue;
    if (options_.tangent_plane_cull && clear_of(plane, master)) continue;
    segment(slave, master, slave_straight && master_straight_[m], points);
  }
  return points;
}

void MortarSegmenter::segment(const FacePatch& slave, const FacePatch& master, bool straight,
                              std::vector<MortarPoint>& points) const {
  // Curved pairs: the master face is cut into sub-squares, each projected on its own. A
  // whole face that reaches far past the slave would project onto the slave patch's
  // polynomial extension where that no longer follows the surface; its sub-squares near the
  // slave project well, and the far ones are rejected by the distance test below.
  const unsigned samples = straight ? 1 : options_.curved_edge_samples;
  const unsigned pieces = straight ? 1 : options_.curved_subdivisions;
  // The pieces' boundary points lie on a grid of (grid + 1)^2 master parameters, and
  // neighbouring pieces share theirs: each point is projected once per master face.
  const unsigned grid = pieces * samples;
  std::vector<signed char> projected((grid + 1) * (grid + 1), 0);  // 0: not yet, 1: ok, -1: not
  std::vector<Point2> projection((grid + 1) * (grid + 1));
  const auto project_grid_point = [&](unsigned a, unsigned b) {
    const unsigned index = b * (grid + 1) + a;
    if (projected[index] != 0) return projected[index] > 0;
    projected[index] = -1;
    dealii::Point<3> y;
    dealii::Tensor<1, 3> ds, dt;
    master.evaluate(double(a) / grid, double(b) / grid, y, ds, dt);
    double s, t;
    // A point far from the slave patch can project onto a spurious point of the patch's
    // extension; a master point opposite the slave lies within the search radius.
    if (!slave.project(y, s, t)) return false;
    dealii::Point<3> foot;
    dealii::Tensor<1, 3> fs, ft;
    slave.evaluate(s, t, foot, fs, ft);
    if (foot.distance(y) > options_.search_radius_mm) return false;
    projected[index] = 1;
    projection[index] = {s, t};
    return true;
  };
  for (unsigned piece = 0; piece < pieces * pieces; ++piece) {
    const unsigned a0 = (piece % pieces) * samples, b0 = (piece / pieces) * samples;
    static constexpr unsigned kS[5] = {0, 1, 1, 0, 0}, kT[5] = {0, 0, 1, 1, 0};
    std::vector<Point2> polygon;
    bool ok = true;
    for (unsigned edge = 0; edge < 4 && ok; ++edge) {
      for (unsigned k = 0; k < samples; ++k) {
        // Along the edge from corner kS/kT[edge] to kS/kT[edge + 1], k samples in.
        const unsigned a = a0 + samples * kS[edge] + k * kS[edge + 1] - k * kS[edge];
        const unsigned b = b0 + samples * kT[edge] + k * kT[edge + 1] - k * kT[edge];
        if (!project_grid_point(a, b)) {
          ok = false;
          break;
        }
        polygon.push_back(projection[b * (grid + 1) + a]);
      }
    }
    if (!ok) continue;
    polygon = clipped_to_face(std::move(polygon));
    if (polygon.size() < 3) continue;
    const double area = signed_area(polygon);
    if (std::abs(area) < 1e-14) continue;  // touches along an edge only
    integrate_polygon(slave, master, polygon, area > 0 ? 1.0 : -1.0, points);
  }
}

void MortarSegmenter::integrate_polygon(const FacePatch& slave, const FacePatch& master,
                                        const std::vector<std::array<double, 2>>& polygon,
                                        double orientation, std::vector<MortarPoint>& points) const {
  // Fan from vertex 0; signed triangle areas make this exact for any simple polygon.
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    const Point2& a = polygon[0];
    const Point2& b = polygon[i];
    const Point2& c = polygon[i + 1];
    const double det = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
    if (det == 0.0) continue;
    // Consecutive Gauss points are neighbours: each line meets the master near the last.
    double start_sm = 0.5, start_tm = 0.5, start_lambda = 0.0;
    for (std::size_t qu = 0; qu < gauss_x_.size(); ++qu) {
      for (std::size_t qv = 0; qv < gauss_x_.size(); ++qv) {
        // Duffy: p = a + u (b - a) + u v (c - b), dp = u det du dv.
        const double u = gauss_x_[qu], v = gauss_x_[qv];
        const double s = a[0] + u * (b[0] - a[0]) + u * v * (c[0] - b[0]);
        const double t = a[1] + u * (b[1] - a[1]) + u * v * (c[1] - b[1]);
        MortarPoint point;
        dealii::Tensor<1, 3> ds, dt;
        slave.evaluate(s, t, point.slave_point_mm, ds, dt);
        const dealii::Tensor<1, 3> area_vector = dealii::cross_product_3d(ds, dt);
        const double jacobian = area_vector.norm();
        point.jxw = orientation * gauss_w_[qu] * gauss_w_[qv] * u * det * jacobian;
        double sm = start_sm, tm = start_tm, lambda = start_lambda;
        dealii::Tensor<1, 3> dsm, dtm;
        if (!master.intersect_line_from(point.slave_point_mm, area_vector / jacobian, sm, tm,
                                        lambda, point.master_point_mm, dsm, dtm))
          continue;
        start_sm = sm;
        start_tm = tm;
        start_lambda = lambda;
        point.slave_unit_point = slave.unit_cell_point(s, t);
        point.master = &master;
        point.master_unit_point = master.unit_cell_point(sm, tm);
        point.master_normal = master.normal(dsm, dtm);
        points.push_back(point);
      }
    }
  }
}

}  // namespace hipfai::fem
