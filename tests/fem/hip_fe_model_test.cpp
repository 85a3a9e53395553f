// The hip FE model (fem/hip_fe_model.h): hex mesh -> deal.II conversion, model set-up, and a
// few steps of the standing-to-sitting motion under the joint force on a hand-made hip: two
// concentric spherical cartilage caps (femoral 23-25 mm on the rigid femoral head, acetabular
// 25-27 mm under the fixed pelvis) on non-matching meshes, the femoral head an octasphere.
#include "fem/hip_fe_model.h"

#include "core/error.h"
#include "core/literature.h"
#include "fem/rigid_mesh_surface.h"
#include "geometry/hip_frame.h"
#include "geometry/primitive_meshes.h"
#include "tests/fem/same_solution.h"

#include <Eigen/Geometry>
#include <deal.II/grid/grid_tools.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace hipfai::fem {
namespace {

using geometry::HexMesh;
using geometry::SurfaceTag;
using geometry::Vec3;
using geometry::VolumeTag;

constexpr double kBoneRadius = 23.0, kContactRadius = 25.0, kCupRadius = 27.0;  // mm

// Cap of a spherical shell about the origin around +Z (superior), r in [r_in, r_out]: the
// gnomonic grid direction (u, v, 1) / |.| for u, v in [-extent, extent], n x n cells, `layers`
// hexahedra radially. Faces: inner sphere `inner_tag`, outer `outer_tag`, sides kFree.
void add_cap(HexMesh& mesh, double r_in, double r_out, double extent, int n, int layers,
             VolumeTag tissue, SurfaceTag inner_tag, SurfaceTag outer_tag) {
  const auto first = static_cast<std::int32_t>(mesh.vertices.size());
  const auto id = [&](int i, int j, int k) { return first + (k * (n + 1) + j) * (n + 1) + i; };
  for (int k = 0; k <= layers; ++k) {
    const double r = r_in + (r_out - r_in) * k / layers;
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        const double u = -extent + 2.0 * extent * i / n, v = -extent + 2.0 * extent * j / n;
        mesh.vertices.push_back(r * Vec3(u, v, 1.0).normalized());
      }
    }
  }
  for (int k = 0; k < layers; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        mesh.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                              id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1),
                              id(i, j + 1, k + 1)});
        mesh.hex_tags.push_back(tissue);
      }
    }
  }
  const auto quad = [&](std::array<std::int32_t, 4> q, SurfaceTag tag) {
    mesh.quads.push_back(q);
    mesh.quad_tags.push_back(tag);
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      quad({id(i, j, 0), id(i, j + 1, 0), id(i + 1, j + 1, 0), id(i + 1, j, 0)}, inner_tag);
      quad({id(i, j, layers), id(i + 1, j, layers), id(i + 1, j + 1, layers), id(i, j + 1, layers)},
           outer_tag);
    }
  }
  for (int k = 0; k < layers; ++k) {
    for (int s = 0; s < n; ++s) {
      quad({id(s, 0, k), id(s + 1, 0, k), id(s + 1, 0, k + 1), id(s, 0, k + 1)}, SurfaceTag::kFree);
      quad({id(s, n, k), id(s, n, k + 1), id(s + 1, n, k + 1), id(s + 1, n, k)}, SurfaceTag::kFree);
      quad({id(0, s, k), id(0, s, k + 1), id(0, s + 1, k + 1), id(0, s + 1, k)}, SurfaceTag::kFree);
      quad({id(n, s, k), id(n, s + 1, k), id(n, s + 1, k + 1), id(n, s, k + 1)}, SurfaceTag::kFree);
    }
  }
}

// Femoral cap wider than the acetabular one, so every acetabular node has the femoral cartilage
// opposite through the few degrees of rotation below; non-matching (8 vs 7 cells a side).
constexpr double kFemoralExtent = 0.8, kAcetabularExtent = 0.6;  // tan of the half-angles
HexMesh two_caps() {
  HexMesh mesh;
  add_cap(mesh, kBoneRadius, kContactRadius, kFemoralExtent, 8, 1, VolumeTag::kFemoralCartilage,
          SurfaceTag::kFemoralCartilageBonded, SurfaceTag::kFemoralCartilageArticular);
  add_cap(mesh, kContactRadius, kCupRadius, kAcetabularExtent, 7, 1, VolumeTag::kAcetabularCartilage,
          SurfaceTag::kAcetabularCartilageArticular, SurfaceTag::kAcetabularCartilageBonded);
  return mesh;
}

TEST(CreateHexTriangulation, KeepsVolumeTagsAndBoundaryTags) {
  const HexMesh mesh = two_caps();
  dealii::Triangulation<3> triangulation;
  create_hex_triangulation(mesh, triangulation);
  EXPECT_EQ(triangulation.n_active_cells(), mesh.hexes.size());
  // Every cell has positive volume (the conversion fixed the orientation) and the volumes add
  // up to the two shell sectors' flat-faced volume: compare per tissue with the hex count.
  std::map<int, int> cells_per_material;
  for (const auto& cell : triangulation.active_cell_iterators()) {
    EXPECT_GT(cell->measure(), 0.0);
    ++cells_per_material[cell->material_id()];
  }
  EXPECT_EQ(cells_per_material[static_cast<int>(VolumeTag::kFemoralCartilage)], 64);
  EXPECT_EQ(cells_per_material[static_cast<int>(VolumeTag::kAcetabularCartilage)], 49);
  // Boundary faces carry their tag; the radius tells which face it must be.
  std::map<int, int> faces_per_tag;
  for (const auto& face : triangulation.active_face_iterators()) {
    if (!face->at_boundary()) continue;
    ++faces_per_tag[face->boundary_id()];
    // Bonded faces: all four vertices on their sphere (to round-off of the normalisation).
    for (const unsigned int v : face->vertex_indices()) {
      const double r = face->vertex(v).norm();
      if (face->boundary_id() == static_cast<int>(SurfaceTag::kFemoralCartilageBonded)) {
        EXPECT_NEAR(r, kBoneRadius, 1e-12);
      }
      if (face->boundary_id() == static_cast<int>(SurfaceTag::kAcetabularCartilageBonded)) {
        EXPECT_NEAR(r, kCupRadius, 1e-12);
      }
    }
  }
  EXPECT_EQ(faces_per_tag[static_cast<int>(SurfaceTag::kFemoralCartilageArticular)], 64);
  EXPECT_EQ(faces_per_tag[static_cast<int>(SurfaceTag::kAcetabularCartilageArticular)], 49);
  EXPECT_EQ(faces_per_tag[static_cast<int>(SurfaceTag::kFree)], 4 * 8 + 4 * 7);
}

TEST(CreateHexTriangulation, RejectsBrokenMeshesWithOneLine) {
  HexMesh mesh = two_caps();
  mesh.hexes[3][5] = 1 << 30;
  dealii::Triangulation<3> triangulation;
  try {
    create_hex_triangulation(mesh, triangulation, "model/hip.msh");
    FAIL() << "an out-of-range vertex index must be rejected";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("model/hip.msh: vertex index", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
  HexMesh untagged = two_caps();
  untagged.quad_tags.pop_back();
  EXPECT_THROW(create_hex_triangulation(untagged, triangulation), Error);
}

TEST(HipFeLevel, NamesRoundTripAndRefineMonotonically) {
  for (const std::string& name : fe_level_names()) EXPECT_EQ(to_string(parse_fe_level(name, "test")), name);
  for (const std::string& name : fe_solver_names()) EXPECT_EQ(to_string(parse_fe_solver(name, "test")), name);
  EXPECT_THROW(parse_fe_level("medium", "test"), Error);
  EXPECT_THROW(parse_fe_solver("gauss", "test"), Error);
  const auto coarse = hip_volume_options(HipFeLevel::kCoarse);
  const auto normal = hip_volume_options(HipFeLevel::kDefault);
  const auto fine = hip_volume_options(HipFeLevel::kFine);
  EXPECT_GT(coarse.edge_mm, normal.edge_mm);
  EXPECT_GT(normal.edge_mm, fine.edge_mm);
  EXPECT_LE(coarse.layers, normal.layers);
  EXPECT_LE(normal.layers, fine.layers);
  EXPECT_EQ(coarse.min_thickness_mm, fine.min_thickness_mm);  // same geometry at every level
}

// Standing-to-sitting (thesis §4.3.2.3) split into equal angles about its single axis, computed
// here from the Cardan angles independently of studies/motion.
Eigen::Matrix3d sub_motion(int k, int n) {
  const Eigen::AngleAxisd end(geometry::femur_rotation(
      {literature::kStandToSitFlexionDeg, literature::kStandToSitAdductionDeg,
       literature::kStandToSitInternalRotationDeg}));
  return Eigen::AngleAxisd(end.angle() * k / n, end.axis()).toRotationMatrix();
}

TEST(HipFeModel, FirstStepsOfSittingDownBalanceTheJointForce) {
  const HexMesh mesh = two_caps();
  const geometry::TriMesh bone = geometry::make_octasphere(Vec3::Zero(), kBoneRadius, 5);
  ContactProblem problem(MPI_COMM_WORLD, ContactOptions{});
  build_hip_fe_model(problem, mesh, bone, Vec3::Zero());
  ASSERT_EQ(problem.model().bodies.size(), 2u);  // no labrum in this mesh
  ASSERT_EQ(problem.model().contact_pairs.size(), 2u);

  const Eigen::Vector3d force = constant_joint_force_n(kDefaultBodyWeightN);
  std::vector<MotionStep> steps;
  // The first three sub-motions of 30 (6 deg in all): the acetabular cap stays inside the
  // femoral one (half-angles atan 0.6 = 31 deg, atan 0.8 = 38.7 deg).
  for (int k = 1; k <= 3; ++k) steps.push_back(make_hip_motion_step(sub_motion(k, 30), force));
  MotionOptions options;
  options.moving_body = kFemurBody;
  const std::vector<ContactResult> results = run_motion(problem, steps, options);
  ASSERT_EQ(results.size(), steps.size());

  // Confined (uniaxial-strain) modulus of each layer, M = E (1 - nu) / ((1 + nu)(1 - 2 nu)), and
  // of the two layers in series, K = 1 / (h1/M1 + h2/M2): a translation d of the head towards the
  // cup compresses the layers by d cos(theta) at polar angle theta.
  const double e = literature::kCartilageYoungsModulusMPa, nu = literature::kCartilagePoissonRatio;
  const double m = e * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  const double h = kContactRadius - kBoneRadius;
  const double k_series = 1.0 / (h / m + h / m);
  // Projected area of the acetabular articular surface on the plane normal to the force (Z):
  // the square cap of the sphere r = 25 under the gnomonic grid, by a fine midpoint rule on it.
  double projected_area = 0.0;
  {
    constexpr int kN = 400;  // converged to < 1e-4 relative
    const double du = 2 * kAcetabularExtent / kN;
    for (int j = 0; j < kN; ++j) {
      for (int i = 0; i < kN; ++i) {
        const double u = -kAcetabularExtent + (i + 0.5) * du, v = -kAcetabularExtent + (j + 0.5) * du;
        // Surface element of r (u, v, 1)/|.|: r^2 du dv / (1 + u^2 + v^2)^1.5; its Z-projection
        // multiplies by n_z = 1 / sqrt(1 + u^2 + v^2).
        projected_area += kContactRadius * kContactRadius * du * du / std::pow(1 + u * u + v * v, 2.0);
      }
    }
  }

  for (std::size_t k = 0; k < results.size(); ++k) {
    const ContactResult& r = results[k];
    ASSERT_EQ(r.status, ContactStatus::kConverged) << "step " << k;
    ASSERT_TRUE(std::isfinite(r.peaks.max_pressure_mpa) && std::isfinite(r.peaks.max_penetration_mm));
    for (const double v : r.peaks.max_von_mises_mpa) ASSERT_TRUE(std::isfinite(v));
    // Contact resultant on the acetabular side (slaves) = the force the femur applies: the load
    // control solves exactly for it (linear in the translation for the converged active set), up
    // to the CG tolerance 1e-12.
    dealii::Tensor<1, 3> resultant;
    for (const auto& pair_force : r.pair_force_n) resultant += pair_force;
    const dealii::Tensor<1, 3> applied = steps[k].force_n;
    EXPECT_LT((resultant - applied).norm(), 1e-6 * applied.norm()) << "step " << k;
    // Residual penetration below 1 % of the cartilage thickness.
    EXPECT_LT(r.peaks.max_penetration_mm, 0.01 * h) << "step " << k;
    // Peak pressure bounds. Lower: F = sum p_i (n_i . e_z) A_i <= p_max * (projected contact
    // area) <= p_max * projected_area, exact for any pressure distribution on this surface.
    EXPECT_GE(r.peaks.max_pressure_mpa, applied.norm() / projected_area) << "step " << k;
    // Upper: no point of a bonded layer is stiffer than confined compression, and no point is
    // compressed by more than the head's displacement along the force (the layers are concentric)
    // plus the residual penetration: p <= K (d + penetration). Nodal pressures are force / nodal
    // area, a lumped value; 20 % covers their oscillation on Q2 faces (corner vs mid-side nodes).
    const double d = r.rigid_translation_mm[kFemurBody].norm() + r.peaks.max_penetration_mm;
    EXPECT_LE(r.peaks.max_pressure_mpa, 1.2 * k_series * d) << "step " << k;
    std::printf("step %zu: %s, %u active-set iterations, p_max %.3f MPa (bounds %.3f .. %.3f), "
                "penetration %.2e mm, translation %.4f mm, von Mises %.3f / %.3f MPa, %.1f s\n",
                k, to_string(r.status), r.statistics.active_set_iterations, r.peaks.max_pressure_mpa,
                applied.norm() / projected_area, 1.2 * k_series * d, r.peaks.max_penetration_mm,
                r.rigid_translation_mm[kFemurBody].norm(), r.peaks.max_von_mises_mpa[0],
                r.peaks.max_von_mises_mpa[1], r.statistics.wall_time_s);
  }
}

// The bordered (low-rank) active-set updates of the direct solver on a mesh that needs no gmsh
// (so the sanitizer build runs it too): the first steps of sitting down with and without them
// give the same active sets, pressures, translations and stresses to round-off, and some steps
// are solved by an update (steps of a 10-step motion: at 30 steps the warm start predicts
// every later step's set, and nothing is left to update).
TEST(HipFeModel, BorderedUpdatesGiveTheRefactorisedResultOnTwoCaps) {
  const HexMesh mesh = two_caps();
  const geometry::TriMesh bone = geometry::make_octasphere(Vec3::Zero(), kBoneRadius, 5);
  const Eigen::Vector3d force = constant_joint_force_n(kDefaultBodyWeightN);
  std::vector<MotionStep> steps;
  for (int k = 1; k <= 3; ++k) steps.push_back(make_hip_motion_step(sub_motion(k, 10), force));
  const auto solve = [&](bool low_rank) {
    ContactOptions solver;
    solver.linear_solver = LinearSolver::kDirect;
    solver.low_rank_updates = low_rank;
    ContactProblem problem(MPI_COMM_WORLD, solver);
    build_hip_fe_model(problem, mesh, bone, Vec3::Zero());
    MotionOptions options;
    options.moving_body = kFemurBody;
    return run_motion(problem, steps, options);
  };
  const std::vector<ContactResult> updated = solve(true), refactorised = solve(false);
  ASSERT_EQ(updated.size(), steps.size());
  ASSERT_EQ(refactorised.size(), steps.size());
  unsigned updates = 0;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    const ContactResult& u = updated[k];
    const ContactResult& r = refactorised[k];
    ASSERT_EQ(u.status, ContactStatus::kConverged);
    ASSERT_EQ(r.status, ContactStatus::kConverged);
    expect_same_nodes_and_solution(u, r);
    EXPECT_EQ(r.statistics.low_rank_updates, 0u);
    updates += u.statistics.low_rank_updates;
  }
  std::printf("two caps, %zu steps: %u bordered updates\n", steps.size(), updates);
  EXPECT_GT(updates, 0u);
}

// The two caps through three steps of sitting down and a fourth whose joint force turns by 15
// degrees (the head translates sideways and the contact zone moves; the acetabular cap's normals
// reach 31 degrees from its axis, so the turned force is still carried), each solved with one
// solver setting from a fresh problem.
std::vector<ContactResult> two_caps_motion(const ContactOptions& solver,
                                           std::size_t first_step = 0) {
  const HexMesh mesh = two_caps();
  const geometry::TriMesh bone = geometry::make_octasphere(Vec3::Zero(), kBoneRadius, 5);
  const Eigen::Vector3d force = constant_joint_force_n(kDefaultBodyWeightN);
  std::vector<MotionStep> steps;
  for (int k = 1; k <= 3; ++k) steps.push_back(make_hip_motion_step(sub_motion(k, 30), force));
  const Eigen::Vector3d turned =
      Eigen::AngleAxisd(15.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()) * force;
  steps.push_back(make_hip_motion_step(sub_motion(3, 30), turned));
  steps.erase(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(first_step));
  ContactProblem problem(MPI_COMM_WORLD, solver);
  build_hip_fe_model(problem, mesh, bone, Vec3::Zero());
  MotionOptions options;
  options.moving_body = kFemurBody;
  return run_motion(problem, steps, options);
}

ContactOptions with_solver(LinearSolver kind) {
  ContactOptions solver;
  solver.linear_solver = kind;
  return solver;
}

// The substructured solver (each body factorised once, the contact condensed) against the
// monolithic direct solve of the same discrete problem: the same active sets, pressures, gaps,
// translations and stresses at every step, including the one where the zone moves.
TEST(HipFeSubstructured, EqualsTheMonolithicSolveOnTwoCaps) {
  const std::vector<ContactResult> condensed = two_caps_motion(with_solver(LinearSolver::kSubstructured));
  const std::vector<ContactResult> monolithic = two_caps_motion(with_solver(LinearSolver::kDirect));
  ASSERT_EQ(condensed.size(), 4u);
  ASSERT_EQ(monolithic.size(), 4u);
  for (std::size_t k = 0; k < condensed.size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    ASSERT_EQ(condensed[k].status, ContactStatus::kConverged);
    ASSERT_EQ(monolithic[k].status, ContactStatus::kConverged);
    expect_same_nodes_and_solution(condensed[k], monolithic[k]);
    // Factorised once, in the first step only.
    EXPECT_EQ(condensed[k].statistics.factorisations, k == 0 ? 2u : 0u);
  }
  // The turned force moved the head sideways by more than a tenth of a millimetre, and the
  // contact zone with it (a different set of active nodes).
  const dealii::Tensor<1, 3> shift =
      condensed[3].rigid_translation_mm[kFemurBody] - condensed[2].rigid_translation_mm[kFemurBody];
  EXPECT_GT(shift.norm(), 0.01);
  std::size_t changed = 0;
  for (std::size_t n = 0; n < condensed[3].nodes.size(); ++n)
    changed += condensed[3].nodes[n].active != condensed[2].nodes[n].active;
  EXPECT_GT(changed, 0u);
  std::printf("two caps: the turned force moved the head %.4f mm, %zu nodes changed state\n",
              shift.norm(), changed);
}

// A step solved with the compliance columns kept from earlier steps (computed in the frame of
// the first step's pose, rotated since) equals the same step solved by a fresh problem that
// factorises and computes every column at that pose.
TEST(HipFeSubstructured, ReusedComplianceEqualsAFreshOne) {
  const std::vector<ContactResult> after_others = two_caps_motion(with_solver(LinearSolver::kSubstructured));
  const std::vector<ContactResult> alone = two_caps_motion(with_solver(LinearSolver::kSubstructured), 2);
  ASSERT_EQ(alone.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 3));
    ASSERT_EQ(alone[k].status, ContactStatus::kConverged);
    expect_same_nodes_and_solution(after_others[k + 2], alone[k]);
  }
  EXPECT_EQ(after_others[2].statistics.factorisations, 0u);
  EXPECT_EQ(alone[0].statistics.factorisations, 2u);
}

// The contact search's tangent-plane cull skips only master faces that contribute nothing: the
// solution with it is bit for bit the solution without it.
TEST(HipFeSubstructured, TangentPlaneCullChangesNothing) {
  ContactOptions plain = with_solver(LinearSolver::kSubstructured);
  plain.tangent_plane_cull = false;
  const std::vector<ContactResult> culled = two_caps_motion(with_solver(LinearSolver::kSubstructured));
  const std::vector<ContactResult> unculled = two_caps_motion(plain);
  ASSERT_EQ(culled.size(), unculled.size());
  for (std::size_t k = 0; k < culled.size(); ++k) {
    ASSERT_EQ(culled[k].nodes.size(), unculled[k].nodes.size());
    for (std::size_t n = 0; n < culled[k].nodes.size(); ++n) {
      EXPECT_EQ(culled[k].nodes[n].pressure_mpa, unculled[k].nodes[n].pressure_mpa);
      EXPECT_EQ(culled[k].nodes[n].gap_mm, unculled[k].nodes[n].gap_mm);
    }
    EXPECT_EQ(culled[k].peaks.max_von_mises_mpa, unculled[k].peaks.max_von_mises_mpa);
  }
}

TEST(HipFeModel, RejectsAMeshWithoutFemoralCartilage) {
  HexMesh mesh;
  add_cap(mesh, kContactRadius, kCupRadius, kAcetabularExtent, 3, 1, VolumeTag::kAcetabularCartilage,
          SurfaceTag::kAcetabularCartilageArticular, SurfaceTag::kAcetabularCartilageBonded);
  ContactProblem problem(MPI_COMM_WORLD, ContactOptions{});
  EXPECT_THROW(build_hip_fe_model(problem, mesh, geometry::make_octasphere(Vec3::Zero(), kBoneRadius, 3),
                                  Vec3::Zero()),
               Error);
}

}  // namespace
}  // namespace hipfai::fem
