// hipfai — Boolean operations on closed triangle surfaces with CGAL corefinement.
#include "anatomy/mesh_boolean.h"

#include "core/error.h"
#include "geometry/mesh_check.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_self_intersections.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <array>
#include <cstdint>
#include <vector>

namespace hipfai::anatomy {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using EpickKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = EpickKernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

// A manifold TriMesh as a Surface_mesh; vertices no triangle uses are left out.
SurfaceMesh to_surface_mesh(const geometry::TriMesh& mesh, const std::string& what) {
  SurfaceMesh out;
  std::vector<SurfaceMesh::Vertex_index> index(mesh.num_vertices(), SurfaceMesh::null_vertex());
  for (const auto& t : mesh.triangles) {
    for (const std::int32_t v : t) {
      if (index[v] == SurfaceMesh::null_vertex()) {
        const auto& p = mesh.vertices[v];
        index[v] = out.add_vertex(Point(p.x(), p.y(), p.z()));
      }
    }
  }
  for (const auto& t : mesh.triangles) {
    if (out.add_face(index[t[0]], index[t[1]], index[t[2]]) == SurfaceMesh::null_face()) {
      throw_error(what, ": not a manifold surface (CGAL could not add a triangle)");
    }
  }
  return out;
}

geometry::TriMesh to_tri_mesh(const SurfaceMesh& mesh) {
  geometry::TriMesh out;
  std::vector<std::int32_t> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), -1);
  out.vertices.reserve(mesh.number_of_vertices());
  for (const auto v : mesh.vertices()) {
    index[v.idx()] = static_cast<std::int32_t>(out.vertices.size());
    const Point& p = mesh.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  out.triangles.reserve(mesh.number_of_faces());
  for (const auto f : mesh.faces()) {
    geometry::Triangle t{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) t[k] = index[v.idx()];
      ++k;
    }
    if (k != 3) throw_error("mesh Boolean: CGAL returned a face with ", k, " vertices");
    out.triangles.push_back(t);
  }
  return out;
}

}  // namespace

bool is_closed(const geometry::TriMesh& mesh) {
  if (mesh.empty()) return false;
  return geometry::check_mesh(mesh).boundary_edges == 0;
}

bool is_manifold(const geometry::TriMesh& mesh) {
  if (mesh.empty()) return true;
  const auto report = geometry::check_mesh(mesh);
  return report.non_manifold_edges == 0 && report.non_manifold_vertices == 0;
}

bool does_self_intersect(const geometry::TriMesh& mesh) {
  if (mesh.empty()) return false;
  if (is_manifold(mesh)) return PMP::does_self_intersect(to_surface_mesh(mesh, "mesh"));
  // Split the soup at its non-manifold edges and vertices (orient_polygon_soup duplicates the
  // points there) so that it becomes a polygon mesh; triangles that met there then intersect.
  std::vector<Point> points;
  points.reserve(mesh.num_vertices());
  for (const auto& p : mesh.vertices) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::array<std::size_t, 3>> polygons;
  polygons.reserve(mesh.num_triangles());
  for (const auto& t : mesh.triangles) {
    polygons.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                        static_cast<std::size_t>(t[2])});
  }
  PMP::orient_polygon_soup(points, polygons);
  SurfaceMesh split;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, split);
  return PMP::does_self_intersect(split);
}

double volume(const geometry::TriMesh& mesh, const std::string& what) {
  if (!is_closed(mesh)) throw_error(what, ": the volume of an open surface is undefined");
  return geometry::signed_volume(mesh);
}

void require_solid(const geometry::TriMesh& mesh, const std::string& what) {
  geometry::validate_mesh(mesh, what);
  const auto report = geometry::check_mesh(mesh);
  if (report.boundary_edges > 0) {
    throw_error(what, ": not closed (", report.boundary_edges, " boundary edges)");
  }
  if (report.non_manifold_edges > 0 || report.non_manifold_vertices > 0) {
    throw_error(what, ": not manifold (", report.non_manifold_edges, " non-manifold edges, ",
                report.non_manifold_vertices, " non-manifold vertices)");
  }
  if (report.degenerate_triangles > 0) {
    throw_error(what, ": ", report.degenerate_triangles, " degenerate triangles");
  }
  if (!report.outward) {
    throw_error(what, ": not outward-oriented (signed volume ", report.signed_volume_mm3,
                " mm^3, ", report.inconsistent_edges, " inconsistently oriented edges)");
  }
  if (PMP::does_self_intersect(to_surface_mesh(mesh, what))) {
    throw_error(what, ": the surface intersects itself");
  }
}

BooleanResult compute_booleans(const BooleanRequest& request) {
  if (request.a == nullptr || request.b == nullptr) {
    throw_error("mesh Boolean: both solids are required");
  }
  require_solid(*request.a, request.a_name);
  require_solid(*request.b, request.b_name);
  // Corefinement modifies both inputs: it works on copies.
  SurfaceMesh a = to_surface_mesh(*request.a, request.a_name);
  SurfaceMesh b = to_surface_mesh(*request.b, request.b_name);
  std::array<SurfaceMesh, 3> outputs;
  std::array<boost::optional<SurfaceMesh*>, 4> wanted;
  const auto& asked = request.outputs;
  if (asked.union_of) wanted[PMP::Corefinement::UNION] = &outputs[0];
  if (asked.intersection) wanted[PMP::Corefinement::INTERSECTION] = &outputs[1];
  if (asked.difference) wanted[PMP::Corefinement::TM1_MINUS_TM2] = &outputs[2];
  const std::array<bool, 4> ok = PMP::corefine_and_compute_boolean_operations(a, b, wanted);
  const auto check = [&](bool asked_for, int op, const char* name) {
    if (asked_for && !ok[op]) {
      throw_error("mesh Boolean ", request.a_name, " ", name, " ", request.b_name,
                  ": CGAL could not build a manifold result");
    }
  };
  check(asked.union_of, PMP::Corefinement::UNION, "union");
  check(asked.intersection, PMP::Corefinement::INTERSECTION, "intersection");
  check(asked.difference, PMP::Corefinement::TM1_MINUS_TM2, "minus");
  BooleanResult result;
  if (asked.union_of) result.union_of = to_tri_mesh(outputs[0]);
  if (asked.intersection) result.intersection = to_tri_mesh(outputs[1]);
  if (asked.difference) result.difference = to_tri_mesh(outputs[2]);
  return result;
}

namespace {

BooleanResult one_boolean(const geometry::TriMesh& a, const geometry::TriMesh& b, const std::string& a_name,
                          const std::string& b_name, BooleanOutputs outputs) {
  BooleanRequest request;
  request.a = &a;
  request.b = &b;
  request.a_name = a_name;
  request.b_name = b_name;
  request.outputs = outputs;
  return compute_booleans(request);
}

}  // namespace

geometry::TriMesh difference(const geometry::TriMesh& a, const geometry::TriMesh& b, const std::string& a_name,
                             const std::string& b_name) {
  return one_boolean(a, b, a_name, b_name, {false, false, true}).difference;
}

geometry::TriMesh intersection(const geometry::TriMesh& a, const geometry::TriMesh& b,
                               const std::string& a_name, const std::string& b_name) {
  return one_boolean(a, b, a_name, b_name, {false, true, false}).intersection;
}

geometry::TriMesh union_of(const geometry::TriMesh& a, const geometry::TriMesh& b, const std::string& a_name,
                           const std::string& b_name) {
  return one_boolean(a, b, a_name, b_name, {true, false, false}).union_of;
}

SelfIntersectionRepair repair_self_intersections(const geometry::TriMesh& mesh, const std::string& what) {
  SelfIntersectionRepair out;
  if (!is_closed(mesh) || !is_manifold(mesh)) throw_error(what, ": not a closed manifold surface");
  SurfaceMesh surface = to_surface_mesh(mesh, what);
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> pairs;
  PMP::self_intersections(surface, std::back_inserter(pairs));
  out.pairs_before = pairs.size();
  if (pairs.empty()) {
    out.mesh = mesh;
    return out;
  }
  geometry::Vec3 sum = geometry::Vec3::Zero();
  for (const auto& [f, g] : pairs) {
    for (const auto face : {f, g}) {
      for (const auto v : CGAL::vertices_around_face(surface.halfedge(face), surface)) {
        const Point& p = surface.point(v);
        sum += geometry::Vec3(p.x(), p.y(), p.z()) / 6.0;
      }
    }
  }
  out.where_mm = sum / static_cast<double>(pairs.size());
  PMP::experimental::remove_self_intersections(surface);
  if (PMP::does_self_intersect(surface) || !CGAL::is_closed(surface)) {
    throw_error(what, ": ", pairs.size(), " self-intersecting triangle pairs near (", out.where_mm.x(), ", ",
                out.where_mm.y(), ", ", out.where_mm.z(), ") could not be repaired");
  }
  out.mesh = to_tri_mesh(surface);
  out.repaired = true;
  return out;
}

}  // namespace hipfai::anatomy
