// hipfai — what a caller asks of contact/penetrate.h: which depths, of which body pair, at which
// poses, with which tolerances. One request, one result (penetration_result.h), one entry point
// (penetrate.h); which method answers (a cylindrical table, a pose cache, a radial table, a radial
// pose query) is chosen behind the entry point and never changes an answer.
//
// The fixed mesh F stays put; the mobile mesh M is given at rest and moved by each step's rotation
// about the centre. A role swap (thesis §3.3.1, §4.3: "repeated by exchanging the role") is a
// second request with the meshes exchanged, each step's rotation inverted and the radial
// configuration swapped (radial_segmenting.h: swapped()).
#pragma once

#include "contact/arc_triangle.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_table.h"
#include "geometry/tri_mesh.h"

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::contact {

// One pose of the mobile mesh: a rotation about the request's centre, given twice because the two
// depths read it differently and each must see the caller's own numbers bit for bit.
struct PenetrationStep {
  // The rotation in F's frame: radial depth poses each mobile vertex v as centre + rotation (v - centre).
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  // The same rotation as a unit axis through the centre and an angle about it (right-hand rule),
  // degrees. Curvilinear depth is measured along each vertex's circle about this axis. Steps whose
  // axes are equal component by component share one pre-processing of M: give every step of a
  // motion about one axis the same axis vector.
  Vec3 axis = Vec3::UnitX();
  double angle_deg = 0.0;
};

struct PenetrationRequest {
  // F: closed and consistently outward-oriented (cylindrical_segmenting.h, radial_segmenting.h
  // state what an open mesh gives). Referenced, not copied: it must outlive the call.
  const geometry::TriMesh* fixed = nullptr;
  // M at rest (pose 0), in F's frame. Referenced, not copied.
  const geometry::TriMesh* mobile = nullptr;
  // Centre of rotation (the HJC), mm, in F's frame: the rotation of every step is about it, and
  // radial rays start from it.
  Vec3 centre = Vec3::Zero();

  // Curvilinear depth (cylindrical segmenting, thesis §3.2): per step, the mobile vertices inside F
  // with the arc r * |delta| that turns each back onto F's surface about the step's axis.
  bool curvilinear = false;
  // Radial depth (radial segmenting, thesis §3.3): per step, the mobile vertices the crossing rule
  // (radial_rule) finds penetrating along the ray from the centre, with their radial depth.
  bool radial = false;

  // The poses, in order; one step asks about one pose. Empty: nothing is computed.
  std::vector<PenetrationStep> steps;

  // Curvilinear: a vertex within this arc distance (mm) of F's surface only touches and is not
  // reported. Radial depths have no tolerance here: filter the pairs by depth_mm.
  double touching_mm = kDefaultTouchingMm;
  // Radial: which mesh is inside the other, and which crossing decides (radial_segmenting.h).
  RadialConfiguration radial_configuration = RadialConfiguration::kMobileInsideFixed;
  RadialCrossingRule radial_rule = RadialCrossingRule::kAdjacent;
  // Radial: the mapping and size of F's table about the centre (radial_table.h).
  RadialTableOptions radial_table;

  // Threads of the per-pose queries and of the pre-processing (0: all hardware threads; the radial
  // queries use 1 or 2). The answers do not depend on it.
  int num_threads = 1;

  // Pre-processing kept on disk: when not empty, the tables a request builds are saved in this
  // folder (made when missing) and loaded, instead of built, by later requests with the same
  // inputs. Loaded tables answer bit for bit as built ones.
  std::filesystem::path cache_dir;
  // Content hashes of F and M (e.g. geometry::mesh_hash or the hash of their files): with the
  // centre, the axis and the radial table options they name the cached files. Required with
  // cache_dir; a cached file is only as right as these keys.
  std::string fixed_key;
  std::string mobile_key;
};

}  // namespace hipfai::contact
