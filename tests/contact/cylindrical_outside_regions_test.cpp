// The outside regions of the ring table (CylindricalTable::outside_every_shell): a point the table
// calls outside must be outside every closed shell of the fixed mesh by an independent test (the
// winding number of each shell, from solid angles: tests/geometry/mesh_inside.h), its angle must lie in no candidate's angular
// extent, and its nearest crossing must not say "penetrating". Hard cases: region borders exactly
// and 1e-15 .. 1e-3 rad either side, two shells that intersect (a point inside one and outside the
// other is never outside), a point inside a shell, meshes that are not closed shells (no regions),
// the real CT bones and a generated hip (regions exist and the one-pass query skips most walks
// there; cylindrical_angular_walk_test.cpp checks the pairs are the same with and without them).
#include "contact/cylindrical_segmenting.h"
#include "contact/cylindrical_table.h"
#include "geometry/hip_generator.h"
#include "geometry/mesh_io.h"
#include "geometry/primitive_meshes.h"
#include "random_shapes.h"
#include "../geometry/mesh_inside.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace hipfai::contact {
namespace {

using geometry::TriMesh;
using test_shapes::random_pose;
using test_shapes::random_shape;
using test_shapes::random_unit;
using geometry::test_support::winding_number;

bool outside_all(const std::vector<const TriMesh*>& shells, const Vec3& p) {
  for (const TriMesh* shell : shells) {
    if (std::abs(winding_number(*shell, p)) > 0.5) return false;
  }
  return true;
}

// Whether theta lies within a candidate of the circle (r, z) as seen from the axis: in its angular
// extent less the extent's widening margin (so rounding at an extent's end does not count).
bool in_some_extent(const CylindricalTable& table, double r, double z, double theta) {
  bool in = false;
  table.for_each_candidate(r, z, [&](std::int32_t t) {
    const auto& tri = table.triangle(t);
    const AngularExtent e =
        triangle_angular_extent(table.local_vertex(tri[0]), table.local_vertex(tri[1]), table.local_vertex(tri[2]));
    const double margin = 0.5 * kAngularExtentMarginRad;
    for (const double turn : {-2.0 * std::numbers::pi, 0.0, 2.0 * std::numbers::pi}) {
      in = in || e.all_angles() || (theta + turn >= e.lo + margin && theta + turn <= e.lo + e.width - margin);
    }
  });
  return in;
}

Vec3 global_point(const CylindricalTable& table, double r, double z, double theta) {
  const AxisFrame& f = table.frame();
  return f.centre + r * std::cos(theta) * f.e1 + r * std::sin(theta) * f.e2 + z * f.axis;
}

// Checks every claim of outside_every_shell at (r, z, theta); returns 1 for a claim.
int check_point(const CylindricalTable& table, const std::vector<const TriMesh*>& shells, double r, double z,
                double theta, const std::string& what) {
  if (!table.outside_every_shell(r, z, theta)) return 0;
  EXPECT_TRUE(outside_all(shells, global_point(table, r, z, theta))) << what << " r " << r << " z " << z << " theta " << theta;
  EXPECT_FALSE(in_some_extent(table, r, z, theta)) << what << " r " << r << " z " << z << " theta " << theta;
  const NearestCrossing nearest = table.nearest_crossing_of_every_candidate(r, z, theta);
  if (nearest.found()) {
    EXPECT_NE(arc_verdict(r, z, theta, nearest.crossing_theta_rad, table.local_normal(nearest.triangle), 0.0),
              ArcVerdict::kPenetrating)
        << what;
  }
  return 1;
}

// Every region of every cell: off every extent of the cell, outside every shell at points spread
// over it, and its borders (open) and 1e-15 .. 1e-3 rad inside and outside them.
int check_every_region(const CylindricalTable& table, const std::vector<const TriMesh*>& shells, const std::string& what) {
  int claims = 0;
  for (long long iz = 0; iz < table.num_z_cells(); ++iz) {
    for (long long ir = 0; ir < table.num_r_cells(); ++ir) {
      for (const CylindricalTable::OutsideRegion& region : table.outside_regions(iz, ir)) {
        EXPECT_LT(region.lo, region.hi) << what;
        const double lo = std::max(region.lo, -std::numbers::pi), hi = std::min(region.hi, std::numbers::pi);
        for (const double fr : {0.02, 0.5, 0.98}) {
          for (const double fz : {0.02, 0.5, 0.98}) {
            const double r = table.r_lo_mm() + (static_cast<double>(ir) + fr) * table.resolution_r_mm();
            const double z = table.z_lo_mm() + (static_cast<double>(iz) + fz) * table.resolution_z_mm();
            if (r <= 0.0) continue;
            for (const double f : {0.0, 0.3, 0.5, 0.9}) claims += check_point(table, shells, r, z, lo + f * (hi - lo), what);
            for (const double border : {region.lo, region.hi}) {
              if (std::abs(border) > std::numbers::pi) continue;  // a split region's outer end
              EXPECT_FALSE(table.outside_every_shell(r, z, border)) << what << ": regions are open";
              for (const double offset : {1e-15, 1e-12, 1e-9, 1e-6, 1e-3}) {
                claims += check_point(table, shells, r, z, border + offset, what);
                claims += check_point(table, shells, r, z, border - offset, what);
              }
            }
          }
        }
      }
    }
  }
  return claims;
}

TEST(CylindricalOutsideRegions, ClaimsAreOutsideEveryShellOnRandomScenes) {
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int claims = 0, points = 0;
  for (int trial = 0; trial < 12; ++trial) {
    // Two shapes near each other: they often intersect, and each is its own shell.
    const TriMesh first = random_shape(rng, trial % 3);
    const TriMesh second = random_shape(rng, (trial + 1) % 3);
    const TriMesh fixed = geometry::merge_meshes({&first, &second});
    const std::vector<const TriMesh*> shells{&first, &second};
    const Vec3 centre(20 * u(rng) - 10, 20 * u(rng) - 10, 20 * u(rng) - 10);
    CylindricalTableOptions options;
    options.resolution_r_mm = options.resolution_z_mm = geometry::mean_edge_length(fixed) * (0.5 + 2 * u(rng));
    const CylindricalTable table = CylindricalTable::build(fixed, centre, random_unit(rng), options);
    ASSERT_GT(table.num_outside_regions(), 0u);
    const std::string what = "trial " + std::to_string(trial);
    claims += check_every_region(table, shells, what);
    // Points anywhere in the grid, at any angle.
    for (int k = 0; k < 400; ++k) {
      const double r = table.r_lo_mm() + u(rng) * table.resolution_r_mm() * static_cast<double>(table.num_r_cells());
      const double z = table.z_lo_mm() + u(rng) * table.resolution_z_mm() * static_cast<double>(table.num_z_cells());
      if (r <= 0.0) continue;
      ++points;
      claims += check_point(table, shells, r, z, std::numbers::pi * (2.0 * u(rng) - 1.0), what);
    }
  }
  EXPECT_GT(claims, 5000);  // the regions are really there and really used
  EXPECT_GT(points, 4000);
}

TEST(CylindricalOutsideRegions, InsideOneOfTwoIntersectingBoxesIsNeverOutside) {
  const TriMesh a = geometry::make_box(Vec3(4, -2, -2), Vec3(10, 2, 2), 4);
  const TriMesh b = geometry::make_box(Vec3(7, -1, -4), Vec3(9, 1, 4), 4);  // crosses a's top and bottom
  const TriMesh fixed = geometry::merge_meshes({&a, &b});
  const std::vector<const TriMesh*> shells{&a, &b};
  for (const double resolution : {0.3, 1.0, 2.5}) {
    CylindricalTableOptions options;
    options.resolution_r_mm = options.resolution_z_mm = resolution;
    const CylindricalTable table = CylindricalTable::build(fixed, Vec3::Zero(), Vec3::UnitZ(), options);
    EXPECT_GT(check_every_region(table, shells, "boxes"), 0);
    // A point inside a only, inside b only, inside both, outside both (at the same circle).
    for (const Vec3& p : {Vec3(5, 0, 0), Vec3(8, 0, 3), Vec3(8, 0, 0), Vec3(0, 8, 0)}) {
      const Cylindrical cyl = to_cylindrical(table.frame().to_local(p));
      const bool claimed = table.outside_every_shell(cyl.r, cyl.z, cyl.theta);
      EXPECT_EQ(claimed && !outside_all(shells, p), false) << p.transpose();
    }
    const Cylindrical far = to_cylindrical(table.frame().to_local(Vec3(0, 8, 0)));
    EXPECT_TRUE(table.outside_every_shell(far.r, far.z, far.theta)) << "a region the other side of the axis";
  }
}

TEST(CylindricalOutsideRegions, NoneUnlessTheMeshIsClosedShells) {
  const TriMesh box = geometry::make_box(Vec3(3, -2, -2), Vec3(8, 2, 2), 3);
  EXPECT_GT(CylindricalTable::build(box, Vec3::Zero(), Vec3::UnitZ()).num_outside_regions(), 0u);
  TriMesh open = box;
  open.triangles.pop_back();
  TriMesh flipped = box;
  std::swap(flipped.triangles[4][1], flipped.triangles[4][2]);
  for (const TriMesh* mesh : {&open, &flipped}) {
    const CylindricalTable table = CylindricalTable::build(*mesh, Vec3::Zero(), Vec3::UnitZ());
    EXPECT_EQ(table.num_outside_regions(), 0u);
    EXPECT_FALSE(table.outside_every_shell(5.0, 0.0, std::numbers::pi / 2));
  }
  // A box turned inside out is a closed shell too, whose solid is the rest of space: its outside
  // regions are the box's inside (where the walk, by the same normals, says "not penetrating").
  TriMesh inside_out = box;
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  const CylindricalTable table = CylindricalTable::build(inside_out, Vec3::Zero(), Vec3::UnitZ(), {0.4, 0.4});
  ASSERT_GT(table.num_outside_regions(), 0u);
  for (long long iz = 0; iz < table.num_z_cells(); ++iz) {
    for (long long ir = 0; ir < table.num_r_cells(); ++ir) {
      for (const CylindricalTable::OutsideRegion& region : table.outside_regions(iz, ir)) {
        const double r = table.r_lo_mm() + (static_cast<double>(ir) + 0.5) * table.resolution_r_mm();
        const double z = table.z_lo_mm() + (static_cast<double>(iz) + 0.5) * table.resolution_z_mm();
        const double theta = 0.5 * (std::max(region.lo, -std::numbers::pi) + std::min(region.hi, std::numbers::pi));
        EXPECT_NEAR(winding_number(box, global_point(table, r, z, theta)), 1.0, 1e-9);
        const NearestCrossing nearest = table.nearest_crossing_of_every_candidate(r, z, theta);
        ASSERT_TRUE(nearest.found());
        EXPECT_EQ(arc_verdict(r, z, theta, nearest.crossing_theta_rad, table.local_normal(nearest.triangle), 0.0),
                  ArcVerdict::kOutside);
      }
    }
  }
  // Without the angular index there is nothing to walk and no region.
  CylindricalTableOptions no_index;
  no_index.angular_index = false;
  EXPECT_EQ(CylindricalTable::build(box, Vec3::Zero(), Vec3::UnitZ(), no_index).num_outside_regions(), 0u);
}

// How many posed mobile vertices reach a non-empty cell, and how many of them lie in a region.
std::pair<std::size_t, std::size_t> region_share(const CylindricalTable& table, const TriMesh& mobile,
                                                 const Eigen::Isometry3d& pose) {
  std::size_t reaching = 0, in_region = 0;
  for (const Vec3& p : mobile.vertices) {
    const Vec3 local = table.frame().to_local(pose * p);
    if (!table.distance_may_touch(local.norm())) continue;
    const Cylindrical cyl = to_cylindrical(local);
    if (!table.has_candidates(cyl.r, cyl.z)) continue;
    ++reaching;
    in_region += table.outside_every_shell(cyl.r, cyl.z, cyl.theta) ? 1 : 0;
  }
  return {reaching, in_region};
}

TEST(CylindricalOutsideRegions, RealCtBonesSkipMostWalks) {
  const std::string folder = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
  const TriMesh pelvis = geometry::read_mesh(folder + "pelvis_no_sacrum.ply");
  const TriMesh femur = geometry::read_mesh(folder + "femur_r.ply");
  const Vec3 hjc(143.80, 243.46, -432.58);
  const Vec3 axis = Vec3(1.0, 0.3, 0.2).normalized();
  const CylindricalTable table = CylindricalTable::build(pelvis, hjc, axis, {}, &femur);
  ASSERT_GT(table.num_outside_regions(), 0u) << "the CT pelvis is a closed shell";
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.5, axis).toRotationMatrix();
  pose = Eigen::Translation3d(hjc) * pose * Eigen::Translation3d(-hjc);
  const auto [reaching, in_region] = region_share(table, femur, pose);
  EXPECT_GT(reaching, 1000u);
  EXPECT_GT(in_region, reaching / 2);
  // Claims checked against the pelvis' own winding number at a sample of the femur's vertices.
  const std::vector<const TriMesh*> shells{&pelvis};
  int claims = 0;
  for (std::size_t v = 0; v < femur.vertices.size(); v += 97) {
    const Cylindrical cyl = to_cylindrical(table.frame().to_local(pose * femur.vertices[v]));
    claims += check_point(table, shells, cyl.r, cyl.z, cyl.theta, "CT");
  }
  EXPECT_GT(claims, 0);
}

}  // namespace
}  // namespace hipfai::contact
