#include "geometry/hjc_functional.h"

#include "geometry/hip_frame.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace hipfai::geometry {
namespace {

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, §5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

PatchDistance::PatchDistance(const TriMesh& patch, const std::vector<Vec3>& normals)
    : patch_(patch), normals_(normals) {
  const std::size_t n = patch.num_vertices();
  ring_.assign(n, {});
  std::map<std::pair<std::int32_t, std::int32_t>, int> edge_use;
  for (std::size_t t = 0; t < patch.num_triangles(); ++t) {
    const Triangle& tri = patch.triangles[t];
    for (int k = 0; k < 3; ++k) {
      ring_[static_cast<std::size_t>(tri[static_cast<std::size_t>(k)])].push_back(static_cast<std::int32_t>(t));
      std::int32_t a = tri[static_cast<std::size_t>(k)], b = tri[static_cast<std::size_t>((k + 1) % 3)];
      if (a > b) std::swap(a, b);
      ++edge_use[{a, b}];
    }
  }
  border_.assign(n, 0);
  for (const auto& [edge, uses] : edge_use) {
    if (uses == 1) border_[static_cast<std::size_t>(edge.first)] = border_[static_cast<std::size_t>(edge.second)] = 1;
  }
  for (std::size_t v = 0; v < n; ++v) if (ring_[v].empty()) border_[v] = 1;
  const BoundingBox box = bounding_box(patch);
  const double edge = patch.num_triangles() > 0 ? mean_edge_length(patch) : 1.0;
  cell_mm_ = std::max({2.0 * edge, box.extent().maxCoeff() / 100.0, 1e-3});
  origin_ = box.min;
  dims_ = ((box.extent() / cell_mm_).array().floor().cast<int>() + 1).matrix();
  cells_.assign(static_cast<std::size_t>(dims_.x()) * dims_.y() * dims_.z(), {});
  for (std::size_t v = 0; v < n; ++v) {
    const Eigen::Vector3i c = ((patch.vertices[v] - origin_) / cell_mm_).array().floor().cast<int>().matrix()
                                  .cwiseMax(Eigen::Vector3i::Zero()).cwiseMin(dims_ - Eigen::Vector3i::Ones());
    cells_[(static_cast<std::size_t>(c.z()) * dims_.y() + c.y()) * dims_.x() + c.x()].push_back(static_cast<std::int32_t>(v));
  }
}

std::int32_t PatchDistance::nearest_vertex(const Vec3& point) const {
  const Eigen::Vector3d local = (point - origin_) / cell_mm_;
  const Eigen::Vector3i home = local.array().floor().cast<int>().matrix();
  std::int32_t best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  const int max_shell = dims_.maxCoeff() + std::max(0, (home.cwiseAbs().maxCoeff())) + 2;
  for (int shell = 0; shell <= max_shell; ++shell) {
    // Any vertex in a farther shell is at least (shell - 1) cells away from the point's cell box.
    const double reach = (shell - 1) * cell_mm_;
    if (best >= 0 && reach > 0.0 && reach * reach > best_d2) break;
    for (int dz = -shell; dz <= shell; ++dz)
      for (int dy = -shell; dy <= shell; ++dy)
        for (int dx = -shell; dx <= shell; ++dx) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != shell) continue;
          const Eigen::Vector3i c = home + Eigen::Vector3i(dx, dy, dz);
          if ((c.array() < 0).any() || (c.array() >= dims_.array()).any()) continue;
          for (const auto v : cells_[(static_cast<std::size_t>(c.z()) * dims_.y() + c.y()) * dims_.x() + c.x()]) {
            const double d2 = (patch_.vertices[static_cast<std::size_t>(v)] - point).squaredNorm();
            if (d2 < best_d2) { best_d2 = d2; best = v; }
          }
        }
  }
  return best;
}

double PatchDistance::signed_distance(const Vec3& point, Vec3& gradient, bool& on_border) const {
  const std::int32_t nearest = nearest_vertex(point);
  on_border = border_[static_cast<std::size_t>(nearest)] != 0;
  Vec3 closest = patch_.vertices[static_cast<std::size_t>(nearest)];
  double best = (closest - point).squaredNorm();
  for (const auto t : ring_[static_cast<std::size_t>(nearest)]) {
    const Triangle& tri = patch_.triangles[static_cast<std::size_t>(t)];
    const Vec3 q = closest_on_triangle(point, patch_.vertices[static_cast<std::size_t>(tri[0])],
                                       patch_.vertices[static_cast<std::size_t>(tri[1])],
                                       patch_.vertices[static_cast<std::size_t>(tri[2])]);
    const double d2 = (q - point).squaredNorm();
    if (d2 < best) { best = d2; closest = q; }
  }
  const Vec3& normal = normals_[static_cast<std::size_t>(nearest)];
  const Vec3 offset = point - closest;
  const double distance = offset.norm();
  const double sign = offset.dot(normal) < 0.0 ? -1.0 : 1.0;
  gradient = distance > 1e-12 ? Vec3(sign * offset / distance) : normal;
  return sign * distance;
}

namespace {

// Target distances of the lunate vertices in the scanned pose (the reference ones, or the
// constant) and whether each lies over the head patch; vertices beyond it are not used.
struct LunateTargets {
  std::vector<double> target_mm;
  std::vector<char> usable;
};

LunateTargets lunate_targets(const PatchDistance& distance, const std::vector<Vec3>& lunate,
                             FunctionalTarget target, double constant_mm) {
  const std::size_t n = lunate.size();
  LunateTargets targets{std::vector<double>(n, constant_mm), std::vector<char>(n, 1)};
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 gradient;
    bool border = false;
    const double d = distance.signed_distance(lunate[i], gradient, border);
    if (target == FunctionalTarget::kReference) targets.target_mm[i] = d;
    if (border) targets.usable[i] = 0;
  }
  return targets;
}

// The femur in one circumduction pose, x -> R (x - c0) + c0 + t, shifted by t to restore the
// inter-articular distances. A lunate point P seen from the femur: q = R^T (P - c0 - t) + c0;
// d(q) its signed distance, dd/dt = -(R g)^T.
struct PoseShiftFit {
  const PatchDistance& distance;
  const std::vector<Vec3>& lunate;
  const LunateTargets& targets;
  Eigen::Matrix3d rotation;
  Vec3 c0;
  std::vector<double> residual = std::vector<double>(lunate.size(), 0.0);
  std::vector<char> used = std::vector<char>(lunate.size(), 0);

  // Residuals, normal equations and mean squared residual at a shift.
  double evaluate(const Vec3& shift, Eigen::Matrix3d& jtj, Eigen::Vector3d& jtr) {
    jtj.setZero();
    jtr.setZero();
    double sum = 0.0;
    int count = 0;
    for (std::size_t i = 0; i < lunate.size(); ++i) {
      used[i] = 0;
      if (!targets.usable[i]) continue;
      const Vec3 q = rotation.transpose() * (lunate[i] - c0 - shift) + c0;
      Vec3 gradient;
      bool border = false;
      const double d = distance.signed_distance(q, gradient, border);
      if (border) continue;
      const Vec3 row = -(rotation * gradient);
      residual[i] = d - targets.target_mm[i];
      used[i] = 1;
      jtj.noalias() += row * row.transpose();
      jtr.noalias() += row * residual[i];
      sum += residual[i] * residual[i];
      ++count;
    }
    return count < 4 ? std::numeric_limits<double>::infinity() : sum / count;
  }

  // Gauss-Newton with step halving: the set of lunate vertices over the head changes with the
  // shift, and a full step can overshoot across such a change. Whether it converged; `shift`,
  // `residual` and `used` are those of the last evaluation at the shift returned.
  bool solve(const FunctionalHjcOptions& options, Vec3& shift) {
    shift = Vec3::Zero();
    Eigen::Matrix3d jtj;
    Eigen::Vector3d jtr;
    double cost = evaluate(shift, jtj, jtr);
    for (int iteration = 0; iteration < options.max_iterations && std::isfinite(cost); ++iteration) {
      Eigen::Vector3d step = jtj.ldlt().solve(-jtr);
      if (!step.allFinite()) break;
      Eigen::Matrix3d trial_jtj;
      Eigen::Vector3d trial_jtr;
      double trial_cost = evaluate(shift + step, trial_jtj, trial_jtr);
      for (int halving = 0; halving < 20 && !(trial_cost <= cost); ++halving) {
        step *= 0.5;
        trial_cost = evaluate(shift + step, trial_jtj, trial_jtr);
      }
      if (!(trial_cost <= cost)) {  // no descent along the Gauss-Newton direction: at the minimum
        const bool converged = step.norm() < 1e3 * options.tolerance_mm;
        evaluate(shift, jtj, jtr);
        return converged;
      }
      shift += step;
      cost = trial_cost;
      jtj = trial_jtj;
      jtr = trial_jtr;
      if (step.norm() < options.tolerance_mm) return true;
    }
    return false;
  }
};

// The least-moving point of the poses (R, b), x -> R x + b, and how much it still moves.
void least_moving_point(const std::vector<std::pair<Eigen::Matrix3d, Vec3>>& poses, const Eigen::Matrix3d& normal_matrix,
                        const Eigen::Vector3d& normal_rhs, FunctionalHjc& result) {
  result.center_mm = normal_matrix.ldlt().solve(normal_rhs);
  double motion_sum = 0.0;
  for (const auto& [rotation, b] : poses) {
    const double moved = ((rotation - Eigen::Matrix3d::Identity()) * result.center_mm + b).norm();
    motion_sum += moved * moved;
    result.residual_motion_max_mm = std::max(result.residual_motion_max_mm, moved);
  }
  result.residual_motion_rms_mm = std::sqrt(motion_sum / static_cast<double>(poses.size()));
}

}  // namespace

FunctionalHjc functional_hjc(const TriMesh& head, const std::vector<Vec3>& head_normals,
                             const std::vector<Vec3>& lunate, const Vec3& start_center_mm,
                             const Vec3& long_axis, FunctionalTarget target, double constant_mm,
                             const FunctionalHjcOptions& options) {
  FunctionalHjc result;
  if (head.num_vertices() < 4 || lunate.size() < 4) {
    result.message = "the head patch and the lunate surface need at least 4 vertices each";
    return result;
  }
  if (!(long_axis.norm() > 0.0)) {
    result.message = "the circumduction axis has zero length";
    return result;
  }
  const PatchDistance distance(head, head_normals);
  const std::size_t n = lunate.size();
  const LunateTargets targets = lunate_targets(distance, lunate, target, constant_mm);
  result.target_mm = target == FunctionalTarget::kConstant ? constant_mm : 0.0;
  const Vec3 axis = long_axis.normalized();
  const Vec3 e1 = axis.unitOrthogonal();
  const Vec3 e2 = axis.cross(e1);
  const double elevation = options.elevation_deg * kDegToRad;
  const Vec3& c0 = start_center_mm;

  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  Eigen::Vector3d normal_rhs = Eigen::Vector3d::Zero();
  std::vector<std::pair<Eigen::Matrix3d, Vec3>> poses;
  double distance_sum = 0.0, distance_max = 0.0;
  std::size_t distance_count = 0;
  for (int k = 0; k < options.poses; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / options.poses;
    const Vec3 turn_axis = std::cos(phi) * e1 + std::sin(phi) * e2;
    const Eigen::Matrix3d rotation = Eigen::AngleAxisd(elevation, turn_axis).toRotationMatrix();
    PoseShiftFit fit{distance, lunate, targets, rotation, c0};
    Vec3 shift;
    if (!fit.solve(options, shift)) continue;
    for (std::size_t i = 0; i < n; ++i) {
      if (!fit.used[i]) continue;
      distance_sum += fit.residual[i] * fit.residual[i];
      distance_max = std::max(distance_max, std::abs(fit.residual[i]));
      ++distance_count;
    }
    const Eigen::Matrix3d a = rotation - Eigen::Matrix3d::Identity();
    const Vec3 b = c0 - rotation * c0 + shift;
    normal_matrix += a.transpose() * a;
    normal_rhs -= a.transpose() * b;
    poses.push_back({rotation, b});
    result.shifts_mm.push_back(shift);
  }
  result.poses_used = static_cast<int>(poses.size());
  if (poses.size() < 2) {
    result.message = "the inter-articular distances could not be restored in the circumduction poses";
    return result;
  }
  least_moving_point(poses, normal_matrix, normal_rhs, result);
  result.distance_rms_mm = distance_count > 0 ? std::sqrt(distance_sum / static_cast<double>(distance_count)) : 0.0;
  result.distance_max_mm = distance_max;
  result.ok = result.center_mm.allFinite();
  if (!result.ok) result.message = "the least-moving point is undetermined";
  return result;
}

}  // namespace hipfai::geometry
