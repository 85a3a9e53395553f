// Tests of the parametric hip: surface topology, dimensions measured on the meshes against the
// thesis' numbers, non-overlap in the neutral pose, model.json round trip and parameter errors.
#include "core/error.h"
#include "core/literature.h"
#include "geometry/hip_frame.h"
#include "geometry/gmsh_runtime.h"
#include "geometry/hip_generator.h"
#include "geometry/hip_model.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_parts.h"
#include "tests/geometry/mesh_inside.h"
#include "tests/geometry/study_hips.h"
#include "geometry/hjc_regions.h"

#include <gmsh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <numbers>

namespace hipfai::geometry {
namespace {

using test_support::InsideTester;

const HipModel& hip(double ce, double alpha, double edge_mm) {
  return test_support::study_hip(ce, alpha, edge_mm);
}

// Vertices of `a`, pushed `depth_mm` into `a`, that lie inside `b`: a volume overlap of a and b
// that touching on a shared interface does not produce (the pushed points leave the interface).
std::size_t points_of_a_inside_b(const TriMesh& a, const TriMesh& b, double depth_mm) {
  const auto normals = vertex_normals(a);
  const InsideTester inside_a(a);
  const InsideTester inside_b(b);
  std::size_t count = 0;
  for (std::size_t i = 0; i < a.vertices.size(); ++i) {
    // At thin wedges (the cartilage lens edge, the labrum tip) the push can leave a, so a point
    // counts only when it is inside both solids: a witness of a common volume.
    const Vec3 q = a.vertices[i] - depth_mm * normals[i];
    if (inside_a.inside(q) && inside_b.inside(q)) ++count;
  }
  return count;
}

// Distance from the origin along `direction` to the triangles of `mesh` it crosses (Möller-Trumbore).
std::vector<double> ray_hits(const TriMesh& mesh, const Vec3& origin, const Vec3& direction) {
  std::vector<double> hits;
  for (const Triangle& t : mesh.triangles) {
    const Vec3& p0 = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Vec3 e1 = mesh.vertices[static_cast<std::size_t>(t[1])] - p0;
    const Vec3 e2 = mesh.vertices[static_cast<std::size_t>(t[2])] - p0;
    const Vec3 h = direction.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-12) continue;
    const Vec3 s = origin - p0;
    const double u = s.dot(h) / det;
    const Vec3 qv = s.cross(e1);
    const double v = direction.dot(qv) / det;
    if (u < 0 || v < 0 || u + v > 1) continue;
    const double distance = e2.dot(qv) / det;
    if (distance > 0) hits.push_back(distance);
  }
  std::sort(hits.begin(), hits.end());
  return hits;
}

void expect_clean_surfaces(const HipModel& model) {
  ASSERT_EQ(model.tissues.size(), kHipTissueNames.size());
  for (const char* name : kHipTissueNames) {
    const MeshReport report = check_mesh(model.tissue(name));
    EXPECT_TRUE(report.closed) << name;
    EXPECT_TRUE(report.watertight_manifold) << name;
    EXPECT_TRUE(report.outward) << name;
    EXPECT_EQ(report.non_manifold_vertices, 0u) << name;
    EXPECT_EQ(report.degenerate_triangles, 0u) << name;
    EXPECT_EQ(report.connected_components, 1u) << name;
  }
}

// Every study hip at the coarsest level (~2 k vertices: few triangles across the thin cartilage
// edge, labrum tip and neck clearance, the hardest case for the mesher); three of them at the
// default edge. (The 3 mm test level is checked in hip_study_grid_test.cpp.)
TEST(HipGenerator, SurfacesAreClosedManifoldOutwardAtCoarsestAndDefaultEdges) {
  for (int ce = 0; ce <= 40; ce += 10) {
    for (int alpha = 40; alpha <= 80; alpha += 10) {
      SCOPED_TRACE("ce" + std::to_string(ce) + "_alpha" + std::to_string(alpha));
      expect_clean_surfaces(hip(ce, alpha, test_support::kCoarsestEdgeMm));
    }
  }
  for (const auto& [ce, alpha] : std::vector<std::pair<double, double>>{{0, 40}, {40, 80}, {20, 40}}) {
    expect_clean_surfaces(hip(ce, alpha, HipParameters{}.edge_mm));
  }
}

// The lens: 2 mm at the pole (-neck axis). Both surfaces are spheres there, so the ray from the
// HJC meets the outer one at 25 mm and the inner at 23 mm up to the chord sagitta (< 0.03 mm at
// 2 mm edges): 0.1 mm allowed as the requirement states.
TEST(HipGenerator, FemoralCartilageIsTwoMillimetresAtThePole) {
  for (const auto& [ce, alpha] : std::vector<std::pair<double, double>>{{20, 40}, {40, 80}}) {
    const HipModel& model = hip(ce, alpha, 2.0);
    const auto hits = ray_hits(model.tissue("femoral_cartilage"), model.hjc_mm, -model.neck_axis);
    ASSERT_EQ(hits.size(), 2u);
    EXPECT_NEAR(hits[1] - hits[0], literature::kFemoralCartilageMaxThicknessMm, 0.1);
    EXPECT_NEAR(hits[1], literature::kArticularRadiusMm, 0.05);
  }
}

// Acetabular cartilage: a 25..27 mm shell, so every vertex lies on one of the two spheres or on
// the rim / fossa cuts between them.
TEST(HipGenerator, AcetabularCartilageIsTwoMillimetreShell) {
  const HipModel& model = hip(20, 40, 2.0);
  for (const Vec3& p : model.tissue("acetabular_cartilage").vertices) {
    const double r = (p - model.hjc_mm).norm();
    EXPECT_GE(r, 25.0 - 1e-6);
    EXPECT_LE(r, 27.0 + 1e-6);
  }
  // Horseshoe: the ray to the inferior rim meets no cartilage (the notch), the ray to the roof does.
  const Vec3 a = model.acetabular_axis;
  const Vec3 inferior = (-Vec3::UnitZ() + Vec3::UnitZ().dot(a) * a).normalized();
  const Vec3 roof = (Vec3::UnitZ() - Vec3::UnitZ().dot(a) * a).normalized();
  EXPECT_TRUE(ray_hits(model.tissue("acetabular_cartilage"), model.hjc_mm, (inferior - 0.1 * a).normalized()).empty());
  EXPECT_EQ(ray_hits(model.tissue("acetabular_cartilage"), model.hjc_mm, (roof - 0.3 * a).normalized()).size(), 2u);
}

// Labrum height: its tip's distance from the rim, i.e. from the rim cone's generator in the
// tip's meridian plane: R sin(opening - tip angle), the tip angle being the smallest angle of a
// labrum vertex from the acetabular axis (a plane rim: the height above the rim plane). The tip
// circle is meshed by vertices lying on it, so only rounding is lost; 0.2 mm as required.
TEST(HipGenerator, LabrumIsSevenMillimetresHigh) {
  for (double ce : {0.0, 20.0, 40.0}) {
    const HipModel& model = hip(ce, 40, 2.0);
    const double opening = model.socket_opening_deg * kDegToRad;
    double tip_angle = 10.0;
    for (const Vec3& p : model.tissue("labrum").vertices) {
      const Vec3 d = (p - model.hjc_mm).normalized();
      tip_angle = std::min(tip_angle, std::acos(std::clamp(d.dot(model.acetabular_axis), -1.0, 1.0)));
    }
    EXPECT_NEAR(model.parameters.articular_radius_mm * std::sin(opening - tip_angle), literature::kLabrumHeightMm, 0.2)
        << "ce " << ce;
    // Its inner face continues the articular sphere: no labrum vertex inside 25 mm.
    for (const Vec3& p : model.tissue("labrum").vertices) EXPECT_GE((p - model.hjc_mm).norm(), 25.0 - 1e-6);
  }
}

// Hips whose neck sector ends just short of the notch (sampled CE 27-28 deg): the generator left a
// 2-14 mm^3 sliver of labrum between the two cuts, which the FE volume mesher inverted once it
// meshed every piece. The labrum is one piece now, and whatever piece it keeps holds at least one
// base width of its section along the rim. A grid hip's labrum is one piece as before.
TEST(HipGenerator, NoLabrumSliverBetweenTheNeckSectorAndTheNotch) {
  const double least_mm3 = literature::kLabrumBaseWidthMm * 0.5 * literature::kLabrumBaseWidthMm * literature::kLabrumHeightMm;
  struct Sampled {
    double ce, alpha;
  };
  for (const Sampled& h : {Sampled{28.022534418851137, 73.78243003040552}, Sampled{27.319409418851137, 43.15743003040552},
                           Sampled{40.0, 80.0}}) {
    SCOPED_TRACE(::testing::Message() << "CE " << h.ce << " alpha " << h.alpha);
    const std::vector<TriMesh> pieces = connected_parts(hip(h.ce, h.alpha, 2.0).tissue("labrum"));
    EXPECT_EQ(pieces.size(), 1u);
    for (const TriMesh& piece : pieces) EXPECT_GE(signed_volume(piece), least_mm3);
  }
}

// The neutral pose (no tissue inside another) is tested for all 25 study hips in
// hip_study_grid_test.cpp.

// Sanity for the FAI study (thesis §4.3.2.3): at the standing-to-sitting end pose a normal hip
// keeps its femoral bone off the labrum, a combined pincer+cam hip drives bone into it.
TEST(HipGenerator, StandToSitEndPoseSeparatesNormalFromCombinedFai) {
  const HipPoseDeg pose{literature::kStandToSitFlexionDeg, literature::kStandToSitAdductionDeg,
                        literature::kStandToSitInternalRotationDeg};
  std::map<std::pair<double, double>, std::size_t> overlap;
  for (const auto& [ce, alpha] : std::vector<std::pair<double, double>>{{20, 40}, {40, 80}}) {
    const HipModel& model = hip(ce, alpha, test_support::kStudyTestEdgeMm);
    TriMesh femur = model.tissue("femur_bone");
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    motion.linear() = femur_rotation(pose, model.axes);
    apply_transform(femur, motion);
    overlap[{ce, alpha}] = points_of_a_inside_b(model.tissue("labrum"), femur, 0.1) +
                           points_of_a_inside_b(femur, model.tissue("labrum"), 0.1);
  }
  const std::size_t normal = overlap[std::make_pair(20.0, 40.0)];
  const std::size_t combined = overlap[std::make_pair(40.0, 80.0)];
  std::printf("bone-labrum overlap vertices at (59.6, 13.6, 10.9): normal %zu, combined %zu\n",
              normal, combined);
  EXPECT_EQ(normal, 0u);
  EXPECT_GT(combined, 0u);
}

TEST(HipParameters, RangesAreEnforcedWithTheFieldName) {
  HipParameters p;
  p.ce_deg = 50.0;
  try {
    validate_hip_parameters(p, "test");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ce_deg"), std::string::npos);
  }
  p = HipParameters{};
  p.alpha_deg = 30.0;
  EXPECT_THROW(validate_hip_parameters(p), Error);
  EXPECT_THROW(hip_parameters_from_json("{\"no_such\": 1}", "x"), Error);
  EXPECT_THROW(hip_parameters_from_json("{\"edge_mm\": \"2\"}", "x"), Error);
}

TEST(HipParameters, JsonRoundTripKeepsEveryField) {
  HipParameters p;
  p.ce_deg = 12.5;
  p.alpha_deg = 71.25;
  p.cam_height_mm = 3.5;
  const HipParameters q = hip_parameters_from_json(hip_parameters_to_json(p), "round trip");
  EXPECT_EQ(hip_parameters_to_json(p), hip_parameters_to_json(q));
  EXPECT_EQ(q.alpha_deg, 71.25);
}

TEST(HipModel, WriteThenLoadRoundTripsAndNamesBadKeys) {
  const HipModel& model = hip(20, 40, test_support::kStudyTestEdgeMm);
  const auto dir = std::filesystem::path(HIPFAI_BINARY_DIR) / "hip_model_test";
  std::filesystem::remove_all(dir);
  write_hip_model(model, dir, "ply");
  const HipModel loaded = load_hip_model(dir);
  EXPECT_EQ(loaded.tissues.size(), 5u);
  EXPECT_EQ(loaded.tissue("labrum").num_vertices(), model.tissue("labrum").num_vertices());
  EXPECT_NEAR((loaded.neck_axis - model.neck_axis).norm(), 0.0, 1e-12);
  EXPECT_EQ(loaded.parameters.ce_deg, 20.0);
  // Which gmsh algorithm meshed the surfaces is recorded and read back.
  EXPECT_NE(model.surface_algorithm, 0);
  EXPECT_EQ(loaded.surface_algorithm, model.surface_algorithm);
  EXPECT_EQ(loaded.mesher_failures, model.mesher_failures);

  // Corrupt one axis: the error names model.json and the key.
  std::ifstream in(dir / "model.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const auto at = text.find("\"neck_axis\"");
  ASSERT_NE(at, std::string::npos);
  const auto open = text.find('[', at);
  const auto close = text.find(']', at);
  text.replace(open, close - open + 1, "[1, 1, 0]");
  std::ofstream(dir / "model.json") << text;
  try {
    load_hip_model(dir);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("neck_axis"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("model.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hipfai::geometry

namespace hipfai::geometry {
namespace {

// The mesher runs in a fresh image of the program at fixed addresses, not in a copy of this
// process: what this process did to gmsh (here an option that halves every mesh size) does not
// reach it, nor do its heap and address layout, on which gmsh's and OpenCASCADE's address-ordered
// entities made one hip of an estimator sample mesh with 443 or 446 femur vertices from run to run.
// With the mesher in a forked child the option halves the sizes; in a fresh image at random
// addresses this test failed in one run of six (the hip's two meshes differed).
TEST(HipGenerator, MeshesInAFreshImageWhateverThisProcessDidToGmsh) {
  HipParameters p;
  p.ce_deg = 12.984427614567561;
  p.alpha_deg = 44.29247519387215;
  p.edge_mm = 7.0;
  const HipModel plain = generate_hip(p).model;
  {
    const std::unique_lock<std::mutex> gmsh_lock = lock_gmsh();
    gmsh::option::setNumber("Mesh.MeshSizeFactor", 0.5);
  }
  const HipModel after = generate_hip(p).model;
  {
    const std::unique_lock<std::mutex> gmsh_lock = lock_gmsh();
    gmsh::option::setNumber("Mesh.MeshSizeFactor", 1.0);
  }
  ASSERT_EQ(after.tissues.size(), plain.tissues.size());
  for (const auto& [name, mesh] : plain.tissues) {
    const TriMesh& other = after.tissues.at(name);
    EXPECT_TRUE(other.vertices == mesh.vertices && other.triangles == mesh.triangles) << name << " differs";
  }
}

}  // namespace
}  // namespace hipfai::geometry
