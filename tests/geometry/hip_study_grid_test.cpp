// The 25 study hips at the test level (3 mm edges), each generated once per test process: clean
// surfaces, CE and alpha measured back within 1 deg, and in the neutral pose no femoral vertex
// inside an acetabular tissue (nor the reverse) deeper than the discretisation allows.
//
// The reference is independent of the generator: inside/outside by ray parity (candidates) confirmed
// by the generalised winding number of the closed surface (sum of the solid angles of its
// triangles, Van Oosterom & Strackee 1983: 1 inside, 0 outside, exact up to rounding away from the
// surface, with no ray to place), and depth as the exact distance to the nearest triangle.
#include "geometry/hip_generator.h"
#include "geometry/hip_model.h"
#include "geometry/mesh_check.h"
#include "tests/geometry/mesh_inside.h"
#include "tests/geometry/study_hips.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace hipfai::geometry::test_support {
namespace {

struct Overlap {
  double depth_mm = 0.0;  // deepest vertex of `a` inside `b`
  Vec3 where = Vec3::Zero();
  std::size_t count = 0;  // vertices of `a` inside `b` deeper than the tolerance
};

// Vertices of `a` inside the closed surface `b`. The bucketed ray parity finds the candidates
// quickly; each is confirmed by the winding number (exact, no ray) before its depth counts.
Overlap vertices_inside(const TriMesh& a, const TriMesh& b, double tolerance_mm) {
  const InsideTester parity(b);
  Overlap overlap;
  for (const Vec3& p : a.vertices) {
    if (!parity.inside(p) || winding_number(b, p) < 0.5) continue;
    const double depth = distance_to_surface(b, p);
    if (depth > tolerance_mm) ++overlap.count;
    if (depth > overlap.depth_mm) {
      overlap.depth_mm = depth;
      overlap.where = p;
    }
  }
  return overlap;
}

TriMesh unit_cube() {
  TriMesh box;
  for (int i = 0; i < 8; ++i) box.vertices.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  // Outward CCW faces of the cube, two triangles each.
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    box.triangles.push_back({f[0], f[1], f[2]});
    box.triangles.push_back({f[0], f[2], f[3]});
  }
  return box;
}

// Reference checks of the tools on a cube of side 2 (closed form).
TEST(StudyGridTools, WindingNumberParityAndDistanceOnACube) {
  const TriMesh box = unit_cube();
  const InsideTester parity(box);
  EXPECT_NEAR(winding_number(box, Vec3(0.3, -0.2, 0.9)), 1.0, 1e-12);  // inside
  EXPECT_NEAR(winding_number(box, Vec3(1.2, 0.0, 0.0)), 0.0, 1e-12);   // outside
  EXPECT_TRUE(parity.inside(Vec3(0.3, -0.2, 0.9)));
  EXPECT_FALSE(parity.inside(Vec3(-0.5, 1.01, 0.0)));
  EXPECT_NEAR(distance_to_surface(box, Vec3(0.3, -0.2, 0.9)), 0.1, 1e-12);
  EXPECT_NEAR(distance_to_surface(box, Vec3(2.0, 2.0, 0.0)), std::sqrt(2.0), 1e-12);  // to an edge
  EXPECT_NEAR(distance_to_surface(box, Vec3(2.0, 2.0, 2.0)), std::sqrt(3.0), 1e-12);  // to a corner
  // A half-size cube centred at (1.2, 0, 0): its four vertices at x = 0.7 are inside, 0.3 from
  // the face x = 1 (0.5 from the others); the four at x = 1.7 are outside.
  TriMesh other = box;
  for (Vec3& v : other.vertices) v = 0.5 * v + Vec3(1.2, 0.0, 0.0);
  const Overlap o = vertices_inside(other, box, 0.2);
  EXPECT_EQ(o.count, 4u);
  EXPECT_NEAR(o.depth_mm, 0.3, 1e-12);
  EXPECT_EQ(vertices_inside(other, box, 0.31).count, 0u);
}

// The requirements on every study hip. Angles: within 1 deg of the request (alpha in Nötzli's
// plane and at 1:30); 3 mm edges are the
// hard case, since the measurement's tolerance band grows with the edge. Neutral pose: both sides
// discretise the same 25 mm sphere, so a vertex of one side may lie inside the other by up to the
// sagitta of its longest chord, e^2 / (2 R) (e the longest edge of the model, 0.4-0.7 mm at 3 mm
// edges); anything deeper is a real overlap of the construction (without the labrum's neck
// clearance, CE 0 hips have labrum vertices 2.7 mm inside the femoral neck and this test fails).
TEST(StudyGrid, All25HipsCleanWithinOneDegreeAndApartInNeutral) {
  const std::vector<const char*> femoral = {"femur_bone", "femoral_cartilage"};
  const std::vector<const char*> acetabular = {"acetabular_bone", "acetabular_cartilage", "labrum"};
  for (int ce = 0; ce <= 40; ce += 10) {
    for (int alpha = 40; alpha <= 80; alpha += 10) {
      const std::string label = "ce" + std::to_string(ce) + "_alpha" + std::to_string(alpha);
      const HipModel& model = study_hip(ce, alpha, kStudyTestEdgeMm);
      // The exact inside test needs closed, outward surfaces: check them at this level too.
      for (const char* name : kHipTissueNames) {
        const MeshReport report = check_mesh(model.tissue(name));
        EXPECT_TRUE(report.watertight_manifold && report.outward && report.degenerate_triangles == 0 &&
                    report.connected_components == 1)
            << label << " " << name;
      }
      const MeasuredAngles m = measure_study_angles(model);
      ASSERT_EQ(m.ce.status, MeasureStatus::kOk) << label;
      ASSERT_EQ(m.alpha.status, MeasureStatus::kOk) << label;
      EXPECT_NEAR(m.ce.ce_deg, ce, 1.0) << label;
      EXPECT_NEAR(m.alpha.alpha_deg, alpha, 1.0) << label;
      // Clock profile: the cam holds alpha from 3:00 (Nötzli's plane, above) to 1:30; the
      // inferior head-neck junction (6:00) is the normal one.
      for (const auto& [clock_deg, value] : m.alpha.profile) {
        if (std::abs(clock_deg - 45.0) < 1e-9) {
          EXPECT_NEAR(value, alpha, 1.0) << label << " at 1:30";
        }
        if (std::abs(clock_deg + 90.0) < 1e-9) {
          EXPECT_NEAR(value, 40.0, 1.0) << label << " at 6:00";
        }
      }

      double edge = 0.0;
      for (const auto& [name, mesh] : model.tissues) edge = std::max(edge, longest_edge(mesh));
      const double tolerance_mm = edge * edge / (2.0 * model.parameters.articular_radius_mm);
      for (const char* f : femoral) {
        for (const char* a : acetabular) {
          for (const auto& [inner, outer] : {std::pair{f, a}, std::pair{a, f}}) {
            const Overlap o = vertices_inside(model.tissue(inner), model.tissue(outer), tolerance_mm);
            EXPECT_EQ(o.count, 0u) << label << ": " << o.count << " vertices of " << inner << " inside "
                                   << outer << ", deepest " << o.depth_mm << " mm at ("
                                   << o.where.transpose() << "), tolerance " << tolerance_mm << " mm";
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace hipfai::geometry::test_support
