// Random closed, outward-oriented test shapes for the cylindrical tests: radially perturbed
// octaspheres (still star-shaped, so still embedded and outward), tori and boxes, randomly rotated
// and translated; a random pose and a random unit vector.
#pragma once

#include "geometry/primitive_meshes.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Geometry>

#include <random>
#include <utility>

namespace hipfai::contact::test_shapes {

// The mesh with every triangle's orientation reversed (normals inward).
inline geometry::TriMesh flipped(geometry::TriMesh mesh) {
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

inline Eigen::Isometry3d random_pose(std::mt19937& rng, double translation_mm) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> shift(-translation_mm, translation_mm);
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.toRotationMatrix();
  pose.translation() = geometry::Vec3(shift(rng), shift(rng), shift(rng));
  return pose;
}

// kind 0: perturbed octasphere, 1: torus, 2: box.
inline geometry::TriMesh random_shape(std::mt19937& rng, int kind) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  geometry::TriMesh mesh;
  if (kind == 0) {
    mesh = geometry::make_octasphere(geometry::Vec3::Zero(), 5.0 + 10.0 * u(rng), 3);
    for (geometry::Vec3& p : mesh.vertices) p *= 1.0 + 0.2 * (u(rng) - 0.5);
  } else if (kind == 1) {
    mesh = geometry::make_torus(geometry::Vec3::Zero(), 8.0 + 6.0 * u(rng), 2.0 + 3.0 * u(rng), 20, 10);
  } else {
    const geometry::Vec3 half(3.0 + 8.0 * u(rng), 3.0 + 8.0 * u(rng), 3.0 + 8.0 * u(rng));
    mesh = geometry::make_box(-half, half, 3);
  }
  geometry::apply_transform(mesh, random_pose(rng, 5.0));
  return mesh;
}

inline geometry::Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  return geometry::Vec3(normal(rng), normal(rng), normal(rng)).normalized();
}

}  // namespace hipfai::contact::test_shapes
