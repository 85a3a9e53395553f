// hipfai — hexahedral volume meshes of a hip's soft tissues, for the finite-element ground truth.
//
// The FE model (fem/) needs the deformable tissues — femoral cartilage, acetabular cartilage,
// labrum — as hexahedral meshes (Q2 elements do not lock at nu = 0.45) with tagged cells and
// tagged boundary faces: where a tissue is bonded to bone, where it can touch the other side of
// the joint, and where it is free. Thin layers that taper to zero thickness (the cartilage edge,
// the labrum tip) are meshed as layers of hexahedra between the articular face and the far face
// of the tissue along rays from the hip joint centre, with a minimum thickness.
//
// Construction (each tissue on its own, generic in the tissue's surface): the rays from the HJC
// that cross the tissue form its "shadow" on the sphere of directions, bounded by the boundary
// loops of the faces through which the rays leave on the articular side. The shadow is projected
// stereographically (conformal) about the direction that keeps it closest, quad-meshed there by
// gmsh (Blossom recombination under a size field that undoes the projection's scale, so edges
// come out near edge_mm on the articular sphere), and mapped back. Each node becomes a column
// along its ray from the first to the last crossing of the tissue's surface, split into `layers`
// hexahedra. Consequences a user of the mesh should know:
//   - every hex edge through the thickness lies on a ray from the HJC; the articular and far
//     faces' nodes lie at the distance from the HJC interpolated between the vertices of the
//     triangle the ray crosses (barycentric), so on the sphere itself where the tissue's
//     vertices sample a sphere about the HJC, not on its chords (a spherical manifold about the
//     HJC fits); on side walls (faces more than 45 deg from radial) they lie on the triangles;
//   - a column thinner than min_thickness_mm keeps its articular end and is lengthened at the
//     far end (at a side wall seen from the joint, e.g. the fossa silhouette, the bonded end
//     stays on the bone instead);
//   - corners are checked on the sphere of directions, where the hexahedra's edges are chords:
//     a boundary node used by one quad only, whose corner there is flatter than 178 deg (a plane
//     angle far from the projection centre turns by ~12 deg), has its column turned out of the
//     outline until the corner is 170 deg (0.1-0.4 mm), keeping its extent; an interior node
//     with such a corner moves to the mean of its neighbours when that helps;
//   - an articular-side quad is tagged articular only if all four of its columns hit a face
//     within 45 deg of radial there; quads over a side wall (fossa, labral notch) are kFree;
//   - side faces (the columns at the shadow's boundary) are kFree, except the labrum's side
//     faces lying in the acetabular rim plane: kLabrumBonded;
//   - a tissue in several connected pieces (a labrum open at the notch and again where the neck
//     passes under the rim) is meshed piece by piece, each with its own shadow.
// Tissues synthesised on segmented bones (HipModel::soft_tissue, anatomy/soft_tissue.h) are radial
// layers about the HJC already, but the cartilages' outlines follow the bone's triangles in a
// zigzag: for them the outline is smoothed over one edge length before the quad mesh, and a
// boundary node is moved onto the true outline only when its own ray misses the tissue; their
// labrum's base lies along the measured rim, not on a cone, so its bonded side faces are those
// facing away from the acetabular axis (not the end caps nor the tip). When no candidate
// projection centre holds the whole shadow within 150 deg (a segmented head seen from its
// centre), the centre of the smallest cap holding it is used.
//
// Files are gmsh MSH 2.2 ASCII: hexahedra (type 5) with their tissue as physical tag, boundary
// quadrangles (type 3) with their surface tag as physical tag, $PhysicalNames naming both.
#pragma once

#include "geometry/hip_model.h"
#include "geometry/tri_mesh.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::geometry {

// Physical tags of the hexahedra (one per deformable tissue).
enum class VolumeTag : int {
  kFemoralCartilage = 1,
  kAcetabularCartilage = 2,
  kLabrum = 3,
};

// Physical tags of the boundary quadrangles.
enum class SurfaceTag : int {
  kFree = 10,                          // touches nothing in the model
  kFemoralCartilageArticular = 11,     // faces the acetabulum: contact surface
  kFemoralCartilageBonded = 12,        // on the femoral bone: moves rigidly with the femur
  kAcetabularCartilageArticular = 21,  // faces the femoral head: contact surface
  kAcetabularCartilageBonded = 22,     // on the acetabular bone: fixed
  kLabrumArticular = 31,               // faces the femoral head and neck: contact surface
  kLabrumBonded = 32,                  // its base on the acetabular rim: fixed
};

const char* to_string(VolumeTag tag);
const char* to_string(SurfaceTag tag);

struct HexMesh {
  std::vector<Vec3> vertices;                         // mm, hip frame
  std::vector<std::array<std::int32_t, 8>> hexes;     // gmsh order: bottom face 0-1-2-3, top 4-5-6-7
  std::vector<VolumeTag> hex_tags;                    // one per hexahedron
  std::vector<std::array<std::int32_t, 4>> quads;     // every boundary face, once
  std::vector<SurfaceTag> quad_tags;                  // one per boundary quad
};

struct HipVolumeOptions {
  double edge_mm = 2.0;            // target edge length on the articular faces
  int layers = 2;                  // hexahedra through the thickness
  double min_thickness_mm = 0.25;  // tapered edges (cartilage edge, labrum tip) are blunted to this
  // The labrum's own edge length and layers (0: edge_mm and layers). Its 5 mm section holds
  // only a few cells at the cartilage's sizes.
  double labrum_edge_mm = 0.0;
  int labrum_layers = 0;
};

struct HipVolumeMesh {
  HexMesh mesh;
  HipVolumeOptions options;
  // Smallest scaled Jacobian over all hexahedra (1 = perfect cube corner, <= 0 = inverted).
  double min_scaled_jacobian = 0.0;
};

// Builds the hexahedral meshes of femoral_cartilage, acetabular_cartilage and labrum of `model`
// (their surfaces must be loaded). Throws hipfai::Error on a model it cannot mesh.
HipVolumeMesh build_hip_volume_mesh(const HipModel& model, const HipVolumeOptions& options = {});

// Smallest scaled Jacobian over all hexahedra and their 8 corners: at each corner the determinant
// of the three unit edge vectors leaving it (1 for a cube, <= 0 when inverted or degenerate).
double min_scaled_jacobian(const HexMesh& mesh);

// MSH 2.2 ASCII, written atomically (a temporary file renamed at the end).
void write_hex_msh(const HexMesh& mesh, const std::filesystem::path& file);
// Reads what write_hex_msh writes; throws hipfai::Error "<file>: <problem>" on anything else.
HexMesh read_hex_msh(const std::filesystem::path& file);

}  // namespace hipfai::geometry
