// hipfai — the side of a hip, and mirroring a left hip into a right one.
//
// Everything in anatomy/ that depends on handedness (the hip frame of geometry/hip_frame.h, the
// motions' signs, the clock faces) is written for a RIGHT hip. A left hip is measured by mirroring
// its bones through a plane (reflection x -> x - 2 ((x - p) . n) n, triangles re-wound so they stay
// outward), measuring the mirrored right hip, and mapping points and directions back with the same
// reflection. Angles and clock positions are reported in the right-hip convention for both sides
// (3 o'clock anterior), as clinical hip clock faces usually are.
#pragma once

#include "geometry/tri_mesh.h"

#include <Eigen/Geometry>

#include <string>

namespace hipfai::anatomy {

enum class Side { kRight, kLeft };

// "right" / "left"; side_from_name throws hipfai::Error for anything else.
const char* side_name(Side side);
Side side_from_name(const std::string& name);

// A reflection through the plane through `point` with unit normal `normal` (an improper isometry:
// its linear part has determinant -1; it is its own inverse).
Eigen::Affine3d reflection(const geometry::Vec3& point, const geometry::Vec3& normal);

// `mesh` reflected: vertices mapped, every triangle's winding reversed so that the reflected
// surface still faces outward; vertex fields kept.
geometry::TriMesh reflected(const geometry::TriMesh& mesh, const Eigen::Affine3d& reflection);

// `mesh` moved by an isometry, proper or improper (determinant -1: reflected, triangles re-wound).
geometry::TriMesh transformed(const geometry::TriMesh& mesh, const Eigen::Affine3d& isometry);

}  // namespace hipfai::anatomy
