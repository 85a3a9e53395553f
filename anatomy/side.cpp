// hipfai — the side of a hip, and mirroring a left hip into a right one.
#include "anatomy/side.h"

#include "core/error.h"

#include <utility>

namespace hipfai::anatomy {

const char* side_name(Side side) { return side == Side::kRight ? "right" : "left"; }

Side side_from_name(const std::string& name) {
  if (name == "right") return Side::kRight;
  if (name == "left") return Side::kLeft;
  throw_error("side: '", name, "' is not 'right' or 'left'");
}

Eigen::Affine3d reflection(const geometry::Vec3& point, const geometry::Vec3& normal) {
  const geometry::Vec3 n = normal.normalized();
  Eigen::Affine3d map = Eigen::Affine3d::Identity();
  map.linear() = Eigen::Matrix3d::Identity() - 2.0 * n * n.transpose();
  map.translation() = 2.0 * point.dot(n) * n;
  return map;
}

geometry::TriMesh reflected(const geometry::TriMesh& mesh, const Eigen::Affine3d& reflection) {
  geometry::TriMesh out = mesh;
  for (auto& v : out.vertices) v = reflection * v;
  for (auto& t : out.triangles) std::swap(t[1], t[2]);
  return out;
}

geometry::TriMesh transformed(const geometry::TriMesh& mesh, const Eigen::Affine3d& isometry) {
  if (isometry.linear().determinant() < 0.0) return reflected(mesh, isometry);
  geometry::TriMesh out = mesh;
  for (auto& v : out.vertices) v = isometry * v;
  return out;
}

}  // namespace hipfai::anatomy
