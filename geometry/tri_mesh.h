// hipfai — the triangle surface mesh every module works on.
//
// Vertices are in millimetres. Triangles index vertices (0-based) and are wound counter-clockwise
// seen from outside, so the right-hand normal points out of the solid the surface bounds.
// Per-vertex scalar fields (penetration depth, pressure, ...) travel with the mesh and are written
// to formats that can hold them (VTP, PLY).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace hipfai::geometry {

using Vec3 = Eigen::Vector3d;
using Triangle = std::array<std::int32_t, 3>;

struct TriMesh {
  std::vector<Vec3> vertices;                                  // #V points, mm
  std::vector<Triangle> triangles;                             // #T vertex indices, CCW outward
  std::map<std::string, std::vector<double>> vertex_fields;    // name -> #V values

  std::size_t num_vertices() const { return vertices.size(); }
  std::size_t num_triangles() const { return triangles.size(); }
  bool empty() const { return vertices.empty() || triangles.empty(); }
};

struct BoundingBox {
  Vec3 min = Vec3::Constant(0.0);
  Vec3 max = Vec3::Constant(0.0);
  Vec3 extent() const { return max - min; }
};

// Axis-aligned bounding box of the vertices; a zero box for an empty mesh.
BoundingBox bounding_box(const TriMesh& mesh);

// Unnormalised normal (B - A) x (C - A) of triangle t: twice its area, pointing outward.
Vec3 triangle_area_normal(const TriMesh& mesh, std::size_t t);

// Unit outward normal of triangle t, or the zero vector for a zero-area triangle.
Vec3 triangle_unit_normal(const TriMesh& mesh, std::size_t t);

double triangle_area(const TriMesh& mesh, std::size_t t);

// Whether triangles a and b of the mesh have a vertex index in common.
bool triangles_share_a_vertex(const TriMesh& mesh, std::int32_t a, std::int32_t b);

// Mean length of the distinct edges (each shared edge counted once), mm; 0 for an empty mesh.
double mean_edge_length(const TriMesh& mesh);

// Total surface area, mm^2.
double surface_area(const TriMesh& mesh);

// Signed volume enclosed (positive when outward-oriented and closed), mm^3.
double signed_volume(const TriMesh& mesh);

// Applies x -> transform * x to every vertex.
void apply_transform(TriMesh& mesh, const Eigen::Isometry3d& transform);

// Rotates every vertex by angle_rad about the axis through centre (right-hand rule).
void rotate_about_axis(TriMesh& mesh, const Vec3& centre, const Vec3& axis_unit, double angle_rad);

// Concatenates meshes (indices offset); fields present in every part are concatenated, others dropped.
TriMesh merge_meshes(const std::vector<const TriMesh*>& parts);

// Content hash of the vertices and triangles (16 hex digits): names cache entries and records in
// result files which meshes a result came from.
std::string mesh_hash(const TriMesh& mesh);

// Throws hipfai::Error "<what>: ..." when the mesh is empty, has a non-finite coordinate, an index
// out of range, or a field whose length differs from the vertex count.
void validate_mesh(const TriMesh& mesh, const std::string& what);

}  // namespace hipfai::geometry
