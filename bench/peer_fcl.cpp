#include "bench/peer_fcl.h"

#include <fcl/fcl.h>

#include <algorithm>
#include <limits>

namespace hipfai::bench {

const char* to_string(FclBoundingVolume bv) {
  return bv == FclBoundingVolume::kObbRss ? "OBBRSS" : "OBB";
}

struct FclModel::Impl {
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
};

namespace {

template <typename Bv>
std::shared_ptr<fcl::CollisionGeometryd> make_bvh(const geometry::TriMesh& mesh) {
  auto model = std::make_shared<fcl::BVHModel<Bv>>();
  std::vector<fcl::Vector3d> points(mesh.vertices.begin(), mesh.vertices.end());
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    triangles.emplace_back(static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                           static_cast<std::size_t>(t[2]));
  }
  model->beginModel(static_cast<int>(triangles.size()), static_cast<int>(points.size()));
  model->addSubModel(points, triangles);
  model->endModel();
  return model;
}

}  // namespace

FclModel::FclModel() = default;
FclModel::~FclModel() = default;
FclModel::FclModel(FclModel&&) noexcept = default;
FclModel& FclModel::operator=(FclModel&&) noexcept = default;

FclModel::FclModel(const geometry::TriMesh& mesh, FclBoundingVolume bv)
    : impl_(std::make_unique<Impl>()) {
  impl_->geometry = bv == FclBoundingVolume::kObbRss ? make_bvh<fcl::OBBRSSd>(mesh)
                                                     : make_bvh<fcl::OBBd>(mesh);
}

FclCollideResult FclModel::collide(const FclModel& mobile, const Eigen::Isometry3d& X_FM,
                                   const FclCollideOptions& options) const {
  FclCollideResult out;
  fcl::CollisionObjectd fixed_object(impl_->geometry, fcl::Transform3d::Identity());
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.linear() = X_FM.linear();
  pose.translation() = X_FM.translation();
  fcl::CollisionObjectd mobile_object(mobile.impl_->geometry, pose);
  fcl::CollisionRequestd request(
      options.all_contacts ? std::numeric_limits<std::size_t>::max() : 1, options.enable_contact);
  fcl::CollisionResultd result;
  fcl::collide(&fixed_object, &mobile_object, request, result);
  out.collides = result.isCollision();
  out.triangle_pairs.reserve(result.numContacts());
  for (std::size_t i = 0; i < result.numContacts(); ++i) {
    const auto& contact = result.getContact(i);
    out.triangle_pairs.emplace_back(static_cast<std::int32_t>(contact.b1),
                                    static_cast<std::int32_t>(contact.b2));
  }
  return out;
}

std::vector<std::int32_t> implied_mobile_vertices(const geometry::TriMesh& mobile,
                                                  const FclCollideResult& result) {
  std::vector<std::int32_t> vertices;
  vertices.reserve(3 * result.triangle_pairs.size());
  for (const auto& [fixed_triangle, mobile_triangle] : result.triangle_pairs) {
    (void)fixed_triangle;
    for (std::int32_t v : mobile.triangles[static_cast<std::size_t>(mobile_triangle)]) vertices.push_back(v);
  }
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

Eigen::Isometry3d rotation_about(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis_unit,
                                 double angle_rad, const Eigen::Vector3d& translation_mm) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(angle_rad, axis_unit).toRotationMatrix();
  X.translation() = centre - X.linear() * centre + translation_mm;
  return X;
}

}  // namespace hipfai::bench
