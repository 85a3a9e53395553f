// hipfai — the benchmark scenarios of thesis §3.4 (Tables 1-3), generated.
//
//   striking_hip     femoral bone (mobile) vs acetabular bone (fixed) of a parametric hip, rotated
//                    about the HJC (cylindrical segmenting). Four resolutions: a coarse hip
//                    (~2 k vertices in total) and 1, 2, 3 midpoint subdivisions (x4 each, as the
//                    thesis' Table 1 ladder 773 -> 3 086 -> 12 338 -> 49 346 is), up to ~120 k.
//   striking_real_ct the real CT femur vs pelvis of meshes/real-hips/LHDL_CT at the HJC
//                    of hip.json (83 k vertices), one resolution.
//   sphere_cube      octasphere (mobile, levels 2..8: 66 .. 262 146 vertices) rotating about its
//                    centre, vs a box (fixed) capping the upper ~17 % of its area (bottom face at
//                    z = 0.66 R), box faces 4, 8, 16, 32, 64, 64, 64 divisions (thesis Table 2).
//   cartilage        femoral cartilage (mobile) vs acetabular cartilage + labrum (fixed), rotated
//                    about the HJC and pushed 0.6 mm superiorly (sliding); coarse + 3 subdivisions.
// A midpoint subdivision keeps the shape (planar facets) and multiplies the counts by ~4; it is
// how the resolution ladders are built, so every level of a family has the same geometry.
// Striking poses are chosen from the exact range of motion of the coarsest level: the rotation
// that limits first, plus a margin, so every level penetrates.
#pragma once

#include "contact/radial_segmenting.h"
#include "geometry/hip_model.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace hipfai::bench {

struct Scenario {
  std::string family;     // striking_hip, striking_real_ct, sphere_cube, cartilage
  std::string name;       // family + level, e.g. "sphere_cube_L5"
  int level = 0;
  bool radial = false;    // radial (sliding) or cylindrical (striking)
  geometry::TriMesh fixed;
  geometry::TriMesh mobile;                      // at pose 0
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit
  double angle_deg = 0.0;                        // the benchmark pose
  Eigen::Vector3d translation_mm = Eigen::Vector3d::Zero();
  contact::RadialConfiguration configuration = contact::RadialConfiguration::kMobileInsideFixed;

  std::size_t total_vertices() const { return fixed.num_vertices() + mobile.num_vertices(); }
  // Pose of the mobile mesh in the fixed frame: rotation about (centre, axis), then translation.
  Eigen::Isometry3d pose() const;
  geometry::TriMesh posed_mobile() const;
};

// Splits every triangle in four at its edge midpoints, `times` times (shared edges keep shared
// midpoints, so a closed mesh stays closed and its orientation is kept).
geometry::TriMesh subdivide_midpoint(const geometry::TriMesh& mesh, int times);

// Applies a rigid transform to a copy of the mesh.
geometry::TriMesh transformed(const geometry::TriMesh& mesh, const Eigen::Isometry3d& transform);

// Sphere (level 2..8) vs capping cube, the sphere rotated by 23 degrees about (1, 2, 3).
Scenario make_sphere_cube(int sphere_level);

// The coarse parametric hip the hip families are subdivided from (gmsh; a few seconds).
geometry::HipModel make_coarse_hip(double edge_mm = 5.5);

// Levels 0..max_level (subdivisions). The pose is chosen on level 0 by the range finder.
std::vector<Scenario> make_striking_hip(const geometry::HipModel& hip, int max_level);
std::vector<Scenario> make_cartilage(const geometry::HipModel& hip, int max_level);

// Thesis §3.7.2, non-medical examples (cylindrical segmenting, about 10 k vertices each):
//   lever_stone  a 120 mm lever (box) turning about its fulcrum (the z axis through the origin)
//                against a stone (sphere of radius 10 mm); the pose is the exact first contact
//                (range finder) plus 2 degrees.
//   torus_rough  a torus wheel (R 20, r 5 mm, axis y) rolling by 7 degrees about its axis on a
//                rough surface (open height field, bumps up to ~1 mm into the wheel's rim).
// The defaults are the benchmark's sizes; the unit tests build smaller ones of the same shapes
// (stone: octasphere level; lever: box divisions per face; wheel: segments around the axis and
// around the tube; ground: grid spacing, which must divide 60 and 24 mm).
Scenario make_lever_stone(int stone_level = 5, int lever_divisions = 24);
Scenario make_torus_rough(int wheel_segments = 160, int tube_segments = 32, double ground_spacing_mm = 0.5);

// The real CT bones (throws hipfai::Error if the files are missing).
Scenario make_striking_real_ct(const std::string& lhdl_dir);

}  // namespace hipfai::bench
