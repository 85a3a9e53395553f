// hipfai — the acetabulum of a RIGHT hip found on the pelvis: its lunate sphere, rim, opening axis
// and orientation (Murray 1993), and the clock face the impingement zones are read on.
//
// Method. The lunate (articular) surface is found around the femoral head (geometry/hjc_regions.h)
// and a sphere fitted to it: the acetabular centre c and radius Ra. The rim is where the bone
// around that sphere ends: about a trial axis a (first the direction away from the lunate surface's
// mean direction), the pelvis vertices within `rim_reach` x Ra of c are binned by their clock angle
// about a; in each bin the vertex with the smallest polar angle from a (the nearest to the opening)
// is the rim there. A plane is fitted to the rim points, the bins far off it (the acetabular notch,
// where the rim is missing, and the ligament's fossa) dropped by a robust residual test, the plane
// refitted; its normal, pointing out of the socket, is the next axis. Three rounds. The acetabular
// axis is that plane's normal (Murray 1993: "the acetabular axis ... perpendicular to the face of
// the acetabulum").
//
// Clock face (both sides in the right-hip convention): clock angle 0 = anterior = 3 o'clock,
// 90 = superior = 12 o'clock, about the acetabular axis, from the pelvis frame's anterior and
// superior projected on the rim plane (anatomy/side.h).
#pragma once

#include "anatomy/anatomical_frame.h"
#include "geometry/tri_mesh.h"

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace hipfai::anatomy {

struct AcetabulumRequest {
  const geometry::TriMesh* pelvis = nullptr;  // required, in the same coordinates as the rest
  geometry::Vec3 head_centre_mm = geometry::Vec3::Zero();  // the femoral head's fitted sphere
  double head_radius_mm = 0.0;
  // The pelvis frame of a RIGHT hip (right = lateral), for the clock face and Murray's angles.
  AnatomicalFrame pelvis_frame;
  double rim_reach = 1.45;   // rim candidates within this x Ra of the centre (the lip, not the wing)
  int clock_bins = 72;       // rim samples around the axis (5 deg)
  std::string what = "pelvis";
};

struct RimPoint {
  double clock_deg = 0.0;        // about the acetabular axis (0 = anterior, 90 = superior)
  double polar_deg = 0.0;        // angle of the rim point from the acetabular axis, at the centre
  geometry::Vec3 point_mm = geometry::Vec3::Zero();
  bool in_plane_fit = false;     // kept by the robust plane fit (false: notch or outlier)
};

struct Acetabulum {
  geometry::Vec3 centre_mm = geometry::Vec3::Zero();  // lunate sphere centre
  double radius_mm = 0.0;                              // lunate sphere radius
  double lunate_rms_mm = 0.0;
  geometry::Vec3 axis = geometry::Vec3::UnitX();       // unit, out of the socket
  geometry::Vec3 clock_anterior = geometry::Vec3::UnitY();  // clock 0, unit, perpendicular to axis
  geometry::Vec3 clock_superior = geometry::Vec3::UnitZ();  // clock 90 = axis x clock_anterior
  std::vector<RimPoint> rim;                           // one per clock bin that has bone, by clock angle
  double rim_plane_rms_mm = 0.0;                       // residual of the plane fit (kept points)
  // Murray (1993), degrees, in the pelvis frame.
  double radiographic_inclination_deg = 0.0;
  double radiographic_anteversion_deg = 0.0;
  double anatomic_inclination_deg = 0.0;
  double anatomic_anteversion_deg = 0.0;

  // Clock angle (deg, (-180, 180]) of a point about the axis through the centre.
  double clock_of(const geometry::Vec3& point_mm) const;
  // (clock_deg, polar_deg) of the rim, for the rim trimming's profile.
  std::vector<std::pair<double, double>> rim_profile() const;
};

// Throws hipfai::Error "<what>: ..." when no lunate surface or too little rim is found.
Acetabulum find_acetabulum(const AcetabulumRequest& request);

// Murray's four angles of an axis given in the frame's (lateral, anterior, superior) coordinates
// of a right hip: {radiographic inclination, radiographic anteversion, anatomic inclination,
// anatomic anteversion}, degrees.
std::array<double, 4> murray_angles(const geometry::Vec3& axis_in_frame);

}  // namespace hipfai::anatomy
