// Tests of the virtual resections: the cutting tools' shape, a cam resected to a target alpha on a
// synthetic femur-like solid, a rim trimmed on a synthetic socket, and bad requests.
#include "anatomy/resection.h"

#include "anatomy/mesh_boolean.h"
#include "core/error.h"
#include "geometry/hip_frame.h"
#include "geometry/hip_measure.h"
#include "geometry/mesh_io.h"
#include "tests/geometry/study_hips.h"
#include "geometry/mesh_check.h"
#include "geometry/primitive_meshes.h"
#include "tests/anatomy/anatomy_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace hipfai::anatomy {
namespace {

using test_support::expect_solid;

using geometry::kDegToRad;
using geometry::kRadToDeg;
using geometry::TriMesh;
using geometry::Vec3;

// Polar angle of x about (c, axis), deg.
double polar_deg(const Vec3& x, const Vec3& c, const Vec3& axis) {
  const Vec3 d = x - c;
  return std::atan2(d.cross(axis).norm(), d.dot(axis)) * kRadToDeg;
}

CamResectionRequest cam_request(const TriMesh* femur) {
  CamResectionRequest r;
  r.femur = femur;
  r.head_centre_mm = Vec3(1, 2, 3);
  r.head_radius_mm = 25.0;
  r.neck_axis = Vec3::UnitX();
  r.anterior = Vec3::UnitY();
  r.superior = Vec3::UnitZ();
  r.target_alpha_deg = 50.0;
  r.tolerance_mm = 0.2;
  return r;
}

// The cam tool is a solid spherical-shell cap; its inner (cutting) surface lies between R + t/2
// and R + 3t/4 everywhere — checked with each facet plane's distance from the centre, a lower
// bound of the facet's nearest point — and its volume matches the shell sector's
// (2 pi / 3)(b^3 - a^3)(1 + cos A) within the facets' sag: both spheres use the same angular step,
// so every facet is within the relative sag s = (t / 4) / (R + 3t/4) of its sphere, and a volume
// bounded by such facets is within 3 s of the exact one (0.6 % here).
TEST(CamTool, ClosedShellCapBetweenToleranceBounds) {
  CamResectionRequest r = cam_request(nullptr);
  r.transition_deg = 0.0;  // the cap alone: its volume has a closed form
  const TriMesh tool = make_cam_tool(r);
  expect_solid(tool);
  const double R = r.head_radius_mm, t = r.tolerance_mm, rout = 1.5 * R;
  int inner = 0;
  for (std::size_t k = 0; k < tool.num_triangles(); ++k) {
    const auto& tri = tool.triangles[k];
    const Vec3 a = tool.vertices[tri[0]] - r.head_centre_mm;
    bool on_inner = true;
    for (const auto v : tri) on_inner = on_inner && (tool.vertices[v] - r.head_centre_mm).norm() < R + t;
    for (const auto v : tri) EXPECT_GE(polar_deg(tool.vertices[v], r.head_centre_mm, r.neck_axis), 50.0 - 1e-9);
    if (!on_inner) continue;
    ++inner;
    EXPECT_NEAR(a.norm(), R + 0.75 * t, 1e-9);
    const double plane_distance = std::abs(geometry::triangle_unit_normal(tool, k).dot(a));
    EXPECT_GE(plane_distance, R + 0.5 * t);
  }
  EXPECT_GT(inner, 1000);
  const double a = R + 0.75 * t;
  const double exact = 2.0 * std::numbers::pi / 3.0 * (rout * rout * rout - a * a * a) * (1.0 + std::cos(50 * kDegToRad));
  EXPECT_NEAR(volume(tool), exact, 3.0 * (0.25 * t / a) * exact);
}

// A restricted clock sector gives a closed wedge of the same cap, of proportional volume.
TEST(CamTool, ClockSectorIsAClosedWedge) {
  CamResectionRequest r = cam_request(nullptr);
  r.transition_deg = 0.0;
  const double full = volume(make_cam_tool(r));
  r.sector = {-30.0, 60.0};
  const TriMesh wedge = make_cam_tool(r);
  expect_solid(wedge);
  EXPECT_NEAR(volume(wedge), full / 4.0, 0.002 * full);
}

// Femur-like solid: head sphere (R 25, 16 k vertices) + a square neck along +X (inside the head
// sphere at polar angles >= 29 deg, so its own alpha is 29-43 deg) + a round bump (radius 6,
// centre 24 mm out at 70 deg polar, clock 45 deg) standing 5 mm proud between polar 56 and 84.
TriMesh femur_like() {
  const TriMesh head = geometry::make_octasphere(Vec3::Zero(), 25.0, 6);
  const TriMesh neck = geometry::make_box(Vec3(0, -12, -12), Vec3(50, 12, 12), 4);
  const double p = 70 * kDegToRad, c = 45 * kDegToRad;
  const Vec3 bump_centre = 24.0 * Vec3(std::cos(p), std::sin(p) * std::cos(c), std::sin(p) * std::sin(c));
  const TriMesh bump = geometry::make_octasphere(bump_centre, 6.0, 4);
  return union_of(union_of(head, neck), bump);
}

geometry::AlphaMeasurement alpha_of(const TriMesh& femur) {
  return geometry::measure_alpha_angle({&femur}, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ(), Vec3::UnitY());
}

TEST(CamResection, BringsEveryClockAlphaDownToTarget) {
  const TriMesh femur = femur_like();
  const auto before = alpha_of(femur);
  ASSERT_EQ(before.status, geometry::MeasureStatus::kOk);
  double before_max = 0.0;
  for (const auto& [clock, alpha] : before.profile) before_max = std::max(before_max, alpha);
  EXPECT_GT(before_max, 80.0);  // the bump is there to be removed

  CamResectionRequest r;
  r.femur = &femur;
  r.head_centre_mm = before.head_centre_mm;
  r.head_radius_mm = before.head_radius_mm;
  r.neck_axis = Vec3::UnitX();
  r.target_alpha_deg = 50.0;
  r.tolerance_mm = before.tolerance_mm;
  const CamResection out = resect_cam(r);
  expect_solid(out.resected);
  expect_solid(out.removed);

  // The same measurement afterwards: no clock position leaves the sphere beyond 50 deg. 1 deg:
  // the cut face at polar A is inscribed in its cone (chords of a ~4 deg clock step lean < 0.1
  // deg towards the neck) and the measurement samples its contour in steps finer than 0.5 deg.
  const auto after = alpha_of(out.resected);
  ASSERT_EQ(after.status, geometry::MeasureStatus::kOk);
  ASSERT_EQ(after.profile.size(), before.profile.size());
  for (const auto& [clock, alpha] : after.profile) {
    ASSERT_FALSE(std::isnan(alpha)) << clock;
    EXPECT_LE(alpha, 50.0 + 1.0) << "clock " << clock;
  }
  // The head sphere is untouched: the refitted sphere is the same within rounding of the fit.
  EXPECT_NEAR(after.head_radius_mm, before.head_radius_mm, 1e-3);

  // Volumes: removed > 0, and original = resected + removed (exact up to vertex rounding).
  EXPECT_GT(out.removed_volume_mm3, 50.0);
  EXPECT_LT(out.resected_volume_mm3, out.original_volume_mm3);
  EXPECT_NEAR(out.removed_volume_mm3, out.original_volume_mm3 - out.resected_volume_mm3,
              1e-9 * out.original_volume_mm3);
  // The clock bins sum to the removed volume; the bump (clock 45 +- 15 deg as seen from the
  // neck axis) holds it all: the neck and head lie inside the tool's inner sphere.
  double total = 0.0, near_bump = 0.0;
  for (const auto& bin : out.removed_by_clock) {
    total += bin.removed_mm3;
    if (bin.to_deg > 20.0 && bin.from_deg < 70.0) near_bump += bin.removed_mm3;
  }
  EXPECT_NEAR(total, out.removed_volume_mm3, 1e-9 * out.original_volume_mm3);
  EXPECT_NEAR(near_bump, total, 1e-6 * total);
}

// A socket: a box minus the head sphere, its face at x = 12.5 cutting the sphere on the circle of
// polar angle 60 deg about +X, so CE = 90 - 60 = 30 deg. Trimming 10 deg moves the superior rim to
// polar 70 deg on an exact cone, so CE = 20 deg. Tolerance 0.2 deg: the faceted sphere puts the
// original rim up to 0.05 deg off (chord sag 0.02 mm at 25 mm), the tool's cut face is within
// facet_tolerance_mm = 0.05 mm of its cone out to r_out = 40 mm (0.07 deg at the 25 mm socket
// surface where the rim point is), and plane sections of a mesh are exact.
TEST(RimTrim, LowersTheCeAngleByTheTrim) {
  const TriMesh sphere = geometry::make_octasphere(Vec3::Zero(), 25.0, 6);
  const TriMesh block = geometry::make_box(Vec3(-40, -40, -40), Vec3(12.5, 40, 40), 4);
  const TriMesh socket = difference(block, sphere);
  const auto ce = [](const TriMesh& m) {
    return geometry::measure_ce_angle({&m}, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ());
  };
  const auto before = ce(socket);
  ASSERT_EQ(before.status, geometry::MeasureStatus::kOk);
  EXPECT_NEAR(before.ce_deg, 30.0, 0.2);

  RimTrimRequest r;
  r.pelvis = &socket;
  r.acetabular_radius_mm = 25.0;
  r.opening_axis = Vec3::UnitX();
  r.rim = {{0.0, 60.0}, {120.0, 60.0}, {240.0, 60.0}};
  r.trim_deg = 10.0;
  const RimTrim out = trim_rim(r);
  expect_solid(out.trimmed);
  expect_solid(out.tool);
  const auto after = ce(out.trimmed);
  ASSERT_EQ(after.status, geometry::MeasureStatus::kOk);
  EXPECT_NEAR(after.ce_deg, 20.0, 0.2);
  EXPECT_NEAR(before.ce_deg - after.ce_deg, r.trim_deg, 0.2);
  std::cout << "socket: CE " << before.ce_deg << " -> " << after.ce_deg << " deg, removed "
            << out.removed_volume_mm3 << " mm^3, tool " << out.tool.num_triangles() << " triangles\n";

  EXPECT_GT(out.removed_volume_mm3, 0.0);
  EXPECT_NEAR(out.removed_volume_mm3, out.original_volume_mm3 - out.trimmed_volume_mm3,
              1e-9 * out.original_volume_mm3);
  // Nothing is removed outside the superior half (clock 0 to 180).
  double total = 0.0;
  for (const auto& bin : out.removed_by_clock) {
    total += bin.removed_mm3;
    if (bin.to_deg <= 0.0) {
      EXPECT_NEAR(bin.removed_mm3, 0.0, 1e-6 * out.removed_volume_mm3);
    }
  }
  EXPECT_NEAR(total, out.removed_volume_mm3, 1e-9 * out.original_volume_mm3);
}

std::string profile_text(const geometry::AlphaMeasurement& m) {
  std::ostringstream text;
  text.precision(4);
  for (const auto& [clock, alpha] : m.profile) text << " " << clock << ":" << alpha;
  return text.str();
}

// A generated alpha-80 hip (its cam on the bone, anterosuperior): resected to 50 deg, the
// bone's own alpha profile (measured on the bone alone, so its fitted sphere is the bone's head)
// is at most 50 + 1 deg everywhere (1 deg: as for the synthetic femur above).
TEST(CamResection, GeneratedAlpha80HipDownTo50) {
  const auto& model = geometry::test_support::study_hip(20.0, 80.0, geometry::test_support::kStudyTestEdgeMm);
  const TriMesh& bone = model.tissue("femur_bone");
  const auto measure = [&](const TriMesh& m) {
    return geometry::measure_alpha_angle({&m}, model.hjc_mm, model.neck_axis, model.superior, Vec3::UnitY());
  };
  const auto before = measure(bone);
  ASSERT_EQ(before.status, geometry::MeasureStatus::kOk);
  EXPECT_GT(before.max_alpha_deg, 70.0);
  CamResectionRequest r;
  r.femur = &bone;
  r.head_centre_mm = before.head_centre_mm;
  r.head_radius_mm = before.head_radius_mm;
  r.neck_axis = model.neck_axis;
  r.anterior = Vec3::UnitY();
  r.superior = model.superior;
  r.target_alpha_deg = 50.0;
  r.tolerance_mm = before.tolerance_mm;
  const CamResection out = resect_cam(r);
  expect_solid(out.resected);
  const auto after = measure(out.resected);
  ASSERT_EQ(after.status, geometry::MeasureStatus::kOk);
  for (const auto& [clock, alpha] : after.profile) EXPECT_LE(alpha, 51.0) << "clock " << clock;
  EXPECT_GT(out.removed_volume_mm3, 0.0);
  EXPECT_NEAR(out.removed_volume_mm3, out.original_volume_mm3 - out.resected_volume_mm3,
              1e-9 * out.original_volume_mm3);
  std::cout << "generated ce20 alpha80 (edge " << geometry::test_support::kStudyTestEdgeMm << " mm, "
            << bone.num_triangles() << " triangles): R " << before.head_radius_mm << " t "
            << before.tolerance_mm << " removed " << out.removed_volume_mm3 << " mm^3 in " << out.seconds
            << " s\n  alpha before:" << profile_text(before) << "\n  alpha after: " << profile_text(after)
            << "\n";
}

// The LHDL CT femur (whole right femur, 70 k triangles): a real segmented surface is cut into a
// solid. The neck axis is a rough estimate (mean direction of the bone 1.3-1.9 R from the head
// centre: the neck); the anterior direction is any perpendicular (CT frame).
TEST(CamResection, RealLhdlFemurStaysSolid) {
  const TriMesh femur = geometry::read_mesh(std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/femur_r.ply");
  const Vec3 c(143.33, 243.35, -432.43);
  const double R = 23.08;
  Vec3 sum = Vec3::Zero();
  for (const Vec3& p : femur.vertices) {
    const double d = (p - c).norm();
    if (d > 1.3 * R && d < 1.9 * R) sum += (p - c) / d;
  }
  ASSERT_GT(sum.norm(), 0.0);
  CamResectionRequest r;
  r.femur = &femur;
  r.head_centre_mm = c;
  r.head_radius_mm = R;
  r.neck_axis = sum.normalized();
  r.anterior = r.neck_axis.cross(Vec3::UnitZ()).normalized();
  r.superior = Vec3::UnitZ();
  r.tolerance_mm = 0.5;
  const CamResection out = resect_cam(r);
  expect_solid(out.resected);
  EXPECT_NEAR(out.removed_volume_mm3, out.original_volume_mm3 - out.resected_volume_mm3,
              1e-9 * out.original_volume_mm3);
  std::cout << "LHDL femur (" << femur.num_triangles() << " triangles): neck axis " << r.neck_axis.transpose()
            << ", tool " << out.tool.num_triangles() << " triangles, removed " << out.removed_volume_mm3
            << " mm^3, resect_cam " << out.seconds << " s\n";
}

TEST(RimProfile, InterpolatesPeriodically) {
  const std::vector<RimSample> rim = {{350.0, 80.0}, {10.0, 60.0}, {180.0, 70.0}};
  EXPECT_NEAR(rim_polar_deg(rim, 0.0), 70.0, 1e-12);
  EXPECT_NEAR(rim_polar_deg(rim, -10.0), 80.0, 1e-12);
  EXPECT_NEAR(rim_polar_deg(rim, 95.0), 65.0, 1e-12);
  EXPECT_NEAR(rim_polar_deg(rim, 265.0), 75.0, 1e-12);
  EXPECT_NEAR(rim_polar_deg({{42.0, 55.0}}, 200.0), 55.0, 1e-12);
}

void expect_one_line_error(const std::function<void()>& call, const std::string& needle) {
  try {
    call();
    FAIL() << "no error for " << needle;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << message;
  }
}

TEST(CamResection, BadRequestsGiveOneLineErrors) {
  const TriMesh ball = geometry::make_octasphere(Vec3::Zero(), 25.0, 3);
  TriMesh open = ball;
  open.triangles.pop_back();
  expect_one_line_error([&] { (void)resect_cam(cam_request(nullptr)); }, "femur mesh is required");
  expect_one_line_error([&] { (void)resect_cam(cam_request(&open)); }, "femur: not closed");
  auto r = cam_request(&ball);
  r.tolerance_mm = 0.0;
  expect_one_line_error([&] { (void)resect_cam(r); }, "tolerance");
  r = cam_request(&ball);
  r.anterior = r.neck_axis;
  expect_one_line_error([&] { (void)resect_cam(r); }, "parallel to the axis");
  r = cam_request(&ball);
  r.target_alpha_deg = 190.0;
  expect_one_line_error([&] { (void)resect_cam(r); }, "target alpha");
  RimTrimRequest rim;
  rim.pelvis = &ball;
  rim.acetabular_radius_mm = 25.0;
  rim.trim_deg = 5.0;
  expect_one_line_error([&] { (void)trim_rim(rim); }, "no samples");
}

}  // namespace
}  // namespace hipfai::anatomy
