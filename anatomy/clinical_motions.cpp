// hipfai — the clinical motions of a hip to bony impingement (see clinical_motions.h).
#include "anatomy/clinical_motions.h"

#include "core/error.h"
#include "core/stopwatch.h"
#include "geometry/hip_frame.h"
#include "geometry/hip_measure.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hipfai::anatomy {

namespace {

using geometry::TriMesh;
using geometry::Vec3;

constexpr double kAxisTolerance = 1e-6;  // unit length and orthogonality of given axes

// The femur rotated by `rotation` about `centre`.
TriMesh posed(const TriMesh& femur, const Eigen::Matrix3d& rotation, const Vec3& centre) {
  TriMesh out = femur;
  for (auto& v : out.vertices) v = centre + rotation * (v - centre);
  return out;
}

// A JCS pose (geometry/hip_frame.h) as a rotation in mesh coordinates.
Eigen::Matrix3d pose_rotation(const Eigen::Matrix3d& axes, double flexion_deg, double adduction_deg) {
  geometry::HipPoseDeg pose;
  pose.flexion_deg = flexion_deg;
  pose.adduction_deg = adduction_deg;
  return axes * geometry::femur_rotation(pose) * axes.transpose();
}

Eigen::Matrix3d turn(const Vec3& axis, double angle_deg) {
  return Eigen::AngleAxisd(angle_deg * geometry::kDegToRad, axis).toRotationMatrix();
}

// Midpoint of the shortest segment between segments [p0, p1] and [q0, q1].
Vec3 segments_meeting_point(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 0.0 && e <= 0.0) return 0.5 * (p0 + q0);
  if (a <= 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denominator = a * e - b * b;
      s = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return 0.5 * ((p0 + s * d1) + (q0 + t * d2));
}

ClockPosition clock_position(const ClockFace& face, const Vec3& point) {
  ClockPosition position;
  position.angle_deg = clock_angle_deg(face, point);
  position.label = geometry::clock_label(position.angle_deg);
  return position;
}

// Runs the range finder for the motions of one request.
class MotionRunner {
 public:
  explicit MotionRunner(const ClinicalRomRequest& request) : request_(request) {
    options_.query.num_threads = request.num_threads;
  }

  const Eigen::Matrix3d& axes() const { return request_.hip_axes; }

  // Both directions about `axis` of the femur posed by `start`.
  contact::RangeOfMotion range(const TriMesh& posed_femur, const Vec3& axis) const {
    contact::RangeOfMotion range =
        contact::range_of_motion(*request_.pelvis, posed_femur, request_.hjc_mm, axis, options_);
    if (range.status == contact::QueryStatus::kInvalidInput) throw_error("clinical motions: ", range.message);
    return range;
  }

  // One direction of a range as a MotionLimit, with its contact point and clocks.
  MotionLimit limit(const std::string& name, const TriMesh& posed_femur, const Eigen::Matrix3d& start,
                    const Vec3& axis, const contact::RangeOfMotion& range, bool anticlockwise) const {
    MotionLimit m;
    m.name = name;
    m.axis = axis.normalized();
    m.sign = anticlockwise ? 1.0 : -1.0;
    m.angle_deg = anticlockwise ? range.anticlockwise_deg : range.clockwise_deg;
    m.contact = anticlockwise ? range.anticlockwise_limit : range.clockwise_limit;
    m.start_rotation = start;
    m.unlimited = m.contact.kind == contact::ContactKind::kNone;
    if (m.unlimited) return m;
    const Vec3& c = request_.hjc_mm;
    const Eigen::Matrix3d motion = turn(m.axis, m.sign * m.angle_deg);
    auto moved = [&](std::int32_t v) {
      return Vec3(c + motion * (posed_femur.vertices[static_cast<std::size_t>(v)] - c));
    };
    const auto& pelvis = request_.pelvis->vertices;
    switch (m.contact.kind) {
      case contact::ContactKind::kMobileVertexOnFixedTriangle:
        m.contact_point_mm = moved(m.contact.vertex);
        break;
      case contact::ContactKind::kFixedVertexOnMobileTriangle:
        m.contact_point_mm = pelvis[static_cast<std::size_t>(m.contact.vertex)];
        break;
      case contact::ContactKind::kEdgeOnEdge:
        m.contact_point_mm = segments_meeting_point(
            moved(m.contact.mobile_edge[0]), moved(m.contact.mobile_edge[1]),
            pelvis[static_cast<std::size_t>(m.contact.fixed_edge[0])],
            pelvis[static_cast<std::size_t>(m.contact.fixed_edge[1])]);
        break;
      case contact::ContactKind::kNone: break;
    }
    const Eigen::Matrix3d total = motion * start;
    const Vec3 at_neutral = c + total.transpose() * (m.contact_point_mm - c);
    m.acetabular_clock = clock_position(request_.acetabulum, m.contact_point_mm);
    m.femoral_clock = clock_position(request_.femoral_head, at_neutral);
    return m;
  }

 private:
  const ClinicalRomRequest& request_;
  contact::RangeOfMotionOptions options_;
};

MotionOutcome reached(MotionLimit limit) {
  MotionOutcome outcome;
  outcome.limit = std::move(limit);
  return outcome;
}

MotionOutcome unreachable(const std::string& reason) {
  MotionOutcome outcome;
  outcome.reason = reason;
  return outcome;
}

std::string stop_reason(const std::string& motion, double reached_deg, double needed_deg) {
  char buffer[160];
  std::snprintf(buffer, sizeof(buffer), "%s stops at %.1f deg, before %g", motion.c_str(), reached_deg,
                needed_deg);
  return buffer;
}

void check_request(const ClinicalRomRequest& request) {
  if (!request.pelvis || !request.femur) throw_error("clinical motions: the pelvis and the femur are required");
  geometry::validate_mesh(*request.pelvis, "clinical motions: pelvis");
  geometry::validate_mesh(*request.femur, "clinical motions: femur");
  if (!request.hjc_mm.allFinite()) throw_error("clinical motions: the HJC is not finite");
  check_hip_axes(request.hip_axes, "clinical motions: hip axes");
  check_clock_face(request.acetabulum, "clinical motions: acetabular clock");
  check_clock_face(request.femoral_head, "clinical motions: femoral clock");
  const double angles[] = {request.fadir_adduction_deg, request.faber_flexion_deg, request.faber_abduction_deg};
  for (double a : angles) {
    if (!(a >= 0.0 && a < 180.0)) throw_error("clinical motions: start pose angle ", a, " deg is not in [0, 180)");
  }
  if (!(request.touching_mm >= 0.0)) throw_error("clinical motions: touching_mm must be >= 0");
}

void refuse_neutral_overlap(const ClinicalRomRequest& request) {
  contact::StartPoseOptions options;
  options.touching_mm = request.touching_mm;
  options.centre = request.hjc_mm;
  options.num_threads = request.num_threads == 1 ? 1 : 2;
  const contact::StartPoseOverlap overlap = contact::check_start_pose(*request.pelvis, *request.femur, options);
  if (overlap.status == contact::QueryStatus::kInvalidInput) throw_error("clinical motions: ", overlap.message);
  if (overlap.overlaps()) {
    throw_error("the bones intersect in the neutral pose: ", overlap.summary(),
                " (femur mobile, pelvis fixed); no range of motion starts from an intersecting pose");
  }
}

}  // namespace

ClockFace make_clock_face(const Vec3& centre, const Vec3& axis, const Vec3& towards, bool towards_is_anterior) {
  ClockFace face;
  face.centre_mm = centre;
  face.axis = axis.normalized();
  const Vec3 perpendicular = (towards - towards.dot(face.axis) * face.axis).normalized();
  if (towards_is_anterior) {
    face.anterior = perpendicular;
    face.superior = face.axis.cross(face.anterior);
  } else {
    face.superior = perpendicular;
    face.anterior = face.superior.cross(face.axis);
  }
  return face;
}

double clock_angle_deg(const ClockFace& face, const Vec3& point) {
  const Vec3 d = point - face.centre_mm;
  return std::atan2(d.dot(face.superior), d.dot(face.anterior)) * geometry::kRadToDeg;
}

void check_hip_axes(const Eigen::Matrix3d& axes, const std::string& what) {
  if (!axes.allFinite() || (axes.transpose() * axes - Eigen::Matrix3d::Identity()).norm() > kAxisTolerance ||
      std::abs(axes.determinant() - 1.0) > kAxisTolerance) {
    throw_error(what, ": the columns (lateral, anterior, superior) are not a right-handed orthonormal frame");
  }
}

void check_clock_face(const ClockFace& face, const std::string& what) {
  const bool unit = std::abs(face.axis.norm() - 1.0) <= kAxisTolerance &&
                    std::abs(face.anterior.norm() - 1.0) <= kAxisTolerance &&
                    std::abs(face.superior.norm() - 1.0) <= kAxisTolerance;
  const bool orthogonal = std::abs(face.axis.dot(face.anterior)) <= kAxisTolerance &&
                          std::abs(face.axis.dot(face.superior)) <= kAxisTolerance &&
                          std::abs(face.anterior.dot(face.superior)) <= kAxisTolerance;
  if (!face.centre_mm.allFinite() || !unit || !orthogonal) {
    throw_error(what, ": axis, anterior and superior must be unit and mutually perpendicular");
  }
}

std::vector<const MotionOutcome*> ClinicalRom::motions() const {
  return {&flexion, &extension, &abduction, &adduction, &internal_rotation, &external_rotation,
          &internal_rotation_at_90_flexion, &external_rotation_at_90_flexion, &fadir_internal_rotation, &faber};
}

ClinicalRom clinical_range_of_motion(const ClinicalRomRequest& request) {
  const auto start_time = SteadyClock::now();
  check_request(request);
  refuse_neutral_overlap(request);
  ClinicalRom rom;
  rom.fadir_adduction_deg = request.fadir_adduction_deg;
  rom.faber_flexion_deg = request.faber_flexion_deg;
  rom.faber_abduction_deg = request.faber_abduction_deg;
  const MotionRunner runner(request);
  const Eigen::Matrix3d& A = request.hip_axes;
  const Vec3 lateral = A.col(0), anterior = A.col(1), superior = A.col(2);
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  const TriMesh& femur = *request.femur;
  const Vec3& c = request.hjc_mm;

  // From neutral: three passes, six motions.
  const auto sagittal = runner.range(femur, lateral);
  rom.flexion = reached(runner.limit("flexion", femur, identity, lateral, sagittal, true));
  rom.extension = reached(runner.limit("extension", femur, identity, lateral, sagittal, false));
  const auto frontal = runner.range(femur, anterior);
  rom.adduction = reached(runner.limit("adduction", femur, identity, anterior, frontal, true));
  rom.abduction = reached(runner.limit("abduction", femur, identity, anterior, frontal, false));
  const auto axial = runner.range(femur, superior);
  rom.internal_rotation = reached(runner.limit("internal_rotation", femur, identity, superior, axial, true));
  rom.external_rotation = reached(runner.limit("external_rotation", femur, identity, superior, axial, false));

  // At 90 deg of flexion: rotations, then FADIR from there.
  const double flexed = literature::kImpingementTestFlexionDeg;
  if (sagittal.anticlockwise_deg >= flexed) {
    const Eigen::Matrix3d r90 = pose_rotation(A, flexed, 0.0);
    const TriMesh femur90 = posed(femur, r90, c);
    const Vec3 long_axis = r90 * superior;
    const auto rotation90 = runner.range(femur90, long_axis);
    rom.internal_rotation_at_90_flexion =
        reached(runner.limit("internal_rotation_at_90_flexion", femur90, r90, long_axis, rotation90, true));
    rom.external_rotation_at_90_flexion =
        reached(runner.limit("external_rotation_at_90_flexion", femur90, r90, long_axis, rotation90, false));
    const double adduct = request.fadir_adduction_deg;
    const auto frontal90 = runner.range(femur90, r90 * anterior);
    if (frontal90.anticlockwise_deg >= adduct) {
      const Eigen::Matrix3d r = pose_rotation(A, flexed, adduct);
      const TriMesh femur_fadir = posed(femur, r, c);
      const auto fadir = runner.range(femur_fadir, r * superior);
      rom.fadir_internal_rotation =
          reached(runner.limit("fadir_internal_rotation", femur_fadir, r, r * superior, fadir, true));
    } else {
      rom.fadir_internal_rotation =
          unreachable(stop_reason("adduction at 90 deg flexion", frontal90.anticlockwise_deg, adduct));
    }
  } else {
    const std::string reason = stop_reason("flexion", sagittal.anticlockwise_deg, flexed);
    rom.internal_rotation_at_90_flexion = unreachable(reason);
    rom.external_rotation_at_90_flexion = unreachable(reason);
    rom.fadir_internal_rotation = unreachable(reason);
  }

  // FABER: flexion f, abduction b, then external rotation.
  const double f = request.faber_flexion_deg, b = request.faber_abduction_deg;
  if (sagittal.anticlockwise_deg >= f) {
    const Eigen::Matrix3d rf = pose_rotation(A, f, 0.0);
    const TriMesh femur_f = posed(femur, rf, c);
    const auto frontal_f = runner.range(femur_f, rf * anterior);
    if (frontal_f.clockwise_deg >= b) {
      const Eigen::Matrix3d r = pose_rotation(A, f, -b);
      const TriMesh femur_faber = posed(femur, r, c);
      const auto faber = runner.range(femur_faber, r * superior);
      rom.faber = reached(runner.limit("faber", femur_faber, r, r * superior, faber, false));
    } else {
      char at[64];
      std::snprintf(at, sizeof(at), "abduction at %g deg flexion", f);
      rom.faber = unreachable(stop_reason(at, frontal_f.clockwise_deg, b));
    }
  } else {
    rom.faber = unreachable(stop_reason("flexion", sagittal.anticlockwise_deg, f));
  }
  rom.milliseconds = 1e3 * seconds_since(start_time);
  return rom;
}

namespace {

const char* kind_name(contact::ContactKind kind) {
  switch (kind) {
    case contact::ContactKind::kMobileVertexOnFixedTriangle: return "femur_vertex_on_pelvis_triangle";
    case contact::ContactKind::kFixedVertexOnMobileTriangle: return "pelvis_vertex_on_femur_triangle";
    case contact::ContactKind::kEdgeOnEdge: return "edge_on_edge";
    case contact::ContactKind::kNone: break;
  }
  return "none";
}

nlohmann::json limit_json(const MotionLimit& m) {
  nlohmann::json j;
  j["deg"] = m.angle_deg;
  j["unlimited"] = m.unlimited;
  j["axis"] = {m.axis.x(), m.axis.y(), m.axis.z()};
  j["sign"] = m.sign;
  if (m.unlimited) {
    j["contact"] = nullptr;
    return j;
  }
  nlohmann::json contact;
  contact["kind"] = kind_name(m.contact.kind);
  const bool femur_vertex = m.contact.kind == contact::ContactKind::kMobileVertexOnFixedTriangle;
  if (m.contact.kind == contact::ContactKind::kEdgeOnEdge) {
    contact["femur_edge"] = {m.contact.mobile_edge[0], m.contact.mobile_edge[1]};
    contact["pelvis_edge"] = {m.contact.fixed_edge[0], m.contact.fixed_edge[1]};
  } else {
    contact[femur_vertex ? "femur_vertex" : "pelvis_vertex"] = m.contact.vertex;
    contact[femur_vertex ? "pelvis_triangle" : "femur_triangle"] = m.contact.triangle;
  }
  contact["point_mm"] = {m.contact_point_mm.x(), m.contact_point_mm.y(), m.contact_point_mm.z()};
  contact["acetabular_clock_deg"] = m.acetabular_clock.angle_deg;
  contact["acetabular_clock"] = m.acetabular_clock.label;
  contact["femoral_clock_deg"] = m.femoral_clock.angle_deg;
  contact["femoral_clock"] = m.femoral_clock.label;
  j["contact"] = contact;
  return j;
}

}  // namespace

std::string clinical_rom_json(const ClinicalRom& rom, int indent) {
  nlohmann::json j;
  nlohmann::json reasons = nlohmann::json::object();
  const char* names[] = {"flexion", "extension", "abduction", "adduction", "internal_rotation",
                         "external_rotation", "internal_rotation_at_90_flexion",
                         "external_rotation_at_90_flexion", "fadir_internal_rotation", "faber"};
  const auto motions = rom.motions();
  for (std::size_t k = 0; k < motions.size(); ++k) {
    if (motions[k]->limit) {
      j[names[k]] = limit_json(*motions[k]->limit);
    } else {
      j[names[k]] = nullptr;
      reasons[names[k]] = motions[k]->reason;
    }
  }
  j["reasons"] = reasons;
  j["fadir_adduction_deg"] = rom.fadir_adduction_deg;
  j["faber_flexion_deg"] = rom.faber_flexion_deg;
  j["faber_abduction_deg"] = rom.faber_abduction_deg;
  j["milliseconds"] = rom.milliseconds;
  return j.dump(indent);
}

}  // namespace hipfai::anatomy
