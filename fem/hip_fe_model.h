// hipfai — the finite-element model of a hip (thesis §4.3.2.3 and §4.5.3.3).
//
// Deformable (Q2, linear elastic, core/literature.h): femoral cartilage and acetabular cartilage
// (E = 12 MPa, nu = 0.45), labrum (E = 20 MPa, nu = 0.4), meshed with hexahedra by
// geometry/hip_volume_mesh.h. Rigid: the femur (rigid body kFemurBody) and the pelvis
// (kPelvisBody).
//   - The femoral cartilage is bonded to the femur, which rotates about the hip joint centre
//     (prescribed per step) and translates freely under the joint reaction force (load control,
//     fem/motion_solver.h), so the head can relocate in the socket as in the thesis's ABAQUS runs.
//   - The femoral bone surface (head, neck and cam: the model's femur_bone TriMesh) is also a rigid
//     contact master (fem/rigid_mesh_surface.h) for the labrum and the acetabular cartilage: the cam
//     impinges there where no femoral cartilage covers the bone.
//   - Acetabular cartilage and labrum are bonded to the fixed pelvis.
// Contact pairs (slave -> master), frictionless, gap along the master normal:
//   acetabular cartilage articular -> femoral cartilage articular   (both deformable)
//   labrum articular               -> femoral cartilage articular   (both deformable)
//   labrum articular               -> femur bone surface            (rigid)
//   acetabular cartilage articular -> femur bone surface            (rigid)
// Material ids are the VolumeTag values, boundary ids the SurfaceTag values.
//
// Mesh levels (HipFeLevel -> geometry::HipVolumeOptions): see hip_volume_options(). The hexes are
// built along rays from the HJC and the articular surfaces of the generated hips are spheres about
// it (thesis: deviation < 100 um), so every cell gets a SphericalManifold about the HJC: the Q2
// mapping then follows the spheres instead of facets whose sagitta (e^2 / 8R = 0.02 mm for a 2 mm
// edge on R = 25 mm) would be of the order of the cartilage compression itself.
#pragma once

#include "core/fe_choices.h"
#include "fem/contact_problem.h"
#include "fem/motion_solver.h"
#include "geometry/hip_model.h"
#include "geometry/hip_volume_mesh.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>

#include <deal.II/grid/tria.h>

#include <optional>
#include <string>
#include <vector>

namespace hipfai::fem {

inline constexpr unsigned int kFemurBody = 0;   // index into ContactModel::rigid_bodies
inline constexpr unsigned int kPelvisBody = 1;

// Body weight used when none is given (N): a 71 kg adult. A modelling default, not a literature
// value — every result scales with it through the joint force, so the CLI exposes it.
inline constexpr double kDefaultBodyWeightN = 700.0;

// The mesh levels (their names: core/fe_choices.h).
using HipFeLevel = FeLevel;

// Level -> volume mesh options (edge on the articular faces, hexes through the thickness,
// minimum thickness of the blunted tapered edges); hexes and DOFs for the CE 20 / alpha 40 hip:
//   coarse   edge 6 mm, 1 layer    ~420 hexes, ~16 k DOFs (Q2); the tests' level
//   default  edge 4 mm, 2 layers   ~1 700 hexes
//   fine     edge 3 mm, 3 layers   ~4 500 hexes; the mesh-convergence reference
// (docs/fem-levels.md has the measured numbers.) The minimum thickness stays 0.25 mm at every
// level so that the geometry does not change with the level, only the discretisation does.
// 8 mm is too coarse for the generated hips (inverted hexahedra at the labrum).
geometry::HipVolumeOptions hip_volume_options(HipFeLevel level);

// Fills `triangulation` from `mesh`: gmsh hexahedron order -> deal.II lexicographic order,
// material id = VolumeTag, boundary id = SurfaceTag (faces without a quad keep id 0, which no
// boundary condition uses: free). Cells are re-oriented if needed (negative measure, inconsistent
// face orientation). Throws hipfai::Error "<what>: ..." when the mesh cannot be used.
void create_hex_triangulation(const geometry::HexMesh& mesh, dealii::Triangulation<3>& triangulation,
                              const std::string& what = "hex mesh");

struct HipFeOptions {
  // Attach a SphericalManifold about the HJC to every cell (see above). Off for meshes whose
  // surfaces are not spheres about the HJC (e.g. segmented real hips).
  bool spherical_manifold = true;
};

// Sets up `problem` (its triangulation must be empty): mesh, bodies, rigid bodies, bonded
// boundaries and contact pairs as described above. `femur_bone` is the closed femoral bone
// surface in the hip frame; `hjc_mm` the rotation centre. Tissues missing from the mesh are left
// out with their pairs. Throws hipfai::Error when the mesh has no femoral cartilage or nothing on
// the acetabular side, or when femur_bone is not a usable surface.
void build_hip_fe_model(ContactProblem& problem, const geometry::HexMesh& mesh,
                        const geometry::TriMesh& femur_bone, const geometry::Vec3& hjc_mm,
                        const HipFeOptions& options = {});

// Names of the deformable bodies build_hip_fe_model creates, in order (HDF5 "bodies").
std::vector<std::string> hip_fe_body_names(const ContactProblem& problem);

// One motion step from a femur rotation and the force the femur applies to the pelvis (hip
// frame; the convention of fem::MotionStep and studies::sitting_down_force_n).
MotionStep make_hip_motion_step(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& force_n);

// The stand-in joint force until a load profile is given: kStandToSitPeakForcePercentBW of body
// weight straight up (+Z): the femur pushes the acetabulum superiorly (Bergmann's force on the
// femoral head is the reaction, along -Z).
Eigen::Vector3d constant_joint_force_n(double body_weight_n);

}  // namespace hipfai::fem
