// hipfai — the pre-processed table of radial segmenting (thesis §3.3.3.1.4, §3.3.4).
//
// Built once for the FIXED mesh F and a centre O; reused for every pose of the mobile mesh. Each
// cell holds the index of every fixed triangle whose cone from O meets the cell's region (exact,
// conservative: see cells_of_polygon in radial_mapping.h), so a ray from O in any direction finds,
// in the cell of that direction, every triangle it crosses. Two special lists:
//   - zero-area triangles are stored nowhere (no ray crosses them, ray_triangle.h);
//   - triangles whose plane passes within 1e-6 x their largest vertex distance of O (their cone
//     degenerates toward a fan in a plane through O, which cells_of_polygon cannot bin robustly)
//     are binned along the great-circle arc they cover, thickened by their angular distance from
//     that circle (see cells_of_arc_triangle in radial_table.cpp for the bound and for why rays
//     exactly tangent to them never count); only those so close to O that this band would be
//     thick (>= 0.2 rad) are kept in `always_candidates` and checked by every query. (Revolved
//     rim faces of cartilage and labrum are such triangles: thousands of them made the query
//     quadratic when they were all always-checked.)
// The table stores indices only: the fixed mesh's coordinates are read at query time, so a
// deformation along the rays (radial, §3.3.4) needs no update at all.
//
// Thread safety: a const RadialTable may be queried from any number of threads.
#pragma once

#include "contact/radial_mapping.h"
#include "contact/radial_spans.h"
#include "geometry/tri_mesh.h"

#include <cstdint>
#include <span>
#include <vector>

namespace hipfai::contact {

struct RadialTableOptions {
  RadialMapping mapping = RadialMapping::kCube;
  // Target number of cells (Eq. 8); the thesis advises a cell about the size of a triangle.
  std::int64_t table_size = 4096;
};

struct RadialTable {
  RadialGrid grid;
  Vec3 centre = Vec3::Zero();                     // O, mm
  std::vector<std::vector<std::int32_t>> cells;   // cell id -> fixed triangle indices
  std::vector<std::int32_t> always_candidates;    // plane through O: checked for every vertex
  std::vector<std::vector<std::int32_t>> triangle_cells;  // triangle -> its cells (for updates)
  std::vector<std::uint8_t> is_always;            // triangle -> in always_candidates?
  std::size_t num_triangles = 0;
  RadialSpans spans;  // which vertices need no triangle test (radial_spans.h), rebuilt by updates

  const std::vector<std::int32_t>& cell(int id) const { return cells[static_cast<std::size_t>(id)]; }
  // Total stored entries (memory measure, thesis §3.3.5).
  std::size_t num_entries() const;
};

// Builds the table of `fixed` around `centre`. Throws hipfai::Error naming the mesh when it is
// invalid (validate_mesh) or the centre is not finite.
RadialTable build_radial_table(const geometry::TriMesh& fixed, const Vec3& centre,
                               const RadialTableOptions& options);

// Deformation (§3.3.4): re-bins only the listed triangles of the (deformed) mesh, which must have
// the same triangles as when the table was built. The result equals a full rebuild up to the
// order of indices inside a cell. The spans are recomputed for the whole mesh. Throws hipfai::Error on an index out of range or a size change.
void update_triangles(RadialTable& table, const geometry::TriMesh& fixed,
                      std::span<const std::int32_t> changed_triangles);

}  // namespace hipfai::contact
