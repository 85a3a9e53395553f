// HJC estimation (geometry/hjc.h): the functional methods on a synthetic ball and socket with a
// known centre, region finding on a generated hip, and one-line errors on bad input.
#include "core/error.h"
#include "geometry/hjc.h"
#include "geometry/primitive_meshes.h"
#include "tests/geometry/study_hips.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

namespace hipfai::geometry {
namespace {

const Vec3 kCentre(12.0, -7.0, 30.0);
const Vec3 kNeck = Vec3(1.0, 0.2, 0.6).normalized();      // head cap pole
const Vec3 kSocket = Vec3(0.7, -0.1, 0.8).normalized();   // socket cap pole (opening direction)

// Vertices of `sphere` within cap_deg of `pole` as seen from `centre`.
std::vector<std::int32_t> cap(const TriMesh& sphere, const Vec3& centre, const Vec3& pole, double cap_deg) {
  std::vector<std::int32_t> vertices;
  const double c = std::cos(cap_deg * kDegToRad);
  for (std::size_t v = 0; v < sphere.num_vertices(); ++v) {
    if ((sphere.vertices[v] - centre).normalized().dot(pole) >= c) vertices.push_back(static_cast<std::int32_t>(v));
  }
  return vertices;
}

struct BallAndSocket {
  TriMesh head = make_octasphere(kCentre, 23.0, 5);
  TriMesh socket;
  HjcRequest request;
};

// Head: octasphere r 23 about kCentre (vertices exact, facets inside by at most the sagitta,
// ~0.007 mm at level 5); socket: octasphere r 25 about kCentre + offset (offset 0: uniform gap).
void ball_and_socket(BallAndSocket& b, const Vec3& socket_offset) {
  b.socket = make_octasphere(kCentre + socket_offset, 25.0, 5);
  b.request.femur = &b.head;
  b.request.pelvis = &b.socket;
  b.request.head_region = region_from_vertices(b.head, cap(b.head, kCentre, kNeck, 100.0), "head cap");
  b.request.lunate_region = region_from_vertices(b.socket, cap(b.socket, kCentre, kSocket, 75.0), "socket cap");
  b.request.femur_long_axis = Vec3(0, 0, 1);
}

// Uniform gap: every method finds the centre. The sphere fits are exact (vertices on exact
// spheres); the functional ones measure distances to the faceted head, so they are exact to the
// facets' sagitta (< 0.01 mm), 0.02 mm allowed.
TEST(HjcFunctional, UniformGapEveryMethodRecoversTheCentre) {
  BallAndSocket b;
  ball_and_socket(b, Vec3::Zero());
  const HjcResult result = estimate_hjc(b.request);
  ASSERT_EQ(result.methods.size(), 5u);
  for (const auto& m : result.methods) {
    ASSERT_TRUE(m.ok) << m.name << ": " << m.message;
    const double tolerance = (m.name == "dconst" || m.name == "dref") ? 0.02 : 1e-9;
    EXPECT_LT((m.center_mm - kCentre).norm(), tolerance) << m.name;
  }
  EXPECT_LT(result.method("dref").residual_motion_rms_mm, 0.02);
  EXPECT_NEAR(result.method("doublesphere").radius_b_mm, 25.0, 1e-9);
}

// The JSON shape other tools read: {"methods": {name: {"center_mm": [x, y, z], "radius_mm", "rms_mm", ...}}}.
TEST(HjcFunctional, JsonShape) {
  BallAndSocket b;
  ball_and_socket(b, Vec3::Zero());
  const auto json = nlohmann::json::parse(hjc_result_json(estimate_hjc(b.request)));
  ASSERT_TRUE(json.contains("methods"));
  for (const auto& name : hjc_method_names()) {
    const auto& m = json["methods"][name];
    ASSERT_EQ(m["center_mm"].size(), 3u) << name;
    EXPECT_NEAR(m["center_mm"][0].get<double>(), kCentre.x(), 0.02) << name;
    EXPECT_TRUE(m.contains("rms_mm")) << name;
    const bool functional = name == "dconst" || name == "dref";
    EXPECT_EQ(m["radius_mm"].is_null(), functional) << name;
    EXPECT_EQ(m.contains("residual_motion_rms_mm"), functional) << name;
  }
  EXPECT_EQ(json["regions"]["femoral_head"]["source"], "head cap");
}

// Non-uniform gap (socket centre 1 mm off the head's): the femur still turns about its head, so
// dref (distances of the scanned pose kept) recovers the head centre, while acetabulumsphere
// finds the socket's centre and dconst, forcing a uniform gap, is pulled off. The test fails if
// dref is no better than dconst.
TEST(HjcFunctional, NonUniformGapDrefRecoversTheCentreDconstDoesNot) {
  const Vec3 offset(0.6, -0.5, 0.6);  // |offset| = 0.98 mm
  BallAndSocket b;
  ball_and_socket(b, offset);
  const HjcResult result = estimate_hjc(b.request);
  EXPECT_LT((result.method("dref").center_mm - kCentre).norm(), 0.02);
  EXPECT_LT((result.method("femoralheadsphere").center_mm - kCentre).norm(), 1e-9);
  EXPECT_LT((result.method("acetabulumsphere").center_mm - (kCentre + offset)).norm(), 1e-9);
  EXPECT_GT((result.method("dconst").center_mm - kCentre).norm(), 0.2);
  // dconst makes the gap uniform by shifting the head onto the socket's centre, exactly here.
  EXPECT_LT(result.method("dconst").rms_mm, 0.02);
}

// The functional machinery itself: started 3 mm off the centre, the per-pose shifts must undo the
// wrong rotation centre, and the least-moving point is the true centre again.
TEST(HjcFunctional, ShiftsUndoAWrongStartCentre) {
  BallAndSocket b;
  ball_and_socket(b, Vec3(0.3, 0.8, -0.4));
  const SurfaceRegion& head = *b.request.head_region;
  const SurfaceRegion& lunate = *b.request.lunate_region;
  const FunctionalHjc fit = functional_hjc(head.patch, head.normals, lunate.patch.vertices,
                                           kCentre + Vec3(2.0, -2.0, 1.0), Vec3(0, 0, 1),
                                           FunctionalTarget::kReference, 0.0);
  ASSERT_TRUE(fit.ok) << fit.message;
  EXPECT_EQ(fit.poses_used, 24);
  EXPECT_LT((fit.center_mm - kCentre).norm(), 0.02);
  EXPECT_LT(fit.residual_motion_max_mm, 0.05);
  // The shifts are real: about |(R - I)(c - c0)| ~ 2 sin(10 deg) * 3 mm ~ 1 mm.
  double largest = 0.0;
  for (const Vec3& s : fit.shifts_mm) largest = std::max(largest, s.norm());
  EXPECT_GT(largest, 0.5);
}

TEST(HjcFunctional, SignedDistanceToAPatch) {
  const TriMesh head = make_octasphere(kCentre, 23.0, 5);
  const std::vector<Vec3> normals = vertex_normals(head);
  const PatchDistance distance(head, normals);
  Vec3 gradient;
  bool border = true;
  const double outside = distance.signed_distance(kCentre + 25.0 * kNeck, gradient, border);
  // Facets lie inside the sphere by up to ~ circumradius^2 / (2 r) ~ 0.015 mm at level 5.
  EXPECT_NEAR(outside, 2.0, 0.02);
  EXPECT_FALSE(border);
  EXPECT_GT(gradient.dot(kNeck), 0.999);
  EXPECT_NEAR(distance.signed_distance(kCentre + 21.0 * kNeck, gradient, border), -2.0, 0.02);
}

// Generated hip (CE 20, alpha 40, 3 mm): the articular surfaces are spheres of radius 25 about
// the HJC (the truth). Regions found automatically on them give it back to the fit's precision
// on a 3 mm mesh (vertices exact on the sphere: 0.05 mm allowed for the region's discretisation).
TEST(HjcRegionsOnGeneratedHip, HeadAndLunateAreFound) {
  const HipModel& model = test_support::study_hip(20.0, 40.0, test_support::kStudyTestEdgeMm);
  const TriMesh& cartilage = model.tissue("femoral_cartilage");
  const TriMesh& socket = model.tissue("acetabular_cartilage");
  const SurfaceRegion head = find_femoral_head(cartilage, &socket);
  EXPECT_EQ(head.source, "automatic");
  EXPECT_LT((head.sphere.center_mm - model.hjc_mm).norm(), 0.05);
  EXPECT_NEAR(head.sphere.radius_mm, 25.0, 0.05);
  const SurfaceRegion lunate = find_lunate_surface(socket, head.sphere.center_mm, head.sphere.radius_mm);
  EXPECT_LT((lunate.sphere.center_mm - model.hjc_mm).norm(), 0.05);
  EXPECT_NEAR(lunate.sphere.radius_mm, 25.0, 0.05);
  EXPECT_GT(lunate.patch.num_vertices(), 100u);
  // Every lunate vertex is within the narrowest band (0.5 mm) of the articular sphere: none of
  // the cartilage's outer (bone-side) face, 2 mm out.
  for (const Vec3& p : lunate.patch.vertices) EXPECT_NEAR((p - model.hjc_mm).norm(), 25.0, 0.5);

  // Bones: the bony socket is the R + 2 mm sphere about the HJC; the bony head is the generator's
  // lens-shaped cartilage's inner face, a smaller sphere shifted along the neck (hip_generator.h).
  const TriMesh& femur = model.tissue("femur_bone");
  const TriMesh& pelvis = model.tissue("acetabular_bone");
  const SurfaceRegion bone_head = find_femoral_head(femur, &pelvis);
  EXPECT_GT(bone_head.sphere.radius_mm, 23.0);
  EXPECT_LT(bone_head.sphere.radius_mm, 25.0);
  const Vec3 shift = bone_head.sphere.center_mm - model.hjc_mm;
  EXPECT_GT(shift.dot(model.neck_axis), 0.5);
  EXPECT_LT((shift - shift.dot(model.neck_axis) * model.neck_axis).norm(), 0.1);
  const SurfaceRegion bone_lunate = find_lunate_surface(pelvis, bone_head.sphere.center_mm, bone_head.sphere.radius_mm);
  EXPECT_LT((bone_lunate.sphere.center_mm - model.hjc_mm).norm(), 0.05);
  EXPECT_NEAR(bone_lunate.sphere.radius_mm, 27.0, 0.05);
}

void expect_one_line_error(const HjcRequest& request, const std::string& fragment) {
  try {
    (void)estimate_hjc(request);
    ADD_FAILURE() << "no error; expected '" << fragment << "'";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(fragment), std::string::npos) << message << " (expected: " << fragment << ")";
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(HjcErrors, BadInputIsOneLine) {
  // A finely meshed box (2.5 mm triangles, like a bone mesh). A very coarse one (8 divisions, 5-7 mm
  // triangles) does let a 17 mm "sphere" through at 1.5 mm RMS: the finder's limits are those of
  // segmentation noise (hjc_regions.h), so it cannot reject every coarse non-sphere.
  const TriMesh box = make_box(Vec3(0, 0, 0), Vec3(60, 40, 30), 24);
  const TriMesh ball = make_octasphere(Vec3(0, 0, 0), 23.0, 4);
  HjcRequest one_mesh;
  one_mesh.femur = &ball;
  expect_one_line_error(one_mesh, "both a femur and a pelvis");

  HjcRequest no_head;
  no_head.femur = &box;
  no_head.pelvis = &box;
  expect_one_line_error(no_head, "no femoral head found");

  HjcRequest flat;
  flat.femur = &box;
  flat.pelvis = &box;
  flat.femur_name = "box.ply";
  std::vector<std::int32_t> face;  // the z = 0 face of the box
  for (std::size_t v = 0; v < box.num_vertices(); ++v) if (box.vertices[v].z() == 0.0) face.push_back(static_cast<std::int32_t>(v));
  flat.head_region = region_from_vertices(box, face, "face");
  expect_one_line_error(flat, "box.ply: femoral head region: the points are coplanar");

  HjcRequest no_lunate;  // a head but nothing around it
  no_lunate.femur = &ball;
  no_lunate.pelvis = &box;
  no_lunate.head_options.pelvis_reach_mm = 1000.0;
  expect_one_line_error(no_lunate, "no lunate surface found");

  BallAndSocket b;
  ball_and_socket(b, Vec3::Zero());
  b.request.methods = {"pivot"};
  expect_one_line_error(b.request, "unknown method 'pivot'");
}

}  // namespace
}  // namespace hipfai::geometry
