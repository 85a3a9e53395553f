// hipfai — FCL (Pan, Chitta & Manocha 2012), the bounding-volume-hierarchy peer of the benchmark.
//
// What a user would pick: a BVHModel per mesh (OBBRSS or OBB bounding volumes), the mobile mesh
// placed by a rigid transform, fcl::collide with num_max_contacts raised from its default of 1 to
// "all" so that every intersecting triangle pair is returned. FCL reports triangle PAIRS that
// intersect (and, with enable_contact, a contact point, normal and a per-pair depth); it does not
// report mobile vertices inside the fixed solid, so it is compared with the thesis' methods by the
// set of penetrating vertices it implies (the vertices of the mobile triangles it reports) and by
// time, never by depth. FCL's types stay inside peer_fcl.cpp.
#pragma once

#include "geometry/tri_mesh.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace hipfai::bench {

enum class FclBoundingVolume { kObbRss, kObb };

const char* to_string(FclBoundingVolume bv);

struct FclCollideOptions {
  bool all_contacts = true;     // num_max_contacts = all (false: FCL's default of 1, boolean test)
  bool enable_contact = true;   // compute contact point / normal / depth per pair
};

struct FclCollideResult {
  bool collides = false;
  // (fixed triangle, mobile triangle) for each contact FCL returned.
  std::vector<std::pair<std::int32_t, std::int32_t>> triangle_pairs;
};

// A mesh's BVH (the pre-processing of this peer). Move-only.
class FclModel {
 public:
  FclModel();
  FclModel(const geometry::TriMesh& mesh, FclBoundingVolume bv);
  ~FclModel();
  FclModel(FclModel&&) noexcept;
  FclModel& operator=(FclModel&&) noexcept;

  // `this` is the fixed mesh (identity pose); `mobile` is placed by X_FM (pose of the mobile mesh's
  // own frame in the fixed frame).
  FclCollideResult collide(const FclModel& mobile, const Eigen::Isometry3d& X_FM,
                           const FclCollideOptions& options = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Mobile vertices of every mobile triangle FCL reported (sorted, unique).
std::vector<std::int32_t> implied_mobile_vertices(const geometry::TriMesh& mobile,
                                                  const FclCollideResult& result);

// The rigid transform of a rotation by angle_rad about the unit `axis` through `centre`, followed
// by a translation.
Eigen::Isometry3d rotation_about(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis_unit,
                                 double angle_rad,
                                 const Eigen::Vector3d& translation_mm = Eigen::Vector3d::Zero());

}  // namespace hipfai::bench
