// hipfai — segment-based mortar integration between two non-matching boundary meshes.
//
// The mortar contact constraint of a slave node s couples it to master nodes j through
// M_sj = integral over the slave surface of phi_s(x) N_j(x_m(x)), where x_m(x) is the master
// point opposite x. N_j(x_m(x)) has kinks wherever x_m(x) crosses a master face edge, so a
// quadrature over the slave face alone integrates it only approximately (~1e-3 on coarse
// non-matching layers). Segment-based integration (Puso & Laursen 2004; Popp et al. 2010) cuts
// each slave face into the pieces that see one master face each, and integrates each piece with
// a Gauss rule exact for the polynomial integrand: M is then exact for flat faces, and a
// uniform pressure passes the interface exactly (the patch test).
//
// Here the pieces are found in the slave face's parameter square: the master face's boundary
// is projected onto the slave patch (closest point, i.e. along the slave normal), clipped
// against [0,1]^2 (Sutherland-Hodgman), fanned into triangles, and each triangle integrated
// with a collapsed (Duffy) tensor Gauss rule. At each point the master point is where the slave
// normal line meets the master face, consistent with the projection that made the polygon.
// Curved faces: master faces are cut into sub-squares whose edges are sampled at several
// points, so the polygons follow the curved edges to second order and no master point is
// projected far outside the slave face (where the patch's polynomial extension is unreliable).
#pragma once

#include "fem/face_patch.h"

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <array>
#include <vector>

namespace hipfai::fem {

struct MortarPoint {
  dealii::Point<3> slave_unit_point;  // in the slave cell's reference cell
  dealii::Point<3> slave_point_mm;
  double jxw = 0.0;                   // slave surface measure (signed weights sum to areas)
  const FacePatch* master = nullptr;
  dealii::Point<3> master_unit_point;  // in the master cell's reference cell
  dealii::Point<3> master_point_mm;
  dealii::Tensor<1, 3> master_normal;  // out of the master body
};

struct MortarSegmentOptions {
  double search_radius_mm = 0.0;  // master faces farther than this from the slave face are ignored
  unsigned int gauss_points = 5;  // per direction of the collapsed rule: exact to degree 8 on flat Q2 faces
  unsigned int curved_edge_samples = 2;  // polygon vertices per curved master sub-square edge
  unsigned int curved_subdivisions = 3;  // curved master faces are cut into n x n sub-squares
  // Skip a master face whose projection on the slave face's tangent plane lies clear of the
  // slave face's own, by more than the largest tangential offset a point within the search
  // radius can have there (see MortarSegmenter::integrate). Off: every master face whose box
  // meets the slave face's padded box is segmented (the same points, slower).
  bool tangent_plane_cull = true;
};

class MortarSegmenter {
 public:
  MortarSegmenter(const std::vector<FacePatch>& master_faces, MortarSegmentOptions options);

  // Quadrature points of the part of `slave` that lies opposite some master face.
  std::vector<MortarPoint> integrate(const FacePatch& slave) const;

 private:
  const std::vector<FacePatch>& master_faces_;
  // The points of `slave` opposite `master` (straight: both faces bilinear), added to `points`.
  void segment(const FacePatch& slave, const FacePatch& master, bool straight,
               std::vector<MortarPoint>& points) const;
  // Gauss points of a polygon of the slave face's parameters (its vertices' orientation given).
  void integrate_polygon(const FacePatch& slave, const FacePatch& master,
                         const std::vector<std::array<double, 2>>& polygon, double orientation,
                         std::vector<MortarPoint>& points) const;

  std::vector<bool> master_straight_;  // bilinear faces: edges are straight lines
  MortarSegmentOptions options_;
  std::vector<double> gauss_x_, gauss_w_;  // on [0,1]
};

// True when the patch is the bilinear map of its four corners (to round-off of its size).
bool is_bilinear(const FacePatch& face);

}  // namespace hipfai::fem
