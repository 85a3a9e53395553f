// hipfai — radial spans of a radial table: which mobile vertices need no triangle test.
//
// Rotation about the centre O keeps every point's distance r = |v - O|. A ray from O meets a fixed
// triangle only at a distance within the triangle's radial span [lo, hi] (lo = distance from O to
// the closed triangle, hi = its largest vertex distance), and only in a direction inside the cone
// from O over the triangle. So, before any triangle test:
//   - CAP: every fixed point lies in one cone {x : x . axis >= |x| cos_angle} (a cap of directions,
//     kept only when narrower than 89 deg, where it is convex and so holds each triangle's cone);
//     a vertex whose direction is outside it has no crossing at all and never penetrates.
//   - SPAN of a cell (or of the whole mesh): [lo, hi] over the triangles its ray can meet (the
//     cell's list and the always-checked list). A vertex at r outside it is decided without a test
//     whenever the crossing rule needs a crossing on that side of v:
//       kAdjacent, kMobileInsideFixed   needs a crossing with t < 1: culled when r < lo;
//       kAdjacent, kFixedInsideMobile   needs a crossing with t > 1: culled when r > hi;
//       kUnion (either configuration)   needs winding > 0 from crossings with t > 1: culled when r > hi.
//       kBeyond, kMobileInsideFixed     needs a crossing with 0 < t < 1: culled when r < lo;
//       kBeyond, kFixedInsideMobile     needs a crossing with t > 1: culled when r > hi.
//     A vertex beyond hi in kAdjacent, kMobileInsideFixed is NOT culled: its answer is the facing of
//     the outermost crossing (the parity of the surfaces behind it), which an open or grazed fixed
//     surface can make "enter"; it keeps the full test.
// EXACTNESS: the culled query equals the unculled one bit for bit. The spans are widened by a
// bound on the rounding of the crossing parameter t = a.(b x c) / (d.N) for rays that hit the
// triangle (relative error <= 8 eps (|b-a||c-a| / |N|) (hi / h) + 8 eps |a||b||c| / (h |N|), with
// h the plane's distance from O; for a hit, |d.N| >= |d||N| h / hi), so a float t that the query
// would compare with 1 lies on the same side as the true distance (h is taken as a lower bound,
// its rounding subtracted); triangles whose plane passes through O up to that rounding, or whose
// bound exceeds 1e-3, get the span [0, inf] and are never culled by distance. (Revolved rim faces,
// planes through O to ~1e-10, keep a span widened by ~1e-6 of it.) Every comparison keeps a further 1e-12 relative slack for |d| and the dot products.
// VALIDITY: spans depend on the fixed coordinates, which a radial deformation (§3.3.4) may move
// without updating the table. They are computed for `vertices` (a copy of the fixed coordinates);
// a query uses them only when the fixed mesh it is given has exactly those coordinates, otherwise
// it runs unculled (same answers, old speed).
#pragma once

#include "geometry/tri_mesh.h"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace hipfai::contact {

struct RadialTable;

struct RadialSpans {
  static constexpr double kInfinity = std::numeric_limits<double>::infinity();
  // The cells again, packed for the query (one record per cell, then its entries contiguously, each
  // with its triangle's span as floats rounded outward): the nested vectors of RadialTable cost a
  // cache miss per cell and per triangle span, which dominated the culled query.
  // HINTS (cube mapping): a cell is cut into kHintSide x kHintSide parts of equal extent in the cube
  // coordinates (CubeLocator::cell), and hint[part] is the slot (entry - wedge_end, < 32) of the
  // first entry past the flat wedge, in lo order, whose triangle the ray through the part's centre
  // crosses (in plain floating point: a hint only orders the tests), or kNoHint. The query tests that entry first: a clear hit there skips every entry
  // separated from it wherever it sits in the cell, so a vertex usually needs one test. The order
  // of the tests never changes an answer (ties go to the lowest triangle index).
  static constexpr int kHintSide = 4;
  static constexpr std::uint8_t kNoHint = 255;
  struct alignas(32) Cell {
    std::uint32_t begin = 0, end = 0;  // entries [begin, end)
    // Entries [begin, wedge_end) are the cell's triangles without a span (lo 0: planes through O up
    // to rounding, the rim faces of a revolved surface), skipped together by wedges[wedge] when
    // wedge_end > begin (see FLAT WEDGES below).
    std::uint32_t wedge_end = 0, wedge = 0;
    std::array<std::uint8_t, kHintSide * kHintSide> hint{};  // kNoHint where no entry is hinted
  };
  // FLAT WEDGES. A triangle whose plane passes through O (up to rounding) has no span: the rounding
  // of its crossing parameter is unbounded, so it is never culled by distance, and a cell on the
  // rim of a revolved surface holds a stack of them (every rim face projects onto the same curve of
  // directions). Their cones are thin: each lies within the wedge {x : |x . normal| <= sin_bound |x|}
  // around one plane through O. A ray outside it by far more than rounding (|d . normal| >
  // sin_bound |d|, sin_bound holding a 1e-9 margin) misses each of them in the exact test, so the
  // query skips them all with one dot product. Same answers bit for bit.
  struct FlatWedge {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit up to rounding (the bound is for these values)
    double sin_bound = 2.0;
  };
  struct Entry {
    std::int32_t triangle = -1;
    float lo = 0.0F, hi = 0.0F;
    std::uint32_t separated = 0;  // SEPARATED CONES below
  };
  // What the crossing test of a ray from O needs of one fixed triangle abc (coordinates relative
  // to O), computed once with the very expressions the per-ray test used, so every value is the
  // same bit for bit (ray_triangle.h): the three edge vectors a x b, b x c, c x a (the edge
  // function of a ray d is d . (p x q)), the area normal N = (b - a) x (c - a) and
  // det(a, b, c) = a . (b x c) (the crossing is at t = det / (d . N)). bound_* = 1e-13 |a|_inf
  // |b|_inf (and so on): times |d|_inf they bound the rounding of an edge function by far
  // (radial_segmenting.cpp). A ray is then tested with three dot products instead of three cross
  // products and three dot products over vertices fetched through the triangle's indices.
  struct alignas(64) TrianglePlanes {
    Eigen::Vector3d edge_ab, edge_bc, edge_ca, area_normal;
    double det = 0.0;
    double bound_ab = 0.0, bound_bc = 0.0, bound_ca = 0.0;
  };
  // The cube mapping's cell without atan: the a1 (a2) borders atan(u) + pi/4 = i pi / (2 n) sit at
  // u = tan(i pi / (2 n) - pi/4). Each cell's range of u is cut into kHintSide parts of equal
  // length (HINTS), n kHintSide slices in all; a lookup over u in [-1, 1] (2 n kHintSide bins)
  // gives the slice of the bin's lower end, and one comparison with the next slice border finishes.
  // Slice m lies in cell m / kHintSide (the cell borders are the slice borders m = i kHintSide,
  // the same values). It may differ from cell_of_direction only for directions within rounding
  // (~1e-15 rad) of a border, where both cells hold every triangle the ray can meet (the table bins
  // with a 1e-8 rad margin), so the answers are the same. Empty unless the table uses the cube mapping.
  struct CubeLocator {
    int dimension = 0;
    double bins_per_unit = 0.0;
    std::vector<double> border;        // dimension + 1 cell borders
    std::vector<double> slice_border;  // dimension kHintSide + 1
    std::vector<std::int32_t> start;   // per bin: the slice of its lower end
    int slice(double u) const {
      const int bins = static_cast<int>(start.size());
      int bin = static_cast<int>((u + 1.0) * bins_per_unit);
      bin = bin < 0 ? 0 : (bin >= bins ? bins - 1 : bin);
      int m = start[static_cast<std::size_t>(bin)];
      // A bin (width 1 / (n kHintSide) in u) is narrower than any slice (>= pi / (2 n kHintSide), as
      // du / dangle >= 1): at most one border lies inside it, so one comparison finishes.
      m += static_cast<int>(m + 1 < dimension * kHintSide && u >= slice_border[static_cast<std::size_t>(m + 1)]);
      return m;
    }
    // The cell id of a non-zero direction (as cell_of_direction for the cube mapping).
    int cell(const Eigen::Vector3d& d) const {
      int part = 0;
      return cell(d, part);
    }
    // The same, and the direction's part of the cell for the hints (HINTS).
    int cell(const Eigen::Vector3d& d, int& part) const {
      int k = 0;
      if (std::abs(d.y()) > std::abs(d[k])) k = 1;
      if (std::abs(d.z()) > std::abs(d[k])) k = 2;
      const double along = std::abs(d[k]);
      const int face = 2 * k + (d[k] < 0.0 ? 1 : 0);
      const int su = slice(d[(k + 1) % 3] / along), sw = slice(d[(k + 2) % 3] / along);
      part = (sw % kHintSide) * kHintSide + su % kHintSide;
      return (face * dimension + sw / kHintSide) * dimension + su / kHintSide;
    }
  };
  CubeLocator cube;
  std::vector<Eigen::Vector3d> vertices;  // fixed coordinates the spans are valid for
  std::vector<double> triangle_lo, triangle_hi;  // widened span per fixed triangle
  std::vector<TrianglePlanes> planes;            // per fixed triangle
  std::vector<Cell> cells;
  std::vector<FlatWedge> wedges;
  // Each cell's [lo, hi] again as floats rounded outward, in two arrays (4 bytes per cell each):
  // the test most vertices end at reads the one its side needs instead of the cell records.
  std::vector<float> cell_lo, cell_hi;
  // A cell's entries in ascending lo (ties: triangle index), so a vertex the kBelowLo side tests
  // stops at the first entry beyond its distance.
  std::vector<Entry> entries;
  // SEPARATED CONES (Entry::separated, in the entry so that one cache line brings both): bit s of
  // entries[k].separated is set when the cone from O over the triangle of entry k and that over the
  // entry cell.wedge_end + s of its cell (s < 32; flat triangles are never separated) have disjoint
  // interiors, proved by a plane through O along an edge of one of them with the other on its
  // closed far side (separating planes of two convex cones; the signs are those of the exact
  // triple products, certified by the error bound of TrianglePlanes, and a vertex the two
  // triangles share lies on that plane exactly). A ray whose crossing with entry k is a clear hit
  // (all three edge functions beyond their bounds, t > 0) runs strictly inside that cone, so it
  // misses every triangle separated from it: the query skips them. Same answers bit for bit.
  double lo = kInfinity, hi = -kInfinity;        // whole mesh
  Eigen::Vector3d cap_axis = Eigen::Vector3d::UnitZ();  // unit
  double cap_cos = -2.0;                         // <= -1: no cap (never culls)
};

// Distance from O to the closed triangle abc given relative to O (Ericson 2005 §5.1.5).
double distance_to_origin(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// The crossing test's per-triangle values of a triangle given relative to O (TrianglePlanes).
RadialSpans::TrianglePlanes triangle_planes(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// The cube locator of a cube-mapping grid of `dimension` cells per face edge (CubeLocator).
RadialSpans::CubeLocator make_cube_locator(int dimension);

// The corners of triangle t of `mesh` relative to `centre`.
inline std::array<Eigen::Vector3d, 3> triangle_relative(const geometry::TriMesh& mesh, std::size_t t,
                                                        const Eigen::Vector3d& centre) {
  const auto& tri = mesh.triangles[t];
  return {mesh.vertices[static_cast<std::size_t>(tri[0])] - centre, mesh.vertices[static_cast<std::size_t>(tri[1])] - centre,
          mesh.vertices[static_cast<std::size_t>(tri[2])] - centre};
}

// The flat wedge of triangles given by their vertices relative to O: a plane through O and the sine
// of the largest angle from it of any ray in their cones, with a 1e-9 margin (FLAT WEDGES); sin_bound
// is 2 (no wedge) when a vertex is at O, a triangle's cone reaches 60 deg from its mean direction, or the wedge would
// reach 30 deg from its plane.
RadialSpans::FlatWedge flat_wedge(std::span<const std::array<Eigen::Vector3d, 3>> triangles);

// The widened radial span of a triangle given relative to O (see EXACTNESS above).
void triangle_radial_span(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                          double& lo, double& hi);

// (Re)computes table.spans for `fixed` (the mesh the table's cells were binned from).
void compute_radial_spans(RadialTable& table, const geometry::TriMesh& fixed);

// True when the spans were computed for exactly these fixed coordinates.
bool radial_spans_valid(const RadialSpans& spans, const geometry::TriMesh& fixed);

// Proves cones from O over two triangles of a mesh interior-disjoint (RadialSpans::separated): an
// edge plane of one (through O) has the other on its closed far side. Signs are those of the exact
// triple products: a value counts only beyond the rounding bound of TrianglePlanes, and a vertex
// the two triangles share lies on the plane exactly. Triangles whose orientation det(a, b, c)
// is within rounding of zero (plane through O) are never separated.
class ConeSeparation {
 public:
  // `planes` from triangle_planes of each triangle of `mesh` relative to `centre`; referenced.
  ConeSeparation(const geometry::TriMesh& mesh, const Eigen::Vector3d& centre,
                 std::span<const RadialSpans::TrianglePlanes> planes);
  bool separated(std::int32_t t, std::int32_t u) const;

 private:
  bool edge_plane_separates(std::int32_t t, std::int32_t u) const;
  const geometry::TriMesh* mesh_;
  std::span<const RadialSpans::TrianglePlanes> planes_;
  std::vector<Eigen::Vector3d> relative_;  // vertices - centre
  std::vector<double> scale_;              // |relative|_inf per vertex
  std::vector<int> orientation_;           // certified sign of det(a, b, c) per triangle, or 0
};

// Which side of the span a crossing rule needs (see SPAN above).
enum class SpanCull { kBelowLo, kAboveHi };

// Is a direction d (from O, |d| = r) outside the cap?
inline bool outside_cap(const RadialSpans& spans, const Eigen::Vector3d& d, double r) {
  return d.dot(spans.cap_axis) < r * (spans.cap_cos - 1e-12);
}

// Is a vertex at distance r culled by the span [lo, hi] under the rule's side?
inline bool outside_span(SpanCull side, double r, double lo, double hi) {
  return side == SpanCull::kBelowLo ? r < lo * (1.0 - 1e-12) : r > hi * (1.0 + 1e-12);
}

}  // namespace hipfai::contact
