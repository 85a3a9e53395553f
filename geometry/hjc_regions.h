// hipfai — the surfaces the HJC estimators fit (thesis §4.4.2.2): the femoral head and the
// lunate (articular) surface of the acetabulum, found on the bones or given by the user.
//
// Femoral head, automatic: "the part of the proximal femur that a sphere fits". Every vertex votes,
// for each radius r of the search band, for the centre p - r n (n its outward normal); the densest
// (centre, radius) cells, weighted by the vertices' areas, are candidate spheres. Each candidate
// is refined: the vertices within a band of its surface whose normals point away from its centre
// (the head's outer face), a geometric sphere fit, the band narrowed to max(min_band, 2.5 rms),
// repeated, then the largest connected patch of those vertices. The candidate with the largest
// area wins; when a pelvis is given, only candidates with pelvis vertices within
// radius + pelvis_reach_mm of their centre qualify (the head sits in the acetabulum; the condyles
// of a whole femur do not).
//
// Lunate surface, automatic: pelvis vertices facing the head centre (normal within facing_deg of
// the direction to the centre) at a distance from it in [r_head - 1 mm, r_head + band_mm], then
// refined the same way against their own sphere (this drops the deeper acetabular fossa and the
// rim), largest connected patch.
//
// Given regions: a vertex list (indices into the mesh), a 0/1 mask of one value per vertex, or a
// separate surface mesh of the region alone; `source` says which.
#pragma once

#include "geometry/sphere_fit.h"
#include "geometry/tri_mesh.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace hipfai::geometry {

// A patch of a surface: its own vertices and triangles (indices into `patch.vertices`), the
// outward unit normals of its vertices, and where it came from.
struct SurfaceRegion {
  std::string source;                       // "automatic", "vertex mask", "vertex list", "mesh"
  TriMesh patch;                            // region vertices; triangles with all corners in it
  std::vector<Vec3> normals;                // #patch.vertices unit outward normals
  std::vector<std::int32_t> mesh_vertices;  // index of each patch vertex in its mesh (-1: own mesh)
  SphereFit sphere;                         // the sphere fitted during region finding (automatic)
};

struct HeadRegionOptions {
  // Radius search band, mm: wide around adult femoral heads (the thesis' model: 25 mm articular,
  // its bone 23 mm) so that the search itself does not decide the answer.
  double min_radius_mm = 15.0;
  double max_radius_mm = 35.0;
  double min_band_mm = 0.5;         // narrowest inlier band around the fitted sphere
  double facing_deg = 40.0;         // head normals within this of the radial direction
  double pelvis_reach_mm = 15.0;    // pelvis within radius + this of the centre (when given)
  // Smallest area of the head patch as a fraction of its sphere's (4 pi r^2): a femoral head is
  // more than half a sphere; a box's corner or a bone's flat patch that a sphere happens to touch
  // within the band is far less.
  double min_coverage = 0.15;
  // Largest RMS residual of the head's sphere fit: above segmentation noise (1.5 mm, thesis
  // §4.4.2.1.2) with margin; a box corner's "sphere" is far worse.
  double max_rms_mm = 2.0;
  int candidates = 8;
};

struct LunateRegionOptions {
  double band_mm = 10.0;            // pelvis surface up to r_head + band from the head centre
  double facing_deg = 50.0;         // normal within this of the direction to the head centre
  double min_band_mm = 0.5;
  std::size_t min_vertices = 30;
};

// The triangles of `mesh` whose three corners satisfy keep_vertex, with only the vertices they use
// (compacted, order kept).
TriMesh submesh_where(const TriMesh& mesh, const std::function<bool(const Vec3&)>& keep_vertex);

// Principal axis (direction of largest spread) of the vertices, unit length, sign arbitrary;
// `centroid` (if not null) receives their mean.
Vec3 principal_axis(const TriMesh& mesh, Vec3* centroid = nullptr);

// Outward unit vertex normals (area-weighted triangle normals).
std::vector<Vec3> vertex_normals(const TriMesh& mesh);

// The patch of `mesh` made of `vertices` (indices, any order, duplicates ignored).
SurfaceRegion region_from_vertices(const TriMesh& mesh, const std::vector<std::int32_t>& vertices,
                                   const std::string& source);

// A separate mesh as a region of itself.
SurfaceRegion region_from_mesh(const TriMesh& region_mesh);

// Reads a region of `mesh` from `path`: a mesh file (.stl, .obj, .ply, .vtp, .msh: a separate mesh), or
// a text file of integers, either one 0/1 per vertex of `mesh` (a mask) or vertex indices
// (separated by whitespace or commas). Throws hipfai::Error "<path>: ..." on anything else.
SurfaceRegion read_region(const TriMesh& mesh, const std::filesystem::path& path);

// Automatic femoral head. `pelvis` may be null. Throws hipfai::Error "<what>: no femoral head
// found: ..." when no part of the femur fits a sphere in the radius band.
SurfaceRegion find_femoral_head(const TriMesh& femur, const TriMesh* pelvis,
                                const HeadRegionOptions& options = {},
                                const std::string& what = "femur");

// Automatic lunate surface around the head sphere (centre, radius). Throws hipfai::Error
// "<what>: no lunate surface found: ..." when too few pelvis vertices face the head.
SurfaceRegion find_lunate_surface(const TriMesh& pelvis, const Vec3& head_center_mm,
                                  double head_radius_mm, const LunateRegionOptions& options = {},
                                  const std::string& what = "pelvis");

}  // namespace hipfai::geometry
