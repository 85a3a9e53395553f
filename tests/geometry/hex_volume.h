// The trilinear map of a hexahedron of a HexMesh (geometry/hip_volume_mesh.h) and its exact
// volume, shared by the tests that check volume meshes against the surfaces they fill.
#pragma once

#include "geometry/hip_volume_mesh.h"

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace hipfai::geometry::test_support {

// Jacobian matrix of the trilinear map of a hexahedron at reference point xi in [-1, 1]^3
// (gmsh's reference hexahedron: node k at the signs below).
inline Eigen::Matrix3d trilinear_jacobian(const HexMesh& mesh, const std::array<std::int32_t, 8>& hex, const Vec3& xi) {
  static constexpr std::array<std::array<double, 3>, 8> kSigns{{{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                                                {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}};
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < 8; ++k) {
    const auto& s = kSigns[k];
    const Vec3 gradient(s[0] * (1 + s[1] * xi.y()) * (1 + s[2] * xi.z()) / 8.0,
                        s[1] * (1 + s[0] * xi.x()) * (1 + s[2] * xi.z()) / 8.0,
                        s[2] * (1 + s[0] * xi.x()) * (1 + s[1] * xi.y()) / 8.0);
    jacobian += mesh.vertices[static_cast<std::size_t>(hex[k])] * gradient.transpose();
  }
  return jacobian;
}

// Exact volume of a trilinear hexahedron: det J is of degree <= 2 in each reference coordinate,
// so the 2-point Gauss rule per direction integrates it exactly.
inline double hex_volume(const HexMesh& mesh, const std::array<std::int32_t, 8>& hex) {
  const double g = 1.0 / std::sqrt(3.0);
  double sum = 0.0;
  for (double x : {-g, g}) {
    for (double y : {-g, g}) {
      for (double z : {-g, g}) sum += trilinear_jacobian(mesh, hex, Vec3(x, y, z)).determinant();
    }
  }
  return sum;
}

}  // namespace hipfai::geometry::test_support
