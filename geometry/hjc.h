// hipfai — hip joint centre (HJC) estimation, the five methods of thesis §4.4.2.2 (after
// Gilles 2007), in one request/result pair (FCL style):
//
//   femoralheadsphere  centre of the least-squares sphere of the femoral head (geometric fit)
//   acetabulumsphere   centre of the least-squares sphere of the lunate surface
//   doublesphere       one centre, two radii, fitted to the head and the lunate surface together
//   dconst             functional: simulated circumduction, inter-articular distances restored to
//                      r_acetabulum - r_head at every lunate vertex (geometry/hjc_functional.h)
//   dref               functional: distances restored to those of the scanned pose
//
// Regions (geometry/hjc_regions.h) are found on the bones unless given; HjcResult says which. All
// centres are in the coordinates of the input meshes (mm). Bad input — an empty mesh, no femoral
// head, no lunate surface, a flat region — throws hipfai::Error with one line naming it.
#pragma once

#include "geometry/hjc_functional.h"
#include "geometry/hjc_regions.h"
#include "geometry/sphere_fit.h"
#include "geometry/tri_mesh.h"

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace hipfai::geometry {

// The five method names, in the thesis' order of Fig. 67's legend reversed to predictive first.
const std::vector<std::string>& hjc_method_names();

struct HjcRequest {
  const TriMesh* femur = nullptr;            // required: femur (bone or articular surface)
  const TriMesh* pelvis = nullptr;           // required: pelvis / acetabulum
  std::optional<SurfaceRegion> head_region;    // given femoral head; empty = automatic
  std::optional<SurfaceRegion> lunate_region;  // given lunate surface; empty = automatic
  std::vector<std::string> methods;          // subset of hjc_method_names(); empty = all five
  // Direction the circumduction cone is built around; empty = the femur's principal axis (the
  // shaft of a whole femur).
  std::optional<Vec3> femur_long_axis;
  HeadRegionOptions head_options;
  LunateRegionOptions lunate_options;
  FunctionalHjcOptions functional;
  std::string femur_name = "femur", pelvis_name = "pelvis";  // for error messages
};

struct HjcMethodResult {
  std::string name;
  bool ok = false;
  std::string message;
  Vec3 center_mm = Vec3::Zero();
  // Sphere methods: the fitted radius (doublesphere: the head's; radius_b_mm the acetabulum's).
  double radius_mm = std::numeric_limits<double>::quiet_NaN();
  double radius_b_mm = std::numeric_limits<double>::quiet_NaN();
  double rms_mm = 0.0;     // sphere methods: fit residual; functional: distance residual
  double max_mm = 0.0;
  // Functional methods: displacement of the centre over the circumduction (NaN otherwise).
  double residual_motion_rms_mm = std::numeric_limits<double>::quiet_NaN();
  double residual_motion_max_mm = std::numeric_limits<double>::quiet_NaN();
  double target_distance_mm = std::numeric_limits<double>::quiet_NaN();  // dconst's constant distance
  int poses = 0;
};

struct HjcResult {
  std::string head_source, lunate_source;
  std::size_t head_vertices = 0, lunate_vertices = 0;
  SurfaceRegion head, lunate;
  std::vector<HjcMethodResult> methods;   // in the order requested

  // The result of `name`; throws hipfai::Error when it was not computed.
  const HjcMethodResult& method(const std::string& name) const;
};

HjcResult estimate_hjc(const HjcRequest& request);

// {"methods": {name: {"center_mm": [x,y,z], "radius_mm": r, "rms_mm": e, ...}}, "regions": ...}
std::string hjc_result_json(const HjcResult& result, int indent = 2);

}  // namespace hipfai::geometry
