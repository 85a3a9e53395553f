#include "fem/rigid_surface.h"

#include "core/error.h"

namespace hipfai::fem {

RigidPlane::RigidPlane(const dealii::Point<3>& origin_mm, const dealii::Tensor<1, 3>& normal)
    : origin_mm_(origin_mm) {
  const double length = normal.norm();
  if (!(length > 0.0)) throw_error("rigid plane: normal vector has zero length");
  normal_ = normal / length;
}

SurfacePoint RigidPlane::closest_point(const dealii::Point<3>& query_mm) const {
  const double height = (query_mm - origin_mm_) * normal_;
  return {query_mm - height * normal_, normal_};
}

RigidSphere::RigidSphere(const dealii::Point<3>& center_mm, double radius_mm)
    : center_mm_(center_mm), radius_mm_(radius_mm) {
  if (!(radius_mm > 0.0)) throw_error("rigid sphere: radius must be positive, got ", radius_mm);
}

SurfacePoint RigidSphere::closest_point(const dealii::Point<3>& query_mm) const {
  const dealii::Tensor<1, 3> offset = query_mm - center_mm_;
  const double distance = offset.norm();
  if (!(distance > 1e-12 * radius_mm_)) {
    throw_error("rigid sphere: query point at the centre has no closest point");
  }
  const dealii::Tensor<1, 3> normal = offset / distance;
  return {center_mm_ + radius_mm_ * normal, normal};
}

}  // namespace hipfai::fem
