// hipfai tests — checks and small helpers the anatomy tests share.
#pragma once

#include "anatomy/mesh_boolean.h"
#include "core/error.h"
#include "geometry/hip_frame.h"
#include "geometry/mesh_check.h"
#include "geometry/tri_mesh.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <initializer_list>
#include <string>

namespace hipfai::anatomy::test_support {

// The angle between two vectors (deg), stable near 0 and 180 deg.
inline double angle_deg(const geometry::Vec3& a, const geometry::Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * geometry::kRadToDeg;
}

// The mesh with every vertex rotated about `centre`.
inline geometry::TriMesh rotated(const geometry::TriMesh& mesh, const Eigen::Matrix3d& rotation,
                                 const geometry::Vec3& centre) {
  geometry::TriMesh out = mesh;
  for (auto& v : out.vertices) v = centre + rotation * (v - centre);
  return out;
}

// `parse` throws hipfai::Error with a one-line message containing every one of `parts`.
template <typename Parse>
void expect_error(Parse&& parse, std::initializer_list<std::string> parts) {
  try {
    parse();
    ADD_FAILURE() << "no error; expected one containing '" << *parts.begin() << "'";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    for (const auto& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message << " / " << part;
  }
}

// A closed, manifold, outward surface without self-intersections.
inline void expect_solid(const geometry::TriMesh& mesh) {
  ASSERT_FALSE(mesh.empty());
  EXPECT_TRUE(is_closed(mesh));
  EXPECT_TRUE(is_manifold(mesh));
  EXPECT_FALSE(does_self_intersect(mesh));
  EXPECT_TRUE(geometry::check_mesh(mesh).outward);
}

}  // namespace hipfai::anatomy::test_support
