// hipfai — gmsh MSH 2.2 ASCII: the one reader and writer of the format in the tree.
//
// Two users: geometry/mesh_io.h reads and writes surface meshes as .msh (triangles), and
// geometry/hip_volume_mesh.h the FE's hexahedral meshes (hexahedra and boundary quadrangles with
// physical tags). Both go through MshMesh, the file's content: nodes, elements with their
// physical and elementary tags, and $PhysicalNames. Other sections ($NodeData, ...) are skipped.
// Counts are checked against the bytes left in the file before anything is allocated, so a
// corrupt count is an error, not an allocation of gigabytes.
#pragma once

#include "geometry/tri_mesh.h"

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hipfai::geometry::mesh_io {

// gmsh element types this reader takes (first order only), with their node counts.
enum class MshElementType : int {
  kLine = 1,           // 2 nodes
  kTriangle = 2,       // 3
  kQuadrangle = 3,     // 4
  kTetrahedron = 4,    // 4
  kHexahedron = 5,     // 8
  kPrism = 6,          // 6
  kPyramid = 7,        // 5
  kPoint = 15,         // 1
};

struct MshElement {
  std::int64_t id = 0;  // as in the file (messages name it)
  MshElementType type = MshElementType::kTriangle;
  int physical = 0;     // first tag (0 when the element has none)
  int elementary = 0;   // second tag (0 when absent)
  std::array<std::int32_t, 8> nodes{};  // 0-based indices into MshMesh::nodes, first node_count(type)
};

struct MshPhysicalName {
  int dimension = 0;
  int tag = 0;
  std::string name;
};

struct MshMesh {
  std::vector<Vec3> nodes;
  std::vector<MshElement> elements;
  std::vector<MshPhysicalName> physical_names;
};

std::size_t node_count(MshElementType type);

// Parses an ASCII MSH 2.2 file. Throws hipfai::Error "<name>: <problem>" (not MSH 2.2, binary,
// truncated section, unknown node, unsupported element type, ...).
MshMesh parse_msh(const std::string& name, std::string_view text);
// The file's text; node ids and element ids are 1-based positions.
std::string format_msh(const MshMesh& mesh);

// Surface view for geometry/mesh_io.h: the triangles (quadrangles split in two along their first
// diagonal) over the nodes they use, kept in file order; other elements are ignored.
TriMesh read_msh(const std::string& name, std::string_view text);
// Triangles with physical and elementary tag 1; vertex fields are dropped.
std::string write_msh(const TriMesh& mesh);

}  // namespace hipfai::geometry::mesh_io
