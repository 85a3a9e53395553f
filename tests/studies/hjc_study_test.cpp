// The HJC cohort (known truth) and the HJC sensitivity study, at test size: the files are written,
// the numbers that must hold by construction do, and the bones-only mode runs on a generated
// hip's bones.
#include "core/error.h"
#include "geometry/hip_generator.h"
#include "geometry/mesh_io.h"
#include "studies/hjc_cohort.h"
#include "studies/hjc_study.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <unistd.h>

namespace hipfai::studies {
namespace {

std::filesystem::path temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("hipfai_hjc_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return dir;
}

const HjcCohortRow& row(const HjcCohortResult& r, const std::string& surface, const std::string& perturbation,
                        const std::string& method) {
  for (const auto& x : r.rows) {
    if (x.surface == surface && x.perturbation == perturbation && x.method == method) return x;
  }
  throw Error("no row " + surface + "/" + perturbation + "/" + method);
}

TEST(HjcCohort, KnownTruthTableAtTestSize) {
  HjcCohortOptions options;
  options.out_dir = temp_dir("cohort");
  options.ce_deg = {20.0};
  options.edge_mm = 3.5;
  options.replicates = 1;
  options.include_fine = false;
  options.progress = false;
  const HjcCohortResult result = run_hjc_cohort(options);
  for (const char* file : {"cohort.csv", "cohort_summary.csv", "cohort.md", "cohort.h5"}) {
    EXPECT_TRUE(std::filesystem::exists(options.out_dir / file)) << file;
  }
  // Clean articular surfaces are exact spheres about the truth (to the mesh: vertices on the sphere).
  for (const char* m : {"femoralheadsphere", "acetabulumsphere", "doublesphere"}) {
    EXPECT_LT(row(result, "articular", "clean", m).error_mm, 0.02) << m;
  }
  // An uneven joint space pushes the socket out by A (1 + u.e) / 2: its sphere's centre moves by
  // about A / 2 (exactly so on a whole sphere), while the head is untouched.
  const double socket_error = row(result, "articular", "uneven joint space 1.0 mm", "acetabulumsphere").error_mm;
  EXPECT_GT(socket_error, 0.3);
  EXPECT_LT(socket_error, 0.7);
  EXPECT_LT(row(result, "articular", "uneven joint space 1.0 mm", "femoralheadsphere").error_mm, 0.02);
  EXPECT_LT(row(result, "articular", "uneven joint space 1.0 mm", "dref").error_mm, 0.05);
  std::filesystem::remove_all(options.out_dir);
}

TEST(HjcStudy, DepthDifferencesAndBonesOnlyMode) {
  HjcStudyOptions options;
  options.out_dir = temp_dir("study");
  options.subjects = {{20.0, 60.0}};
  options.edge_mm = 3.5;
  options.step_deg = 10.0;
  options.centre_offsets_mm = {5.0};
  options.progress = false;
  const HjcStudyResult result = run_hjc_study(options);
  ASSERT_EQ(result.subjects.size(), 1u);
  const HjcSubjectResult& s = result.subjects.front();
  EXPECT_EQ(s.centres_mm.size(), 5u + 1u + 6u);
  for (const auto& [label, rotations] : s.depths) {
    EXPECT_EQ(rotations.size(), 6u) << label;
    EXPECT_EQ(rotations.at("flexion").angle_deg.size(), 12u) << label;  // 120 deg in 10 deg steps
  }
  for (const char* file : {"report.md", "steps.csv", "results.h5", "fig67_radial.svg", "fig70.svg", "fig71.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(options.out_dir / file)) << file;
  }
  // A 5 mm centre error moves the radial depths far more than the estimates (within ~1 mm) do.
  auto mean_radial_difference = [&](const std::string& label) {
    double sum = 0.0;
    int n = 0;
    for (const auto& [rotation, d] : s.depths.at(label)) {
      const auto& truth = s.depths.at("truth").at(rotation);
      for (std::size_t k = 0; k < d.radial_mm.size(); ++k, ++n) sum += std::abs(d.radial_mm[k] - truth.radial_mm[k]);
    }
    return sum / n;
  };
  EXPECT_GT(mean_radial_difference("truth +Z 5mm"), 3.0 * mean_radial_difference("femoralheadsphere"));

  // Bones-only mode on the same kind of hip's bones.
  geometry::HipParameters parameters;
  parameters.ce_deg = 20.0;
  parameters.alpha_deg = 60.0;
  parameters.edge_mm = 3.5;
  const auto model = geometry::generate_hip(parameters).model;
  const auto bones = temp_dir("bones");
  std::filesystem::create_directories(bones);
  geometry::write_mesh(model.tissue("femur_bone"), bones / "femur.ply");
  geometry::write_mesh(model.tissue("acetabular_bone"), bones / "pelvis.ply");
  HjcStudyOptions bone_options;
  bone_options.out_dir = bones / "out";
  bone_options.femur = bones / "femur.ply";
  bone_options.pelvis = bones / "pelvis.ply";
  bone_options.progress = false;
  const HjcStudyResult bone_result = run_hjc_study(bone_options);
  EXPECT_EQ(bone_result.rom.size(), 5u * 6u);
  for (const auto& r : bone_result.rom) EXPECT_TRUE(std::isfinite(r.rom_deg)) << r.method << " " << r.rotation;
  EXPECT_TRUE(std::filesystem::exists(bone_options.out_dir / "bones.md"));
  std::filesystem::remove_all(options.out_dir);
  std::filesystem::remove_all(bones);
}

TEST(HjcStudy, BadInputIsAnError) {
  HjcStudyOptions options;
  options.out_dir = temp_dir("bad");
  options.femur = "/nonexistent/femur.ply";
  EXPECT_THROW(run_hjc_study(options), Error);
  options.pelvis = "/nonexistent/pelvis.ply";
  EXPECT_THROW(run_hjc_study(options), Error);
  EXPECT_FALSE(std::filesystem::exists(options.out_dir / "bones.md"));
}

}  // namespace
}  // namespace hipfai::studies
