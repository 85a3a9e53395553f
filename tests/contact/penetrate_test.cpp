// The entry point (contact/penetrate.h): the same pairs, bit for bit, as the methods it chooses
// called directly (the pose cache per axis, radial segmenting on the posed mesh); the same again
// from tables loaded from its cache folder; a request without meshes is a status, not a throw.
#include "contact/penetrate.h"

#include "contact/cylindrical_segmenting.h"
#include "contact/radial_segmenting.h"
#include "geometry/primitive_meshes.h"
#include "geometry/tri_mesh.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <unistd.h>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;

void expect_identical_runs(const PenetrationResult& got, const PenetrationResult& want, const std::string& what) {
  ASSERT_EQ(got.status, want.status) << what;
  ASSERT_EQ(got.pairs.size(), want.pairs.size()) << what;
  for (std::size_t i = 0; i < got.pairs.size(); ++i) {
    EXPECT_EQ(got.pairs[i].mobile_vertex, want.pairs[i].mobile_vertex) << what;
    EXPECT_EQ(got.pairs[i].fixed_triangle, want.pairs[i].fixed_triangle) << what;
    EXPECT_EQ(got.pairs[i].depth_mm, want.pairs[i].depth_mm) << what;
    if (!std::isnan(want.pairs[i].angle_deg)) {
      EXPECT_EQ(got.pairs[i].angle_deg, want.pairs[i].angle_deg) << what;
    }
  }
}

// A socket (spherical shell 10..12 mm, inner surface wound inward) and an off-centre ball in it,
// turned about two axes through the centre: both depths find pairs at every step.
struct PenetrateScene {
  TriMesh socket, ball;
  std::vector<PenetrationStep> steps;
  PenetrateScene() {
    TriMesh inner = geometry::make_octasphere(Vec3(0.5, 0, 0), 10.0, 4);
    for (auto& t : inner.triangles) std::swap(t[1], t[2]);
    const TriMesh outer = geometry::make_octasphere(Vec3(0.5, 0, 0), 12.0, 4);
    socket = geometry::merge_meshes({&inner, &outer});
    ball = geometry::make_octasphere(Vec3(0, 0.3, 0.2), 10.2, 4);
    for (const Vec3& axis : {Vec3(1, 0, 0), Vec3(0, 0.6, 0.8)}) {
      for (const double angle_deg : {0.0, 7.5, -20.0}) {
        PenetrationStep step;
        step.axis = axis;
        step.angle_deg = angle_deg;
        step.rotation = Eigen::AngleAxisd(angle_deg * std::numbers::pi / 180.0, axis).toRotationMatrix();
        steps.push_back(step);
      }
    }
  }
  PenetrationRequest request() const {
    PenetrationRequest request;
    request.fixed = &socket;
    request.mobile = &ball;
    request.curvilinear = true;
    request.radial = true;
    request.steps = steps;
    request.radial_rule = RadialCrossingRule::kUnion;
    request.radial_table.table_size = 1500;
    request.num_threads = 2;
    return request;
  }
};

void expect_as_direct_methods(const PenetrateScene& scene, const PenetrationResponse& response, const std::string& what) {
  ASSERT_EQ(response.status, QueryStatus::kOk) << response.message;
  ASSERT_EQ(response.steps.size(), scene.steps.size());
  const PenetrationRequest request = scene.request();
  RadialQueryOptions radial;
  radial.rule = request.radial_rule;
  const RadialTable table = build_radial_table(scene.socket, Vec3::Zero(), request.radial_table);
  for (std::size_t k = 0; k < scene.steps.size(); ++k) {
    const PenetrationStep& step = scene.steps[k];
    CylindricalTableOptions no_index;
    no_index.angular_index = false;
    const CylindricalPoseCache cache(CylindricalTable::build(scene.socket, Vec3::Zero(), step.axis, no_index, &scene.ball),
                                     scene.ball);
    const std::string label = what + ", step " + std::to_string(k);
    expect_identical_runs(response.steps[k].curvilinear, cache.query(step.angle_deg), label + " curvilinear");
    TriMesh posed = scene.ball;
    for (Vec3& v : posed.vertices) v = step.rotation * v;
    expect_identical_runs(response.steps[k].radial, radial_segmenting(table, scene.socket, posed, radial), label + " radial");
    EXPECT_GT(response.steps[k].radial.pairs.size(), 0u) << label;
  }
}

TEST(Penetrate, AnswersAsTheMethodsItChooses) {
  const PenetrateScene scene;
  const PenetrationResponse response = penetrate(scene.request());
  expect_as_direct_methods(scene, response, "built");
  EXPECT_EQ(response.curvilinear_preprocessing.built, 2);  // one pose cache per distinct axis
  EXPECT_EQ(response.radial_preprocessing.built, 1);
}

TEST(Penetrate, CacheFolderIsMadeAndReused) {
  const PenetrateScene scene;
  PenetrationRequest request = scene.request();
  request.cache_dir = std::filesystem::temp_directory_path() / ("hipfai_penetrate_" + std::to_string(::getpid())) / "cache";
  request.fixed_key = "socket";
  request.mobile_key = "ball";
  std::filesystem::remove_all(request.cache_dir.parent_path());
  const PenetrationResponse first = penetrate(request);
  const PenetrationResponse second = penetrate(request);
  std::filesystem::remove_all(request.cache_dir.parent_path());
  EXPECT_EQ(first.curvilinear_preprocessing.built, 2);
  EXPECT_EQ(second.curvilinear_preprocessing.loaded, 2);
  EXPECT_EQ(second.curvilinear_preprocessing.built, 0);
  EXPECT_EQ(second.radial_preprocessing.loaded, 1);
  expect_as_direct_methods(scene, second, "loaded");
}

TEST(Penetrate, MissingMeshIsAStatus) {
  PenetrationRequest request;
  request.curvilinear = true;
  request.steps.resize(1);
  const PenetrationResponse response = penetrate(request);
  EXPECT_EQ(response.status, QueryStatus::kInvalidInput);
  EXPECT_FALSE(response.message.empty());
}

}  // namespace
}  // namespace hipfai::contact
