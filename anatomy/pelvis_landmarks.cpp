// hipfai — the anterior pelvic plane (APP) and the pelvis frame, found on a whole pelvis alone.
#include "anatomy/pelvis_landmarks.h"

#include "anatomy/frame_file.h"
#include "core/error.h"
#include "core/literature.h"
#include "geometry/hip_frame.h"

#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/convex_hull_2.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace hipfai::anatomy {
namespace {

using geometry::Vec3;
using Kernel = CGAL::Simple_cartesian<double>;
using PointTree = CGAL::Orthogonal_k_neighbor_search<CGAL::Search_traits_3<Kernel>>::Tree;
using Search = CGAL::Orthogonal_k_neighbor_search<CGAL::Search_traits_3<Kernel>>;

// Vertices sampled for the symmetry test: enough for a mean distance good to a fraction of a mm.
constexpr std::size_t kSymmetrySamples = 3000;

struct Principal {
  Vec3 centroid = Vec3::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns, ascending spread
};

Principal principal_axes(const geometry::TriMesh& mesh) {
  Principal p;
  for (const Vec3& v : mesh.vertices) p.centroid += v;
  p.centroid /= static_cast<double>(mesh.num_vertices());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& v : mesh.vertices) covariance += (v - p.centroid) * (v - p.centroid).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  p.axes = solver.eigenvectors();
  return p;
}

// Mean distance from the sampled vertices, mirrored through the plane (centroid, normal), to the
// nearest vertex of the mesh.
double mirror_residual(const geometry::TriMesh& mesh, const PointTree& tree, const Vec3& centroid,
                       const Vec3& normal) {
  const std::size_t stride = std::max<std::size_t>(1, mesh.num_vertices() / kSymmetrySamples);
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < mesh.num_vertices(); i += stride) {
    const Vec3& v = mesh.vertices[i];
    const Vec3 mirrored = v - 2.0 * (v - centroid).dot(normal) * normal;
    Search search(tree, Kernel::Point_3(mirrored.x(), mirrored.y(), mirrored.z()), 1);
    sum += std::sqrt(search.begin()->second);
    ++count;
  }
  return sum / static_cast<double>(count);
}

// Longest edge of the convex hull of the vertices projected on (u, v) whose outward normal lies
// within `max_angle_deg` of +u; returns its two ends as (u, v).
std::array<Eigen::Vector2d, 2> anterior_hull_edge(const geometry::TriMesh& mesh, const Vec3& u,
                                                  const Vec3& v, double max_angle_deg,
                                                  const std::string& what) {
  std::vector<Kernel::Point_2> points;
  points.reserve(mesh.num_vertices());
  for (const Vec3& x : mesh.vertices) points.emplace_back(u.dot(x), v.dot(x));
  std::vector<Kernel::Point_2> hull;
  CGAL::convex_hull_2(points.begin(), points.end(), std::back_inserter(hull));  // counter-clockwise
  const double min_cos = std::cos(max_angle_deg * geometry::kDegToRad);
  double best = -1.0;
  std::array<Eigen::Vector2d, 2> ends{};
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d p(hull[i].x(), hull[i].y());
    const Eigen::Vector2d q(hull[(i + 1) % hull.size()].x(), hull[(i + 1) % hull.size()].y());
    const Eigen::Vector2d edge = q - p;
    const double length = edge.norm();
    if (length <= 0.0) continue;
    const Eigen::Vector2d outward(edge.y() / length, -edge.x() / length);
    if (outward.x() < min_cos) continue;
    if (length > best) {
      best = length;
      ends = {p, q};
    }
  }
  if (best <= 0.0) throw_error(what, ": no anterior face found on the pelvis' sagittal outline");
  return ends;
}

struct Landmarks {
  std::array<std::int64_t, 4> index{-1, -1, -1, -1};  // ASIS right, left, tubercle right, left
};

// The most anterior (along n) vertex of each hemipelvis above and below the split height.
Landmarks most_anterior_points(const geometry::TriMesh& mesh, const Vec3& centroid, const Vec3& right,
                               const Vec3& superior, double split, const Vec3& n) {
  Landmarks found;
  std::array<double, 4> best;
  best.fill(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    const Vec3& x = mesh.vertices[i];
    const bool is_right = right.dot(x - centroid) > 0.0;
    const bool is_upper = superior.dot(x) > split;
    const int slot = (is_upper ? 0 : 2) + (is_right ? 0 : 1);
    const double score = n.dot(x);
    if (score > best[slot]) {
      best[slot] = score;
      found.index[slot] = static_cast<std::int64_t>(i);
    }
  }
  return found;
}

// The plane of bilateral symmetry among the principal planes: its normal (the pelvis' width), how
// far the mirrored pelvis lies from itself on average, and the width along it.
struct Symmetry {
  Vec3 right;
  double residual_mm = 0.0;
  double width_mm = 0.0;
};

Symmetry symmetry_plane(const geometry::TriMesh& mesh, const Principal& principal, const std::string& what) {
  std::vector<Kernel::Point_3> points;
  points.reserve(mesh.num_vertices());
  for (const Vec3& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  const PointTree tree(points.begin(), points.end());
  std::array<double, 3> residual{};
  int ml = 0;
  for (int k = 0; k < 3; ++k) {
    residual[k] = mirror_residual(mesh, tree, principal.centroid, principal.axes.col(k));
    if (residual[k] < residual[ml]) ml = k;
  }
  Symmetry symmetry{principal.axes.col(ml), residual[ml], 0.0};
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec3& v : mesh.vertices) {
    lo = std::min(lo, symmetry.right.dot(v));
    hi = std::max(hi, symmetry.right.dot(v));
  }
  symmetry.width_mm = hi - lo;
  if (symmetry.residual_mm > literature::kPelvisMaxSymmetryResidualFraction * symmetry.width_mm) {
    throw_error(what, ": not a whole pelvis (no plane of bilateral symmetry: mirrored, it lies ",
                symmetry.residual_mm, " mm from itself on average); give the frame (--frame)");
  }
  return symmetry;
}

// Superior from the hint; anterior towards the pubic symphysis (the midline's bone below the hip
// centre); right = anterior x superior, the subject's right.
struct Directions {
  Vec3 superior, anterior, right;
};

Directions pelvis_directions(const geometry::TriMesh& mesh, const PelvisLandmarksRequest& request,
                             const Principal& principal, const Symmetry& symmetry) {
  const Vec3& right = symmetry.right;
  Vec3 superior = request.superior_hint - request.superior_hint.dot(right) * right;
  if (superior.norm() < 0.2 * request.superior_hint.norm()) {
    throw_error(request.what, ": the superior direction given lies along the pelvis' width");
  }
  superior.normalize();
  Vec3 anterior = superior.cross(right);
  std::vector<double> ahead;
  const double midline_slab = literature::kPelvisMidlineSlabFraction * symmetry.width_mm;
  for (const Vec3& v : mesh.vertices) {
    if (std::abs(right.dot(v - principal.centroid)) < midline_slab && superior.dot(v - request.hjc_mm) < 0.0) {
      ahead.push_back(anterior.dot(v - request.hjc_mm));
    }
  }
  if (ahead.empty()) {
    throw_error(request.what, ": no bone at the midline below the hip centre (no pubic symphysis); "
                "give the frame (--frame)");
  }
  std::nth_element(ahead.begin(), ahead.begin() + ahead.size() / 2, ahead.end());
  if (ahead[ahead.size() / 2] < 0.0) anterior = -anterior;
  return {superior, anterior, anterior.cross(superior)};  // y x z = x
}

// The anterior pelvic plane refined from its first guess (normal n through `middle`): the most
// anterior points of each hemipelvis above and below the plane's middle, until they settle; the
// landmarks and rounds into `result`.
void refine_anterior_plane(const geometry::TriMesh& mesh, const PelvisLandmarksRequest& request,
                           const Principal& principal, const Vec3& right, Vec3 n, Vec3 middle,
                           PelvisLandmarks& result) {
  Landmarks previous;
  for (int iteration = 1;; ++iteration) {
    const Vec3 up = right.cross(n).normalized();  // x x y = z: superior, in the plane
    const Landmarks found = most_anterior_points(mesh, principal.centroid, right, up, up.dot(middle), n);
    for (const auto index : found.index) {
      if (index < 0) throw_error(request.what, ": a hemipelvis has no bone above or below the APP's middle");
    }
    result.asis_right_mm = mesh.vertices[found.index[0]];
    result.asis_left_mm = mesh.vertices[found.index[1]];
    result.pubic_tubercle_right_mm = mesh.vertices[found.index[2]];
    result.pubic_tubercle_left_mm = mesh.vertices[found.index[3]];
    const Vec3 asis_mid = 0.5 * (result.asis_right_mm + result.asis_left_mm);
    const Vec3 tubercle_mid = 0.5 * (result.pubic_tubercle_right_mm + result.pubic_tubercle_left_mm);
    Vec3 next = (result.asis_right_mm - result.asis_left_mm).cross(tubercle_mid - result.asis_left_mm);
    if (!(next.norm() > 0.0)) throw_error(request.what, ": the APP landmarks found are collinear");
    next.normalize();
    if (next.dot(n) < 0.0) next = -next;
    n = next;
    middle = 0.5 * (asis_mid + tubercle_mid);
    result.iterations = iteration;
    if (found.index == previous.index) break;
    if (iteration == request.max_iterations) {
      throw_error(request.what, ": the anterior pelvic plane did not settle in ", request.max_iterations,
                  " rounds");
    }
    previous = found;
  }
}

}  // namespace

PelvisLandmarks find_pelvis_landmarks(const PelvisLandmarksRequest& request) {
  if (request.pelvis == nullptr || request.pelvis->empty()) throw_error(request.what, ": empty mesh");
  const geometry::TriMesh& mesh = *request.pelvis;
  geometry::validate_mesh(mesh, request.what);
  if (!(request.superior_hint.norm() > 0.0) || !request.hjc_mm.allFinite()) {
    throw_error(request.what, ": the pelvis search needs a hip centre and a superior direction");
  }
  const Principal principal = principal_axes(mesh);
  const Symmetry symmetry = symmetry_plane(mesh, principal, request.what);
  const Directions directions = pelvis_directions(mesh, request, principal, symmetry);
  // The first plane: the sagittal outline's anterior hull edge.
  const auto ends = anterior_hull_edge(mesh, directions.anterior, directions.superior, 60.0, request.what);
  const Eigen::Vector2d edge = ends[1] - ends[0];
  const Eigen::Vector2d outward = Eigen::Vector2d(edge.y(), -edge.x()).normalized();
  const Vec3 n = (outward.x() * directions.anterior + outward.y() * directions.superior).normalized();
  const Eigen::Vector2d edge_middle = 0.5 * (ends[0] + ends[1]);
  const Vec3 middle = edge_middle.x() * directions.anterior + edge_middle.y() * directions.superior;  // its ML part is irrelevant
  PelvisLandmarks result;
  refine_anterior_plane(mesh, request, principal, directions.right, n, middle, result);

  result.frame = anterior_pelvic_plane_frame({result.asis_right_mm, result.asis_left_mm, result.pubic_tubercle_right_mm,
                                              result.pubic_tubercle_left_mm},
                                             request.hjc_mm, request.what);
  const Vec3 midline = 0.5 * (result.asis_right_mm + result.asis_left_mm);
  result.side = result.frame.right.dot(request.hjc_mm - midline) >= 0.0 ? Side::kRight : Side::kLeft;
  result.symmetry_residual_mm = symmetry.residual_mm;
  result.width_mm = symmetry.width_mm;
  return result;
}

}  // namespace hipfai::anatomy
