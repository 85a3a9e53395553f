// Hips off the study grid: the generator must mesh every (CE, alpha) of its range, not only the 25
// grid hips. Each hip is checked as the grid hips are (hip_study_grid_test.cpp): every tissue
// closed, manifold, outward, one piece, no degenerate triangle; CE and alpha measured back on the
// meshes within 1 deg; in the neutral pose no femoral vertex inside an acetabular tissue (nor the
// reverse) deeper than the sagitta of the longest edge. Between the grid's CE values the labrum may
// be more than one arc (see generate_and_check).
//
// GeneratorCoincidences (in the suite) generates the hips the generator could not mesh
// ("Impossible to mesh periodic surface", OpenCASCADE's errors), one or two per cause found. The random sweep
// (GeneratorSweep.DISABLED_RandomHips: minutes to hours) runs only on request, through
// scripts/generator-sweep, and writes one CSV row per hip.
#include "core/error.h"
#include "core/literature.h"
#include "geometry/hip_generator.h"
#include "geometry/hip_model.h"
#include "geometry/mesh_check.h"
#include "tests/geometry/mesh_inside.h"
#include "tests/geometry/study_hips.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace hipfai::geometry::test_support {
namespace {

struct HipCheck {
  std::string status = "ok";  // "ok", or what failed
  double ce_measured_deg = std::nan("");
  double alpha_measured_deg = std::nan("");
  bool surfaces_clean = false;
  double deepest_overlap_mm = 0.0;  // deepest vertex of one side inside the other
  double overlap_tolerance_mm = 0.0;
  std::size_t overlapping_vertices = 0;  // deeper than the tolerance
  std::size_t vertices = 0;
  std::size_t labrum_pieces = 0;
  int surface_algorithm = 0;        // the gmsh algorithm that meshed the hip (6 first, then 1, 5)
  std::string mesher_failures;      // what the algorithms tried before it reported
  double seconds = 0.0;
};

// Deepest vertex of `inner` inside the closed surface `outer` (ray parity for the candidates,
// confirmed by the winding number) and how many lie deeper than `tolerance_mm`.
void add_overlap(const TriMesh& inner, const TriMesh& outer, double tolerance_mm, HipCheck& check) {
  const InsideTester parity(outer);
  for (const Vec3& p : inner.vertices) {
    if (!parity.inside(p) || winding_number(outer, p) < 0.5) continue;
    const double depth = distance_to_surface(outer, p);
    if (depth > tolerance_mm) ++check.overlapping_vertices;
    check.deepest_overlap_mm = std::max(check.deepest_overlap_mm, depth);
  }
}

// Generates the hip and measures everything the requirements name; never throws (a generation
// error is the status).
HipCheck generate_and_check(double ce_deg, double alpha_deg, double edge_mm, const HipParameters& base = {}) {
  HipParameters p = base;
  p.ce_deg = ce_deg;
  p.alpha_deg = alpha_deg;
  p.edge_mm = edge_mm;
  HipCheck check;
  HipGeneratorResult result;
  try {
    result = generate_hip(p);
  } catch (const Error& e) {
    check.status = e.what();
    return check;
  }
  const HipModel& model = result.model;
  check.seconds = result.seconds;
  check.surface_algorithm = model.surface_algorithm;
  check.mesher_failures = model.mesher_failures;
  check.surfaces_clean = true;
  double edge = 0.0;
  for (const char* name : kHipTissueNames) {
    const TriMesh& mesh = model.tissue(name);
    const MeshReport report = check_mesh(mesh);
    // The labrum is interrupted at the notch and, where the neck passes under the rim, over the
    // neck's sector: one arc when that sector reaches the notch, more when it does not (two arcs at
    // CE 25; near CE 28 also small remnants between the notch's cut and the sector's).
    const bool labrum = std::string(name) == "labrum";
    if (labrum) check.labrum_pieces = report.connected_components;
    check.surfaces_clean = check.surfaces_clean && report.watertight_manifold && report.outward &&
                           report.degenerate_triangles == 0 &&
                           (labrum ? report.connected_components >= 1 : report.connected_components == 1);
    check.vertices += mesh.vertices.size();
    edge = std::max(edge, longest_edge(mesh));
  }
  const MeasuredAngles m = measure_study_angles(model);
  if (m.ce.status == MeasureStatus::kOk) check.ce_measured_deg = m.ce.ce_deg;
  if (m.alpha.status == MeasureStatus::kOk) check.alpha_measured_deg = m.alpha.alpha_deg;
  // Both sides discretise the same R sphere: a vertex may lie inside the other side by up to the
  // sagitta of the longest chord (see hip_study_grid_test.cpp).
  check.overlap_tolerance_mm = edge * edge / (2.0 * p.articular_radius_mm);
  for (const char* f : {"femur_bone", "femoral_cartilage"}) {
    for (const char* a : {"acetabular_bone", "acetabular_cartilage", "labrum"}) {
      add_overlap(model.tissue(f), model.tissue(a), check.overlap_tolerance_mm, check);
      add_overlap(model.tissue(a), model.tissue(f), check.overlap_tolerance_mm, check);
    }
  }
  std::ostringstream failed;
  if (!check.surfaces_clean) failed << "surface not closed/manifold/outward/clean; ";
  if (!(std::abs(check.ce_measured_deg - ce_deg) <= 1.0)) failed << "CE measured " << check.ce_measured_deg << "; ";
  if (!(std::abs(check.alpha_measured_deg - alpha_deg) <= 1.0)) {
    failed << "alpha measured " << check.alpha_measured_deg << "; ";
  }
  if (check.overlapping_vertices > 0) {
    failed << check.overlapping_vertices << " vertices overlapping in neutral, deepest " << check.deepest_overlap_mm
           << " mm; ";
  }
  if (!failed.str().empty()) check.status = failed.str();
  return check;
}

void expect_clean(const HipCheck& check, const std::string& label) {
  EXPECT_EQ(check.status, "ok") << label;
}

// The cam's near foot (angle from the neck axis where its section re-enters the R sphere) for the
// default cam: alpha - 2 delta, delta by the law of cosines on the section circle (radius rc,
// centre R + h - rc from the HJC) and the R sphere.
double near_foot_offset_deg(const HipParameters& p) {
  const double radius = p.articular_radius_mm, rc = p.cam_radius_mm;
  const double distance = radius + p.cam_height_mm - rc;
  return 2.0 * std::acos((radius * radius + distance * distance - rc * rc) / (2.0 * radius * distance)) * 180.0 /
         std::numbers::pi;
}

// The hips the generator could not mesh, each a coincidence of its construction (see
// hip_generator.cpp): a foot of the cam on a circle of the head about the neck axis, the far foot
// (at alpha) on the cartilage margin (femoral_cartilage_edge_deg, 45 by default: CE 35 / alpha 45
// was the reported failure) or the near foot on the head-neck junction (normal_alpha_deg); the
// former end balls' poles on the cam's clipping cylinder (alpha just above normal_alpha_deg: CE 3.8 / alpha
// 40.024 of the random sweep); a socket's rim cone within 1e-4 deg of a hemisphere. Each stopped
// with gmsh's "Impossible to mesh periodic surface" or OpenCASCADE's "Intersection operation
// cannot be performed".
TEST(GeneratorCoincidences, CamFeetCapPolesAndFlatRimsGenerate) {
  const HipParameters defaults;
  expect_clean(generate_and_check(35.0, defaults.femoral_cartilage_edge_deg, 2.0), "CE 35 / alpha on the margin, 2 mm");
  HipParameters margin_47;
  margin_47.femoral_cartilage_edge_deg = 47.0;
  expect_clean(generate_and_check(5.0, 47.0, 3.0, margin_47), "CE 5 / alpha 47 on a 47 deg margin, 3 mm");
  const double junction_alpha = defaults.normal_alpha_deg + near_foot_offset_deg(defaults);
  expect_clean(generate_and_check(25.0, junction_alpha, 3.0), "CE 25 / near foot on the junction, 3 mm");
  expect_clean(generate_and_check(3.805950308, 40.02431821, 2.0), "CE 3.8 / alpha 40.024, 2 mm");
  expect_clean(generate_and_check(defaults.hemisphere_ce_deg + 5e-5, 60.0, 3.0), "CE 5e-5 deg off the hemisphere, 3 mm");
}

// The cam's end balls are tangent to its sweep along the end sections' circles; fused as three
// solids, OpenCASCADE returned for isolated doubles alpha a cam with vertex tolerances of
// millimetres (hip_generator.cpp), and the femur then stopped. Found by `estimator sample`: its hip
// train_144 (gmsh: "Impossible to mesh periodic surface") and CE 5.76 / alpha 56.61 ("BRep_Tool::
// TopoDS_Vertex hasn't gp_Pnt"), both at 2 mm; alpha alone decides (1e-14 deg off, they
// generated). Both sockets are shallow, meshed by the MeshAdapt fallback: 15-25 s each.
TEST(GeneratorCoincidences, CamEndBallsTangentToItsSweepGenerate) {
  expect_clean(generate_and_check(6.401440668851137, 73.31368003040552, 2.0), "CE 6.40 / alpha 73.314, 2 mm");
  expect_clean(generate_and_check(5.757421578288519, 56.61436601558189, 2.0), "CE 5.76 / alpha 56.614, 2 mm");
}

// Retroverted necks: the seam of the femoral spheres came within the head's band of the R sphere
// (between the junction and the cartilage margin) and crossed it twice, and OpenCASCADE's booleans
// left faces gmsh could not mesh, failed, or did not finish (hip_generator.cpp). Two hips of
// `estimator sample --design sobol --seed 1 --vary ce,alpha,neck_shaft_angle,femoral_anteversion`
// ("Fuse operation cannot be performed"; "Identical points in triangulation", then no end in 200 s)
// and one of a scan of femoral version at CCD 118 ("Impossible to mesh periodic surface"), the
// seam 35.6, 38.7 and 39.8 deg from the neck axis, inside the junction's 40.
TEST(GeneratorCoincidences, RetrovertedNecksGenerate) {
  struct Neck {
    double ce, alpha, neck_shaft, version;
  };
  for (const Neck& neck : {Neck{16.772534418851137, 63.78243003040552, 141.94691098295152, -9.88434067927301},
                           Neck{25.210034418851137, 46.28243003040552, 130.63441098295152, -6.759340679273009},
                           Neck{30.0, 55.0, 118.0, -4.7091714418829}}) {
    HipParameters base;
    base.neck_shaft_angle_deg = neck.neck_shaft;
    base.femoral_anteversion_deg = neck.version;
    std::ostringstream label;
    label << "CE " << neck.ce << " / alpha " << neck.alpha << " / CCD " << neck.neck_shaft << " / version "
          << neck.version << ", 2 mm";
    expect_clean(generate_and_check(neck.ce, neck.alpha, 2.0, base), label.str());
  }
}

// Deep sockets whose rim reached the femoral neck in the neutral pose: the labrum was cut back
// over the neck's sector, the acetabular cartilage and the bone's rim were not, and stood 0.45-3.1
// mm inside the femur bone (hip_generator.cpp). A hip of the sensitivity study (CE 40 pure pincer,
// femoral version 20; and with hemisphere_ce_deg 15) and one of `scripts/generator-sweep --neck
// --seed 3` (CE 43.7, CCD 119.4, version 26.5). Each must now be apart in the neutral pose.
TEST(GeneratorCoincidences, DeepSocketsStopShortOfTheNeck) {
  HipParameters version_20;
  version_20.femoral_anteversion_deg = 20.0;
  expect_clean(generate_and_check(40.0, 40.0, 2.0, version_20), "CE 40 / alpha 40 / version 20, 2 mm");
  HipParameters shallow_hemisphere;
  shallow_hemisphere.hemisphere_ce_deg = 15.0;
  expect_clean(generate_and_check(40.0, 40.0, 2.0, shallow_hemisphere), "CE 40 / alpha 40 / hemisphere CE 15, 2 mm");
  HipParameters varus_anteverted;
  varus_anteverted.neck_shaft_angle_deg = 119.4030345;
  varus_anteverted.femoral_anteversion_deg = 26.47750761;
  expect_clean(generate_and_check(43.68839479, 65.52682913, 2.0, varus_anteverted),
               "CE 43.7 / alpha 65.5 / CCD 119.4 / version 26.5, 2 mm");
}

// One value of an environment variable, or the default.
double env_number(const char* name, double fallback) {
  const char* text = std::getenv(name);
  return text != nullptr && *text != '\0' ? std::atof(text) : fallback;
}

// A uniform value in [lo, hi] from the 53 high bits of a 64-bit Mersenne Twister draw (the same
// on every platform, unlike std::uniform_real_distribution).
double uniform(std::mt19937_64& engine, double lo, double hi) {
  const double unit = static_cast<double>(engine() >> 11) * 0x1.0p-53;
  return lo + unit * (hi - lo);
}

// The random sweep: HIPFAI_SWEEP_HIPS hips (default 100), CE uniform in [0, 45] and alpha in
// [40, 80] (real values, from HIPFAI_SWEEP_SEED, default 1), at HIPFAI_SWEEP_EDGE_MM (default 2);
// one CSV row per hip to HIPFAI_SWEEP_CSV (default generator_sweep.csv), written as it goes. With
// HIPFAI_SWEEP_NECK=1 each hip also draws its neck-shaft angle in [110, 146.2] and femoral version
// in [-10, 40] deg (the ranges `estimator sample --vary` takes) from a second engine, so hip k keeps
// the CE and alpha of the sweep without it.
TEST(GeneratorSweep, DISABLED_RandomHips) {
  const int hips = static_cast<int>(env_number("HIPFAI_SWEEP_HIPS", 100));
  const double edge_mm = env_number("HIPFAI_SWEEP_EDGE_MM", 2.0);
  const auto seed = static_cast<std::uint64_t>(env_number("HIPFAI_SWEEP_SEED", 1));
  const char* csv_path = std::getenv("HIPFAI_SWEEP_CSV");
  std::ofstream csv(csv_path != nullptr ? csv_path : "generator_sweep.csv");
  ASSERT_TRUE(csv) << "cannot write the sweep CSV";
  csv << "hip,ce_deg,alpha_deg,edge_mm,status,ce_measured_deg,alpha_measured_deg,ce_error_deg,alpha_error_deg,"
         "surfaces_clean,labrum_pieces,deepest_overlap_mm,overlap_tolerance_mm,vertices,seconds,surface_algorithm,"
         "mesher_failures,neck_shaft_angle_deg,femoral_anteversion_deg\n";
  const bool vary_neck = env_number("HIPFAI_SWEEP_NECK", 0.0) != 0.0;
  std::mt19937_64 engine(seed);
  std::seed_seq neck_seed{seed, std::uint64_t{1}};
  std::mt19937_64 neck_engine(neck_seed);
  for (int k = 0; k < hips; ++k) {
    const double ce = uniform(engine, 0.0, 45.0);
    const double alpha = uniform(engine, 40.0, 80.0);
    HipParameters base;
    if (vary_neck) {
      base.neck_shaft_angle_deg = uniform(neck_engine, 110.0, literature::kAdultNeckShaftAngleMaxDeg);
      base.femoral_anteversion_deg = uniform(neck_engine, -10.0, 40.0);
    }
    const HipCheck check = generate_and_check(ce, alpha, edge_mm, base);
    auto csv_field = [](std::string text) {
      std::replace(text.begin(), text.end(), ',', ';');
      std::replace(text.begin(), text.end(), '\n', ' ');
      return text;
    };
    const std::string status = csv_field(check.status);
    csv << std::setprecision(10) << k << ',' << ce << ',' << alpha << ',' << edge_mm << ',' << status << ','
        << std::setprecision(6) << check.ce_measured_deg << ',' << check.alpha_measured_deg << ','
        << check.ce_measured_deg - ce << ',' << check.alpha_measured_deg - alpha << ','
        << (check.surfaces_clean ? 1 : 0) << ',' << check.labrum_pieces << ',' << check.deepest_overlap_mm << ',' << check.overlap_tolerance_mm << ','
        << check.vertices << ',' << std::setprecision(4) << check.seconds << ',' << check.surface_algorithm << ','
        << csv_field(check.mesher_failures) << ',' << std::setprecision(10) << base.neck_shaft_angle_deg << ','
        << base.femoral_anteversion_deg << '\n'
        << std::flush;
    std::ostringstream label;
    label << "hip " << k << ": CE " << ce << " / alpha " << alpha << " / CCD " << base.neck_shaft_angle_deg
          << " / version " << base.femoral_anteversion_deg << " at " << edge_mm << " mm";
    expect_clean(check, label.str());
  }
}

}  // namespace
}  // namespace hipfai::geometry::test_support
