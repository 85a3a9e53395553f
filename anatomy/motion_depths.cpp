// hipfai — bone-to-bone penetration depths over a motion (see motion_depths.h).
#include "anatomy/motion_depths.h"

#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "contact/radial_segmenting.h"
#include "contact/radial_table.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "geometry/hip_measure.h"

#include <algorithm>
#include <optional>

namespace hipfai::anatomy {

namespace {

using geometry::TriMesh;
using geometry::Vec3;

// Axes closer than this (unit vectors) share one cylindrical table.
constexpr double kSameAxis = 1e-9;

Eigen::Isometry3d rotation_about(const Vec3& centre, const Eigen::Matrix3d& rotation) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = centre - rotation * centre;
  return pose;
}

// The result's pairs deeper than the tolerance: counted, and the deepest kept in `deepest` when
// it beats it. `rotation` poses the mobile body (femur: R; pelvis: R^T).
struct DepthRecorder {
  const MotionDepthsRequest* request = nullptr;
  Eigen::Matrix3d femur_rotation = Eigen::Matrix3d::Identity();  // the step's R

  // `reach` > 0: only vertices within it of the HJC count (distances to the HJC do not change
  // with the rotation about it).
  void record(const contact::PenetrationResult& result, DepthBody body, double& max_depth,
              DeepestVertex& deepest, int& count, double reach = 0.0) const {
    if (result.status == contact::QueryStatus::kInvalidInput) throw_error("motion depths: ", result.message);
    const Vec3& c = request->hjc_mm;
    for (const auto& pair : result.pairs) {
      if (!(pair.depth_mm > request->contact_tolerance_mm)) continue;
      if (reach > 0.0) {
        const TriMesh& mesh = body == DepthBody::kFemur ? *request->femur : *request->pelvis;
        if ((mesh.vertices[static_cast<std::size_t>(pair.mobile_vertex)] - c).norm() > reach) continue;
      }
      ++count;
      if (pair.depth_mm <= max_depth) continue;
      max_depth = pair.depth_mm;
      deepest.body = body;
      deepest.vertex = pair.mobile_vertex;
      deepest.triangle = pair.fixed_triangle;
      deepest.depth_mm = pair.depth_mm;
      const auto v = static_cast<std::size_t>(pair.mobile_vertex);
      Vec3 at_neutral;
      if (body == DepthBody::kFemur) {
        at_neutral = request->femur->vertices[v];
        deepest.point_mm = c + femur_rotation * (at_neutral - c);
      } else {
        deepest.point_mm = request->pelvis->vertices[v];
        at_neutral = c + femur_rotation.transpose() * (deepest.point_mm - c);
      }
      deepest.acetabular_clock.angle_deg = clock_angle_deg(request->acetabulum, deepest.point_mm);
      deepest.acetabular_clock.label = geometry::clock_label(deepest.acetabular_clock.angle_deg);
      deepest.femoral_clock.angle_deg = clock_angle_deg(request->femoral_head, at_neutral);
      deepest.femoral_clock.label = geometry::clock_label(deepest.femoral_clock.angle_deg);
    }
  }
};

// Generalised winding number of a closed surface about `p` (1 inside, 0 outside): the solid
// angles of its triangles (Van Oosterom & Strackee's formula) over 4 pi.
double winding_number(const TriMesh& mesh, const Vec3& p) {
  double total = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[static_cast<std::size_t>(t[0])] - p;
    const Vec3 b = mesh.vertices[static_cast<std::size_t>(t[1])] - p;
    const Vec3 c = mesh.vertices[static_cast<std::size_t>(t[2])] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2.0 * std::atan2(numerator, denominator);
  }
  return total / (4.0 * std::numbers::pi);
}

void check_request(const MotionDepthsRequest& request) {
  if (!request.pelvis || !request.femur) throw_error("motion depths: the pelvis and the femur are required");
  geometry::validate_mesh(*request.pelvis, "motion depths: pelvis");
  geometry::validate_mesh(*request.femur, "motion depths: femur");
  if (!request.hjc_mm.allFinite()) throw_error("motion depths: the HJC is not finite");
  check_hip_axes(request.hip_axes, "motion depths: hip axes");
  check_clock_face(request.acetabulum, "motion depths: acetabular clock");
  check_clock_face(request.femoral_head, "motion depths: femoral clock");
  if (!(request.contact_tolerance_mm >= 0.0)) throw_error("motion depths: contact_tolerance_mm must be >= 0");
  if (!(request.radial_reach_mm >= 0.0)) throw_error("motion depths: radial_reach_mm must be >= 0");
  for (std::size_t k = 0; k < request.poses.size(); ++k) {
    const auto& p = request.poses[k];
    if (!std::isfinite(p.flexion_deg) || !std::isfinite(p.adduction_deg) || !std::isfinite(p.internal_rotation_deg)) {
      throw_error("motion depths: pose ", k, " has a non-finite angle");
    }
  }
}

// A radial table of about one cell per triangle (radial_table.h: a cell about a triangle's size).
contact::RadialTable radial_table(const TriMesh& mesh, const Vec3& centre) {
  contact::RadialTableOptions options;
  options.table_size = std::max<std::int64_t>(4096, static_cast<std::int64_t>(mesh.num_triangles()));
  return contact::build_radial_table(mesh, centre, options);
}

}  // namespace

double MotionDepths::max_curvilinear_mm() const {
  double deepest = 0.0;
  for (const auto& s : steps) deepest = std::max(deepest, s.max_curvilinear_mm);
  return deepest;
}

double MotionDepths::max_radial_mm() const {
  double deepest = 0.0;
  for (const auto& s : steps) deepest = std::max(deepest, s.max_radial_mm);
  return deepest;
}

MotionDepths bone_depths_over_motion(const MotionDepthsRequest& request) {
  const auto start_time = SteadyClock::now();
  check_request(request);
  const TriMesh& femur = *request.femur;
  const TriMesh& pelvis = *request.pelvis;
  const Vec3& c = request.hjc_mm;
  const Eigen::Matrix3d& A = request.hip_axes;
  MotionDepths out;
  out.steps.resize(request.poses.size());
  if (request.poses.empty()) return out;

  // Radial: each body prepared once for the whole motion.
  contact::RadialQueryOptions inside;
  inside.configuration = contact::RadialConfiguration::kMobileInsideFixed;
  inside.rule = contact::RadialCrossingRule::kUnion;
  inside.num_threads = request.num_threads == 1 ? 1 : 2;
  contact::RadialQueryOptions outside = inside;
  outside.configuration = contact::RadialConfiguration::kFixedInsideMobile;
  const contact::RadialTable pelvis_table = radial_table(pelvis, c);
  const contact::RadialPoseQuery femur_in_pelvis(pelvis_table, pelvis, femur, inside);
  if (femur_in_pelvis.status() == contact::QueryStatus::kInvalidInput) {
    throw_error("motion depths: ", femur_in_pelvis.message());
  }
  std::optional<contact::RadialTable> femur_table;
  std::optional<contact::RadialPoseQuery> pelvis_in_femur;
  // The radial depth runs along the ray towards the HJC; a femur that holds the HJC (a whole
  // femoral head rather than its cartilage shell) has no boundary that way, and a pelvis vertex
  // inside it would be measured to the femur's far side (the length of bone along the ray). So the
  // pelvis-in-femur role is left out then; the curvilinear depth keeps both roles.
  out.radial_swap_skipped = request.swap_roles && winding_number(femur, c) > 0.5;
  if (request.swap_roles && !out.radial_swap_skipped) {
    femur_table.emplace(radial_table(femur, c));
    pelvis_in_femur.emplace(*femur_table, femur, pelvis, outside);
    if (pelvis_in_femur->status() == contact::QueryStatus::kInvalidInput) {
      throw_error("motion depths: ", pelvis_in_femur->message());
    }
  }

  contact::CylindricalQueryOptions query;
  query.num_threads = request.num_threads;
  std::optional<Vec3> table_axis;
  contact::CylindricalTable pelvis_cylinder, femur_cylinder;

  for (std::size_t k = 0; k < request.poses.size(); ++k) {
    StepDepths& s = out.steps[k];
    s.pose = request.poses[k];
    const Eigen::Matrix3d R = A * geometry::femur_rotation(s.pose) * A.transpose();
    const Eigen::AngleAxisd axis_angle(R);
    s.angle_deg = axis_angle.angle() * geometry::kRadToDeg;
    s.axis = s.angle_deg > 0.0 ? Vec3(axis_angle.axis().normalized()) : Vec3(A.col(0));
    DepthRecorder recorder{&request, R};

    // Curvilinear, about the step's own axis.
    if (!table_axis || (*table_axis - s.axis).norm() >= kSameAxis) {
      table_axis = s.axis;
      pelvis_cylinder = contact::CylindricalTable::build(pelvis, c, s.axis, {}, &femur);
      if (pelvis_cylinder.status() == contact::QueryStatus::kInvalidInput) {
        throw_error("motion depths: ", pelvis_cylinder.message());
      }
      if (request.swap_roles) {
        femur_cylinder = contact::CylindricalTable::build(femur, c, s.axis, {}, &pelvis);
        if (femur_cylinder.status() == contact::QueryStatus::kInvalidInput) {
          throw_error("motion depths: ", femur_cylinder.message());
        }
      }
    }
    const Eigen::Matrix3d Rs = Eigen::AngleAxisd(s.angle_deg * geometry::kDegToRad, s.axis).toRotationMatrix();
    recorder.record(contact::cylindrical_segmenting(pelvis_cylinder, femur, rotation_about(c, Rs), query),
                    DepthBody::kFemur, s.max_curvilinear_mm, s.curvilinear_deepest, s.curvilinear_vertices);
    if (request.swap_roles) {
      recorder.record(
          contact::cylindrical_segmenting(femur_cylinder, pelvis, rotation_about(c, Rs.transpose()), query),
          DepthBody::kPelvis, s.max_curvilinear_mm, s.curvilinear_deepest, s.curvilinear_vertices);
    }

    // Radial, about the HJC.
    recorder.record(femur_in_pelvis.query_rotation(R), DepthBody::kFemur, s.max_radial_mm, s.radial_deepest,
                    s.radial_vertices, request.radial_reach_mm);
    if (pelvis_in_femur) {
      recorder.record(pelvis_in_femur->query_rotation(R.transpose()), DepthBody::kPelvis, s.max_radial_mm,
                      s.radial_deepest, s.radial_vertices, request.radial_reach_mm);
    }
  }
  out.milliseconds = 1e3 * seconds_since(start_time);
  return out;
}

}  // namespace hipfai::anatomy
