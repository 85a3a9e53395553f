// A hip model folder made from the real LHDL CT bones with synthesised cartilage and labrum: valid,
// separate solids in the hip frame, read back by load_hip_model with what `hipfai run` needs.
#include "studies/pipeline/soft_tissue_model.h"

#include "anatomy/mesh_boolean.h"
#include "anatomy/side.h"
#include "contact/ray_triangle.h"
#include "core/error.h"
#include "core/literature.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"
#include "geometry/hip_volume_mesh.h"
#include "geometry/mesh_parts.h"
#ifdef HIPFAI_WITH_FEM
#include "fem/hip_fe_model.h"
#endif
#include "../geometry/hex_volume.h"
#include "../geometry/mesh_inside.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <tuple>

namespace hipfai::studies {
namespace {

namespace fs = std::filesystem;
using geometry::TriMesh;
using geometry::Vec3;

const fs::path kTissueScratch = fs::path(HIPFAI_BINARY_DIR) / "test-scratch" / "soft_tissue_model";
const std::string kLhdl = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";

// Vertices of `tissue` inside `solid` farther than `tolerance_mm` from its surface, skipping the
// vertices `shared` with a bone (the bone/cartilage interface is the bone's own surface).
std::size_t vertices_inside(const TriMesh& tissue, const TriMesh& solid, const std::set<std::tuple<double, double, double>>& shared,
                            double tolerance_mm) {
  const geometry::test_support::InsideTester tester(solid);
  std::size_t count = 0;
  for (const Vec3& v : tissue.vertices) {
    if (shared.count({v.x(), v.y(), v.z()}) || !tester.inside(v)) continue;
    if (geometry::test_support::distance_to_surface(solid, v) > tolerance_mm) ++count;
  }
  return count;
}

// The soft tissue model of the LHDL CT bones, with the request's default options or `options`.
SoftTissueModel lhdl_model(const anatomy::SoftTissueOptions& options = {}) {
  const TriMesh femur = geometry::read_mesh(kLhdl + "femur_r.ply");
  const TriMesh pelvis = geometry::read_mesh(kLhdl + "pelvis_no_sacrum.ply");
  SoftTissueModelRequest request;
  request.assessment.femur = &femur;
  request.assessment.pelvis = &pelvis;
  request.options = options;
  return build_soft_tissue_model(request);
}

TEST(SoftTissueModel, TheRealBonesGiveAValidModelFolder) {
  const SoftTissueModelRequest request;
  const SoftTissueModel result = lhdl_model();
  const auto& r = result.report;
  std::printf("LHDL: femoral %.0f mm2 mean %.2f (%.2f-%.2f) on sphere %.0f overlap %.0f; acetabular %.0f mm2 mean %.2f "
              "(%.2f-%.2f) on sphere %.0f overlap %.0f; labrum %.0f mm3 %d/%d sections %d pieces (femur %d pelvis %d "
              "rim %d); head %.2f lunate %.2f; %.2f s (assessment %.2f, tissues %.2f)\n",
              r.femoral.covered_area_mm2, r.femoral.mean_thickness_mm, r.femoral.min_thickness_mm,
              r.femoral.max_thickness_mm, r.femoral.articular_area_mm2, r.femoral.overlap_area_mm2,
              r.acetabular.covered_area_mm2, r.acetabular.mean_thickness_mm, r.acetabular.min_thickness_mm,
              r.acetabular.max_thickness_mm, r.acetabular.articular_area_mm2, r.acetabular.overlap_area_mm2,
              r.labrum_volume_mm3, r.labrum_sections, r.labrum_sections_total, r.labrum_pieces, r.labrum_dropped_femur,
              r.labrum_dropped_pelvis, r.labrum_missing_rim, result.head_radius_mm, result.lunate_radius_mm,
              result.total_seconds, result.assessment_seconds, r.seconds);
  EXPECT_EQ(result.side, anatomy::Side::kRight);
  // hip.json: HJC [143.80, 243.46, -432.58] mm (its own sphere fit); the assessment's head fit
  // agrees to within a millimetre (assessment tests).
  EXPECT_LT((result.hjc_input_mm - Vec3(143.80, 243.46, -432.58)).norm(), 1.0);

  const geometry::HipModel& m = result.model;
  const TriMesh& bone_f = m.tissue("femur_bone");
  const TriMesh& bone_p = m.tissue("acetabular_bone");
  for (const char* name : {"femoral_cartilage", "acetabular_cartilage", "labrum"}) {
    const TriMesh& tissue = m.tissue(name);
    const geometry::MeshReport check = geometry::check_mesh(tissue);
    EXPECT_TRUE(check.watertight_manifold) << name << ": boundary " << check.boundary_edges << ", non-manifold "
                                           << check.non_manifold_edges << "/" << check.non_manifold_vertices
                                           << ", degenerate " << check.degenerate_triangles;
    EXPECT_TRUE(check.outward) << name;
    EXPECT_FALSE(anatomy::does_self_intersect(tissue)) << name;
  }
  // In the hip frame: the head centred on the origin, so the cartilage surrounds it at about the
  // head radius (within the head fit's RMS plus the 2 mm layer).
  const auto& fc = m.tissue("femoral_cartilage");
  double mean_r = 0.0;
  for (const Vec3& v : fc.vertices) mean_r += v.norm() / static_cast<double>(fc.vertices.size());
  EXPECT_NEAR(mean_r, result.head_radius_mm, 2.0);
  // Cartilage layers on their bones whose joint sides are one sphere about the HJC (the origin),
  // between the two bones' spheres; a layer leaves it only by the minimum thickness, where its bone
  // stands closer to the sphere than that.
  EXPECT_GT(r.femoral.covered_area_mm2, 1000.0);
  EXPECT_GT(r.acetabular.covered_area_mm2, 1000.0);
  EXPECT_GE(r.femoral.min_thickness_mm, request.options.min_thickness_mm - 1e-9);
  EXPECT_GE(r.acetabular.min_thickness_mm, request.options.min_thickness_mm - 1e-9);
  const double r_art = r.articular_radius_mm;
  EXPECT_GT(r_art, result.head_radius_mm);
  EXPECT_LT(r_art, result.lunate_radius_mm);
  // This joint is narrower than both literature layers (2.1 mm between the bones' spheres), so the
  // sphere splits it in their ratio; within 0.25 mm, the two spheres' centres lying 1.5 mm apart.
  // The deepest head bone, 21.7 mm from the centre, is the fovea's edge: were it not left out (a
  // filled hole of the head region), the femoral maximum above it would put the sphere at 23.7 mm.
  const double t_f = request.options.femoral_max_thickness_mm, t_a = request.options.acetabular_thickness_mm;
  ASSERT_LT(result.lunate_radius_mm - result.head_radius_mm, t_f + t_a);
  EXPECT_NEAR(r_art, result.head_radius_mm + (result.lunate_radius_mm - result.head_radius_mm) * t_f / (t_f + t_a), 0.25);
  EXPECT_GT(r.femoral.holes_filled, 0u);
  const double slack = request.options.min_thickness_mm + 1e-9;
  for (const Vec3& v : m.tissue("acetabular_cartilage").vertices) EXPECT_GE(v.norm(), r_art - slack);
  // The sphere fits this joint: its bones come within the minimum of it over under 1 % of each layer.
  EXPECT_LT(r.femoral.overlap_area_mm2, 0.01 * r.femoral.covered_area_mm2);
  EXPECT_LT(r.acetabular.overlap_area_mm2, 0.01 * r.acetabular.covered_area_mm2);

  // Apart from each other and the bones (the shared bone interfaces aside); tolerance as on the
  // generated hips: 0.1 mm minimum layer plus the chord sagitta of the meshes (~1.5 mm edges on a
  // 23 mm sphere: 0.01 mm), 0.2 mm.
  std::set<std::tuple<double, double, double>> shared;
  for (const TriMesh* bone : {&bone_f, &bone_p}) {
    for (const Vec3& v : bone->vertices) shared.insert({v.x(), v.y(), v.z()});
  }
  const auto& ac = m.tissue("acetabular_cartilage");
  const auto& lab = m.tissue("labrum");
  EXPECT_EQ(vertices_inside(fc, bone_p, shared, 0.2), 0u);
  EXPECT_EQ(vertices_inside(fc, ac, shared, 0.2), 0u);
  EXPECT_EQ(vertices_inside(ac, bone_f, shared, 0.2), 0u);
  EXPECT_EQ(vertices_inside(ac, fc, shared, 0.2), 0u);
  // Touching the bone (within the sphericity tolerance, as the synthesis places it), not inside.
  EXPECT_EQ(vertices_inside(lab, bone_f, shared, literature::kSphericityToleranceMm), 0u);
  // On the rim's face, touching it (the sphericity tolerance: anatomy/soft_tissue.h), not inside.
  EXPECT_EQ(vertices_inside(lab, bone_p, shared, 0.1), 0u);
  EXPECT_EQ(vertices_inside(lab, fc, shared, 0.2), 0u);
  EXPECT_EQ(vertices_inside(lab, ac, shared, 0.2), 0u);

  // The folder, read back.
  const fs::path dir = kTissueScratch / "lhdl";
  fs::create_directories(kTissueScratch);
  write_soft_tissue_model(result, kLhdl + "femur_r.ply", kLhdl + "pelvis_no_sacrum.ply", dir);
  EXPECT_TRUE(fs::exists(dir / "soft_tissue.md"));
  const geometry::HipModel back = geometry::load_hip_model(dir);
  for (const char* name : geometry::kHipTissueNames) {
    EXPECT_EQ(back.tissue(name).num_vertices(), m.tissue(name).num_vertices()) << name;
    EXPECT_EQ(back.tissue(name).num_triangles(), m.tissue(name).num_triangles()) << name;
  }
  EXPECT_NEAR(back.hjc_mm.norm(), 0.0, 1e-12);
  EXPECT_NEAR(back.neck_axis.dot(m.neck_axis), 1.0, 1e-9);
  // model.json: a right hip (a left one is mirrored), the measured angles recorded.
  std::ifstream in(dir / "model.json");
  const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"handedness\": \"right\""), std::string::npos);
  EXPECT_NE(json.find("\"measured\""), std::string::npos);
}

// Whether the ray from `origin` along `direction` crosses the mesh (contact/ray_triangle.h's
// exact crossing test, triangle by triangle).
bool ray_crosses(const TriMesh& mesh, const Vec3& origin, const Vec3& direction) {
  return std::any_of(mesh.triangles.begin(), mesh.triangles.end(), [&](const auto& tri) {
    auto at = [&](int k) { return Vec3(mesh.vertices[static_cast<std::size_t>(tri[static_cast<std::size_t>(k)])] - origin); };
    return contact::ray_triangle_crossing(direction, at(0), at(1), at(2)).hit;
  });
}

TEST(SoftTissueModel, TheRealSocketsCartilageIsAHorseshoeOffTheFossa) {
  // The lunate patch found on these bones reaches over the fossa floor; the bone deeper than the
  // articular sphere plus the thickest cartilage (literature::kAcetabularCartilageMaxThicknessMm)
  // is the fossa and stays bare, the rest one piece with one outline.
  const SoftTissueModel result = lhdl_model();
  const anatomy::SoftTissueReport& r = result.report;
  anatomy::SoftTissueOptions whole_patch;  // the rule off: the whole lunate patch, fossa floor included
  whole_patch.fossa_depth_mm = std::numeric_limits<double>::infinity();
  const SoftTissueModel before = lhdl_model(whole_patch);
  const anatomy::SoftTissueReport& b = before.report;
  std::printf("LHDL acetabular: %.0f mm2 %.2f-%.2f mm (mean %.2f, %.0f mm3) without the fossa rule; %.0f mm2 %.2f-%.2f mm "
              "(mean %.2f, %.0f mm3) with it: fossa %.0f mm2, opened towards the notch %.0f mm2 (%d holes); labrum %d "
              "sections, %d pieces, ring %d\n",
              b.acetabular.covered_area_mm2, b.acetabular.min_thickness_mm, b.acetabular.max_thickness_mm,
              b.acetabular.mean_thickness_mm, b.acetabular.volume_mm3, r.acetabular.covered_area_mm2,
              r.acetabular.min_thickness_mm, r.acetabular.max_thickness_mm, r.acetabular.mean_thickness_mm,
              r.acetabular.volume_mm3, r.fossa_area_mm2, r.fossa_opening_area_mm2, r.fossa_holes_opened,
              r.labrum_sections, r.labrum_pieces, r.labrum_closed_ring ? 1 : 0);
  EXPECT_EQ(b.fossa_area_mm2, 0.0);
  // The same articular sphere: it is measured on the whole patch.
  EXPECT_EQ(r.articular_radius_mm, b.articular_radius_mm);
  // Without the rule the layer runs over the fossa floor, thicker than any cartilage; with it the
  // layer is nowhere thicker than the rule allows, and smaller by at least the fossa.
  EXPECT_GT(b.acetabular.max_thickness_mm, literature::kAcetabularCartilageMaxThicknessMm);
  EXPECT_LE(r.acetabular.max_thickness_mm, literature::kAcetabularCartilageMaxThicknessMm + 1e-9);
  EXPECT_GT(r.fossa_area_mm2, 0.0);
  EXPECT_LT(r.acetabular.covered_area_mm2, b.acetabular.covered_area_mm2 - r.fossa_area_mm2 + 1e-6);
  EXPECT_GT(r.acetabular.covered_area_mm2, 1000.0);
  // One piece with one outline: a closed surface of one part with Euler characteristic 2 (an
  // extruded patch with a hole would be a torus, 0).
  const geometry::HipModel& m = result.model;
  const geometry::MeshReport check = geometry::check_mesh(m.tissue("acetabular_cartilage"));
  EXPECT_TRUE(check.watertight_manifold);
  EXPECT_EQ(check.connected_components, 1u);
  EXPECT_EQ(static_cast<long>(check.num_vertices) - static_cast<long>(check.num_edges) +
                static_cast<long>(check.num_triangles), 2);
  // The deepest bone the whole patch covered (its thickest layer; the segmentation's fossa runs on
  // deeper beyond the patch) is bare now: no acetabular cartilage on its ray from the HJC (the
  // origin).
  const TriMesh& whole_layer = before.model.tissue("acetabular_cartilage");
  const std::vector<double>& thickness = whole_layer.vertex_fields.at("thickness_mm");
  const auto thickest = static_cast<std::size_t>(std::max_element(thickness.begin(), thickness.end()) - thickness.begin());
  const Vec3 deepest_ray = whole_layer.vertices[thickest].normalized();
  EXPECT_NEAR(thickness[thickest], b.acetabular.max_thickness_mm, 1e-9);
  EXPECT_TRUE(ray_crosses(whole_layer, Vec3::Zero(), deepest_ray));
  EXPECT_FALSE(ray_crosses(m.tissue("acetabular_cartilage"), Vec3::Zero(), deepest_ray));
}

#ifdef HIPFAI_WITH_FEM
TEST(SoftTissueModel, TheRealHipMeshesIntoValidTaggedHexahedraAtEveryLevel) {
  // The FE volume mesh of the synthesised layers (hexahedra through the thickness along the rays
  // from the HJC): positive Jacobians, every tissue, and the surfaces the FE model bonds and
  // brings into contact, at each FE level.
  const SoftTissueModel result = lhdl_model();
  EXPECT_EQ(result.model.soft_tissue, geometry::SoftTissueSource::kSynthesised);
  for (const FeLevel level : kFeLevels) {
    SCOPED_TRACE(to_string(level));
    const geometry::HipVolumeMesh volume = geometry::build_hip_volume_mesh(result.model, fem::hip_volume_options(level));
    std::printf("%s: %zu hexahedra, min scaled Jacobian %.2f\n", to_string(level), volume.mesh.hexes.size(),
                volume.min_scaled_jacobian);
    EXPECT_GT(volume.min_scaled_jacobian, 0.0);
    // Every piece of every tissue is meshed: the hexahedra's volume is the tissue's (the labrum
    // comes in two pieces, open at the notch and where the neck passes under the rim).
    std::map<geometry::VolumeTag, double> tissue_hex_volume;
    for (std::size_t h = 0; h < volume.mesh.hexes.size(); ++h) {
      tissue_hex_volume[volume.mesh.hex_tags[h]] += geometry::test_support::hex_volume(volume.mesh, volume.mesh.hexes[h]);
    }
    for (const auto tag : {geometry::VolumeTag::kFemoralCartilage, geometry::VolumeTag::kAcetabularCartilage,
                           geometry::VolumeTag::kLabrum}) {
      const double surface = geometry::signed_volume(result.model.tissue(geometry::to_string(tag)));
      std::printf("  %s: %.1f mm3 of hexahedra, %.1f mm3 enclosed by its surface\n", geometry::to_string(tag),
                  tissue_hex_volume[tag], surface);
      // Within 10 %: the columns' chords and the tapered edges blunted to the mesher's minimum
      // thickness (measured 7 % at coarse, 2.5 % at fine); a piece left out would cost more.
      EXPECT_NEAR(tissue_hex_volume[tag], surface, 0.1 * surface) << geometry::to_string(tag);
    }
    // The labrum's two pieces each: a labrum hexahedron belongs to the piece nearest its centroid.
    const std::vector<TriMesh> labrum_pieces = geometry::connected_parts(result.model.tissue("labrum"));
    ASSERT_EQ(labrum_pieces.size(), 2u);
    std::vector<double> piece_hex_volume(labrum_pieces.size(), 0.0);
    for (std::size_t h = 0; h < volume.mesh.hexes.size(); ++h) {
      if (volume.mesh.hex_tags[h] != geometry::VolumeTag::kLabrum) continue;
      Vec3 centroid = Vec3::Zero();
      for (const auto n : volume.mesh.hexes[h]) centroid += volume.mesh.vertices[static_cast<std::size_t>(n)] / 8.0;
      std::size_t nearest = 0;
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < labrum_pieces.size(); ++k) {
        for (const Vec3& x : labrum_pieces[k].vertices) {
          if ((x - centroid).squaredNorm() < best) {
            best = (x - centroid).squaredNorm();
            nearest = k;
          }
        }
      }
      piece_hex_volume[nearest] += geometry::test_support::hex_volume(volume.mesh, volume.mesh.hexes[h]);
    }
    for (std::size_t k = 0; k < labrum_pieces.size(); ++k) {
      const double enclosed = geometry::signed_volume(labrum_pieces[k]);
      std::printf("  labrum piece %zu: %.1f mm3 of hexahedra, %.1f mm3 enclosed\n", k + 1, piece_hex_volume[k], enclosed);
      // A piece left out would have none. Its 7 mm section's tip, blunted to the mesher's minimum
      // thickness, weighs most on the smaller piece at the coarsest columns (measured +12 %, +6 %,
      // +3 % at coarse, default, fine): within 15 %, and 5 % at fine.
      EXPECT_NEAR(piece_hex_volume[k], enclosed, (level == FeLevel::kFine ? 0.05 : 0.15) * enclosed)
          << "labrum piece " << k + 1;
    }
    std::map<geometry::VolumeTag, std::size_t> hexes;
    std::map<geometry::SurfaceTag, std::size_t> quads;
    for (const auto tag : volume.mesh.hex_tags) ++hexes[tag];
    for (const auto tag : volume.mesh.quad_tags) ++quads[tag];
    for (const auto tag : {geometry::VolumeTag::kFemoralCartilage, geometry::VolumeTag::kAcetabularCartilage,
                           geometry::VolumeTag::kLabrum}) {
      EXPECT_GT(hexes[tag], 0u) << geometry::to_string(tag);
    }
    for (const auto tag : {geometry::SurfaceTag::kFemoralCartilageArticular, geometry::SurfaceTag::kFemoralCartilageBonded,
                           geometry::SurfaceTag::kAcetabularCartilageArticular,
                           geometry::SurfaceTag::kAcetabularCartilageBonded, geometry::SurfaceTag::kLabrumArticular,
                           geometry::SurfaceTag::kLabrumBonded}) {
      EXPECT_GT(quads[tag], 0u) << geometry::to_string(tag);
    }
  }
}
#endif

TEST(SoftTissueModel, AMirroredHipGivesTheSameModel) {
  // The LHDL bones mirrored through a sagittal plane are a left hip; it is mirrored back into a
  // right one for the work, so its tissues match the right hip's.
  const TriMesh femur = geometry::read_mesh(kLhdl + "femur_r.ply");
  const TriMesh pelvis = geometry::read_mesh(kLhdl + "pelvis_no_sacrum.ply");
  const Eigen::Affine3d mirror = anatomy::reflection(Vec3::Zero(), Vec3::UnitX());
  const TriMesh femur_l = anatomy::reflected(femur, mirror), pelvis_l = anatomy::reflected(pelvis, mirror);
  SoftTissueModelRequest right, left;
  right.assessment.femur = &femur;
  right.assessment.pelvis = &pelvis;
  left.assessment.femur = &femur_l;
  left.assessment.pelvis = &pelvis_l;
  const SoftTissueModel a = build_soft_tissue_model(right), b = build_soft_tissue_model(left);
  EXPECT_EQ(b.side, anatomy::Side::kLeft);
  std::printf("right/left: femoral %.1f/%.1f mm2, acetabular %.1f/%.1f mm2, labrum %.1f/%.1f mm3\n",
              a.report.femoral.covered_area_mm2, b.report.femoral.covered_area_mm2, a.report.acetabular.covered_area_mm2,
              b.report.acetabular.covered_area_mm2, a.report.labrum_volume_mm3, b.report.labrum_volume_mm3);
  // The HJC maps back to the mirror of the right hip's; the frames are found on the mirrored bones
  // the same way, up to where the head's Hough vote starts on its fixed grid (femur_landmarks.h):
  // 1 % of area and volume, 0.1 mm of the HJC.
  EXPECT_LT((b.hjc_input_mm - mirror * a.hjc_input_mm).norm(), 0.1);
  EXPECT_NEAR(b.report.femoral.covered_area_mm2, a.report.femoral.covered_area_mm2, 0.01 * a.report.femoral.covered_area_mm2);
  EXPECT_NEAR(b.report.acetabular.covered_area_mm2, a.report.acetabular.covered_area_mm2,
              0.01 * a.report.acetabular.covered_area_mm2);
  EXPECT_NEAR(b.report.labrum_volume_mm3, a.report.labrum_volume_mm3, 0.01 * a.report.labrum_volume_mm3);
  EXPECT_NEAR(b.model.neck_axis.dot(a.model.neck_axis), 1.0, 1e-3);
}

// build_soft_tissue_model on these bones throws one line naming `expected`.
void expect_one_line_error(const TriMesh& femur, const std::string& femur_name, const TriMesh& pelvis,
                           const std::string& expected) {
  SoftTissueModelRequest request;
  request.assessment.femur = &femur;
  request.assessment.femur_name = femur_name;
  request.assessment.pelvis = &pelvis;
  try {
    build_soft_tissue_model(request);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(SoftTissueModel, BonesWithoutAHeadAreAOneLineError) {
  fs::create_directories(kTissueScratch);
  const TriMesh pelvis = geometry::read_mesh(kLhdl + "pelvis_no_sacrum.ply");
  TriMesh square;
  square.vertices = {Vec3(0, 0, 0), Vec3(40, 0, 0), Vec3(40, 40, 0), Vec3(0, 40, 0)};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  expect_one_line_error(square, "square.obj", pelvis, "no femoral head");
}

// Bones that already intersect in the neutral pose (the femur pushed 8 mm into the acetabulum) make
// the tissues meaningless: a one-line error, no folder.
TEST(SoftTissueModel, IntersectingBonesAreAOneLineError) {
  fs::create_directories(kTissueScratch);
  const TriMesh pelvis = geometry::read_mesh(kLhdl + "pelvis_no_sacrum.ply");
  TriMesh femur = geometry::read_mesh(kLhdl + "femur_r.ply");
  for (Vec3& v : femur.vertices) v += Vec3(8.0, 0.0, 0.0);  // medial for this right hip (CT +x is left)
  expect_one_line_error(femur, "femur_r.ply", pelvis, "intersect");
}

}  // namespace
}  // namespace hipfai::studies
