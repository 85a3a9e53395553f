// The patient-specific assessment end to end: known truth on generated hips (their frame given as
// their model.json), invariance under rigid motions and mirroring into a left hip, the real LHDL
// bones from the frame found on them, the cam resection, the output folder, and the one-line errors.
#include "studies/pipeline/assessment.h"

#include "anatomy/frame_file.h"
#include "core/error.h"
#include "geometry/hip_generator.h"
#include "geometry/hip_measure.h"
#include "geometry/hip_model.h"
#include "geometry/mesh_io.h"
#include "studies/pipeline/assessment_report.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

namespace hipfai::studies {
namespace {

using geometry::Vec3;
namespace fs = std::filesystem;

const fs::path kAssessmentScratch = fs::path(HIPFAI_BINARY_DIR) / "test-scratch" / "assessment";
const std::string kRealHip = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";

// A generated hip (bones only) with its model.json, generated once per (ce, alpha).
struct GeneratedHip {
  geometry::TriMesh femur, pelvis;
  anatomy::UserFrame frame;
  double ce_deg = 0.0, alpha_deg = 0.0;
};

const GeneratedHip& generated(double ce, double alpha) {
  static std::map<std::pair<double, double>, GeneratedHip> cache;
  auto it = cache.find({ce, alpha});
  if (it != cache.end()) return it->second;
  geometry::HipParameters p;
  p.ce_deg = ce;
  p.alpha_deg = alpha;
  p.edge_mm = 3.0;
  const geometry::HipModel model = geometry::generate_hip(p).model;
  // One folder per process: CTest runs this file's tests in parallel processes.
  const fs::path dir = kAssessmentScratch / ("hip-" + std::to_string(static_cast<int>(ce)) + "-" + std::to_string(static_cast<int>(alpha)) +
                                   "-" + std::to_string(::getpid()));
  geometry::write_hip_model(model, dir);
  GeneratedHip hip;
  hip.femur = model.tissue("femur_bone");
  hip.pelvis = model.tissue("acetabular_bone");
  hip.frame = anatomy::read_frame_file(dir / "model.json");
  fs::remove_all(dir);
  hip.ce_deg = model.measured_ce_deg;
  hip.alpha_deg = model.measured_alpha_notzli_deg;
  return cache.emplace(std::make_pair(ce, alpha), hip).first->second;
}

AssessmentResult assess(const geometry::TriMesh& femur, const geometry::TriMesh& pelvis,
                        std::optional<anatomy::UserFrame> frame = std::nullopt) {
  AssessmentRequest request;
  request.femur = &femur;
  request.pelvis = &pelvis;
  request.frame = frame;
  return assess_hip(request);
}

Eigen::Affine3d random_motion(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.linear() = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
  t.translation() = Vec3(u(rng), u(rng), u(rng)) * 200.0;
  return t;
}

std::vector<double> rom_values(const AssessmentResult& r) {
  std::vector<double> values;
  for (const auto* o : r.before.rom.motions()) values.push_back(o->limit ? o->limit->angle_deg : -1.0);
  return values;
}

TEST(Assessment, GeneratedHipsMeasureBackTheirCeAndAlpha) {
  // Bones only, the frame given as the model.json. CE (the bony rim) within 1 deg of the
  // generator's. Alpha: the generator measures it on bone and cartilage together (its articular
  // surface); the bone alone leaves its sphere elsewhere, so the reference here is the generator's
  // own method (geometry::measure_alpha_angle, default options) on the bone alone: the
  // assessment's real-bone method (landmark sphere, 3-RMS tolerance, longest articular run) must
  // agree with it within 1 deg on these clean bones.
  for (const auto& [ce, alpha] : std::vector<std::pair<double, double>>{{20.0, 80.0}, {40.0, 40.0}}) {
    const GeneratedHip& hip = generated(ce, alpha);
    const AssessmentResult r = assess(hip.femur, hip.pelvis, hip.frame);
    EXPECT_EQ(r.side, anatomy::Side::kRight);
    EXPECT_NEAR(r.before.measures.lateral_ce.ce_deg, hip.ce_deg, 1.0) << ce << "/" << alpha;
    const auto reference = geometry::measure_alpha_angle({&hip.femur}, Vec3::Zero(), *hip.frame.neck_axis,
                                                         Vec3::UnitZ(), Vec3::UnitY());
    EXPECT_NEAR(r.before.measures.alpha.alpha_deg, reference.alpha_deg, 1.0) << ce << "/" << alpha;
    for (const auto* o : r.before.rom.motions()) EXPECT_TRUE(o->limit.has_value()) << o->reason;
  }
}

TEST(Assessment, RigidMotionsAndMirroringChangeNothing) {
  const GeneratedHip& hip = generated(20.0, 80.0);
  const AssessmentResult reference = assess(hip.femur, hip.pelvis, hip.frame);
  std::mt19937 rng(11);
  for (const bool mirrored : {false, true}) {
    Eigen::Affine3d t = random_motion(rng);
    if (mirrored) t = t * anatomy::reflection(Vec3(3.0, -2.0, 1.0), Vec3(1.0, 0.2, -0.1).normalized());
    const AssessmentResult r = assess(anatomy::transformed(hip.femur, t), anatomy::transformed(hip.pelvis, t),
                                      anatomy::transformed(hip.frame, t));
    EXPECT_EQ(r.side, mirrored ? anatomy::Side::kLeft : anatomy::Side::kRight);
    EXPECT_NEAR(r.before.measures.lateral_ce.ce_deg, reference.before.measures.lateral_ce.ce_deg, 0.1);
    EXPECT_NEAR(r.before.measures.alpha.alpha_deg, reference.before.measures.alpha.alpha_deg, 0.1);
    EXPECT_NEAR(r.before.measures.acetabular_version_deg, reference.before.measures.acetabular_version_deg, 0.1);
    const auto a = rom_values(r), b = rom_values(reference);
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 0.01) << i << (mirrored ? " mirrored" : "");
    // Frames come back in the input's coordinates: the moved reference frames.
    const auto pelvis = r.frame_to_input(r.pelvis_frame);
    EXPECT_LT((pelvis.anterior - t.linear() * reference.pelvis_frame.anterior).norm(), 1e-9);
    EXPECT_LT((r.point_to_input(r.hjc_mm) - t * reference.hjc_mm).norm(), 1e-6);
  }
}

TEST(Assessment, TheRealBonesFromTheFrameFoundOnThem) {
  const geometry::TriMesh femur = geometry::read_mesh(kRealHip + "femur_r.ply");
  const geometry::TriMesh pelvis = geometry::read_mesh(kRealHip + "pelvis_no_sacrum.ply");
  const AssessmentResult r = assess(femur, pelvis);
  EXPECT_EQ(r.side, anatomy::Side::kRight);
  // hip.json's femoral head fit (an algebraic fit of the vertices within 26 mm of the HJC).
  EXPECT_LT((r.hjc_mm - Vec3(143.33, 243.35, -432.43)).norm(), 1.5);
  EXPECT_TRUE(r.femur_landmarks.has_distal);
  const auto& m = r.before.measures;
  // Adult values (Tannast et al. 2007): a measure far outside them means a frame gone wrong.
  EXPECT_GT(m.lateral_ce.ce_deg, 20.0);
  EXPECT_LT(m.lateral_ce.ce_deg, 45.0);
  EXPECT_GT(m.alpha.alpha_deg, 30.0);
  EXPECT_LT(m.alpha.alpha_deg, 70.0);
  EXPECT_GT(m.neck_shaft_deg, 115.0);
  EXPECT_LT(m.neck_shaft_deg, 145.0);
  ASSERT_TRUE(m.femoral_version_deg.has_value());
  // Every clinical motion reached, flexion the largest of them about the lateral axis.
  for (const auto* o : r.before.rom.motions()) EXPECT_TRUE(o->limit.has_value()) << o->reason;
  EXPECT_GT(r.before.rom.flexion.limit->angle_deg, r.before.rom.extension.limit->angle_deg);

  // The same bones mirrored into a left hip (and moved): the same measures and ranges.
  std::mt19937 rng(5);
  const Eigen::Affine3d t = random_motion(rng) * anatomy::reflection(Vec3(240.0, 250.0, -400.0), Vec3::UnitX());
  const AssessmentResult left = assess(anatomy::transformed(femur, t), anatomy::transformed(pelvis, t));
  EXPECT_EQ(left.side, anatomy::Side::kLeft);
  EXPECT_NEAR(left.before.measures.lateral_ce.ce_deg, m.lateral_ce.ce_deg, 0.1);
  EXPECT_NEAR(left.before.measures.alpha.alpha_deg, m.alpha.alpha_deg, 0.1);
  const auto a = rom_values(left), b = rom_values(r);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 0.01) << i;

  // The output folder, whole.
  const fs::path out = kAssessmentScratch / ("lhdl-" + std::to_string(::getpid()));
  write_assessment(r, {"femur_r.ply", "pelvis_no_sacrum.ply", "", ""}, out);
  std::ifstream file(out / "assessment.json");
  const nlohmann::json j = nlohmann::json::parse(file);
  EXPECT_EQ(j["side"], "right");
  for (const char* key : {"lateral_ce_deg", "acetabular_inclination_deg", "acetabular_version_deg", "alpha_deg",
                          "alpha_max_deg", "alpha_max_clock", "neck_shaft_deg", "femoral_version_deg"}) {
    EXPECT_TRUE(j["measures"].contains(key)) << key;
  }
  for (const char* key : {"flexion", "extension", "abduction", "adduction", "internal_rotation", "external_rotation",
                          "internal_rotation_at_90_flexion", "external_rotation_at_90_flexion",
                          "fadir_internal_rotation", "faber"}) {
    EXPECT_TRUE(j["rom_deg"][key].is_number()) << key;
  }
  for (const char* name : {"report.md", "pelvis.vtp", "femur.vtp", "coronal_ce.svg", "notzli_alpha.svg",
                           "impingement_clock.svg", "rom.svg", "alpha_profile.svg"}) {
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
  fs::remove_all(out);
}

TEST(Assessment, ACamResectionBringsAlphaDownAndFreesInternalRotation) {
  const GeneratedHip& hip = generated(20.0, 80.0);
  AssessmentRequest request;
  request.femur = &hip.femur;
  request.pelvis = &hip.pelvis;
  request.frame = hip.frame;
  request.resect_alpha_deg = 50.0;
  const AssessmentResult r = assess_hip(request);
  ASSERT_TRUE(r.after.has_value());
  ASSERT_EQ(r.resections.size(), 1u);
  EXPECT_GT(r.resections[0].removed_volume_mm3, 0.0);
  EXPECT_TRUE(r.resections[0].closed);
  EXPECT_TRUE(r.resections[0].manifold);
  for (const auto& [clock, alpha] : r.after->measures.alpha.profile) {
    if (std::isfinite(alpha)) {
      EXPECT_LE(alpha, 51.0) << "clock " << clock;
    }
  }
  ASSERT_TRUE(r.before.rom.fadir_internal_rotation.limit && r.after->rom.fadir_internal_rotation.limit);
  EXPECT_GT(r.after->rom.fadir_internal_rotation.limit->angle_deg, r.before.rom.fadir_internal_rotation.limit->angle_deg);
}

TEST(Assessment, MeaninglessGeometryIsAOneLineError) {
  const geometry::TriMesh femur = geometry::read_mesh(kRealHip + "femur_r.ply");
  const geometry::TriMesh pelvis = geometry::read_mesh(kRealHip + "pelvis_no_sacrum.ply");
  auto one_line_error = [](const std::function<void()>& f, const std::string& expected) {
    try {
      f();
      ADD_FAILURE() << "no error, expected: " << expected;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(expected), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  };
  // The femur pushed 8 mm into the acetabulum: the bones intersect in the neutral pose.
  geometry::TriMesh pushed = femur;
  for (Vec3& v : pushed.vertices) v += Vec3(8.0, 0.0, 0.0);  // medial for this right hip (CT +x is left)
  one_line_error([&] { assess(pushed, pelvis); }, "intersect");
  // Half a pelvis without a frame.
  const geometry::TriMesh half = [&] {
    geometry::TriMesh h;
    std::vector<std::int32_t> map(pelvis.num_vertices(), -1);
    for (std::size_t i = 0; i < pelvis.num_vertices(); ++i) {
      if (pelvis.vertices[i].x() < 240.0) {
        map[i] = static_cast<std::int32_t>(h.vertices.size());
        h.vertices.push_back(pelvis.vertices[i]);
      }
    }
    for (const auto& t : pelvis.triangles) {
      if (map[t[0]] >= 0 && map[t[1]] >= 0 && map[t[2]] >= 0) h.triangles.push_back({map[t[0]], map[t[1]], map[t[2]]});
    }
    return h;
  }();
  one_line_error([&] { assess(femur, half); }, "--frame");
  // A side that contradicts the bones.
  AssessmentRequest request;
  request.femur = &femur;
  request.pelvis = &pelvis;
  request.side = anatomy::Side::kLeft;
  one_line_error([&] { assess_hip(request); }, "lies in the right half");
}

}  // namespace
}  // namespace hipfai::studies
