// hipfai — analytic rigid surfaces a deformable body can touch (bone stand-ins, indenters).
//
// The contact gap is measured along the normal of the closest point on the rigid surface, in the
// reference configuration; the rigid body's translation is added by the contact solver.
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

namespace hipfai::fem {

struct SurfacePoint {
  dealii::Point<3> point_mm;
  // Unit normal pointing out of the rigid body, i.e. towards the side the deformable body is on.
  dealii::Tensor<1, 3> normal;
};

class RigidSurface {
 public:
  virtual ~RigidSurface() = default;
  // Closest point of the surface to `query_mm` (reference configuration).
  virtual SurfacePoint closest_point(const dealii::Point<3>& query_mm) const = 0;
};

// Infinite plane through `origin_mm` with outward normal `normal` (the rigid body is behind it).
class RigidPlane final : public RigidSurface {
 public:
  RigidPlane(const dealii::Point<3>& origin_mm, const dealii::Tensor<1, 3>& normal);
  SurfacePoint closest_point(const dealii::Point<3>& query_mm) const override;

 private:
  dealii::Point<3> origin_mm_;
  dealii::Tensor<1, 3> normal_;
};

// Solid sphere (e.g. a rigid indenter). Queries at the centre are rejected (no unique normal).
class RigidSphere final : public RigidSurface {
 public:
  RigidSphere(const dealii::Point<3>& center_mm, double radius_mm);
  SurfacePoint closest_point(const dealii::Point<3>& query_mm) const override;

 private:
  dealii::Point<3> center_mm_;
  double radius_mm_;
};

}  // namespace hipfai::fem
