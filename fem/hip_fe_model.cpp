#include "fem/hip_fe_model.h"

#include "core/error.h"
#include "core/literature.h"
#include "fem/rigid_mesh_surface.h"

#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/manifold_lib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <exception>
#include <memory>
#include <set>

namespace hipfai::fem {

using geometry::SurfaceTag;
using geometry::VolumeTag;

namespace {

dealii::types::boundary_id boundary_of(SurfaceTag tag) {
  return static_cast<dealii::types::boundary_id>(tag);
}

dealii::types::material_id material_of(VolumeTag tag) {
  return static_cast<dealii::types::material_id>(tag);
}

}  // namespace

geometry::HipVolumeOptions hip_volume_options(HipFeLevel level) {
  geometry::HipVolumeOptions options;
  options.min_thickness_mm = 0.25;
  switch (level) {
    case HipFeLevel::kCoarse: options.edge_mm = 6.0; options.layers = 1; break;
    case HipFeLevel::kDefault: options.edge_mm = 4.0; options.layers = 2; break;
    case HipFeLevel::kFine: options.edge_mm = 3.0; options.layers = 3; break;
  }
  return options;
}

void create_hex_triangulation(const geometry::HexMesh& mesh, dealii::Triangulation<3>& triangulation,
                              const std::string& what) {
  if (mesh.hexes.empty()) throw_error(what, ": no hexahedra");
  if (mesh.hex_tags.size() != mesh.hexes.size() || mesh.quad_tags.size() != mesh.quads.size()) {
    throw_error(what, ": ", mesh.hexes.size(), " hexahedra with ", mesh.hex_tags.size(), " tags, ",
                mesh.quads.size(), " quadrangles with ", mesh.quad_tags.size(), " tags");
  }
  const auto n_vertices = static_cast<std::int64_t>(mesh.vertices.size());
  const auto check_index = [&](std::int32_t v) {
    if (v < 0 || v >= n_vertices) throw_error(what, ": vertex index ", v, " out of range");
    return static_cast<unsigned int>(v);
  };
  std::vector<dealii::Point<3>> vertices;
  vertices.reserve(mesh.vertices.size());
  for (const geometry::Vec3& v : mesh.vertices) vertices.emplace_back(v[0], v[1], v[2]);

  // gmsh numbers a hexahedron's bottom face 0-1-2-3 and top 4-5-6-7 around the face; deal.II
  // numbers vertices lexicographically (x fastest), so 2 and 3 (and 6 and 7) swap.
  constexpr std::array<int, 8> kGmshToDealii{0, 1, 3, 2, 4, 5, 7, 6};
  std::vector<dealii::CellData<3>> cells(mesh.hexes.size());
  for (std::size_t h = 0; h < mesh.hexes.size(); ++h) {
    for (unsigned int v = 0; v < 8; ++v) cells[h].vertices[v] = check_index(mesh.hexes[h][kGmshToDealii[v]]);
    cells[h].material_id = material_of(mesh.hex_tags[h]);
  }
  dealii::SubCellData boundary;
  boundary.boundary_quads.resize(mesh.quads.size());
  for (std::size_t q = 0; q < mesh.quads.size(); ++q) {
    constexpr std::array<int, 4> kQuadToDealii{0, 1, 3, 2};
    for (unsigned int v = 0; v < 4; ++v) {
      boundary.boundary_quads[q].vertices[v] = check_index(mesh.quads[q][kQuadToDealii[v]]);
    }
    boundary.boundary_quads[q].boundary_id = boundary_of(mesh.quad_tags[q]);
  }
  try {
    dealii::GridTools::delete_unused_vertices(vertices, cells, boundary);
    dealii::GridTools::invert_all_negative_measure_cells(vertices, cells);
    dealii::GridTools::consistently_order_cells(cells);
    triangulation.create_triangulation(vertices, cells, boundary);
  } catch (const std::exception& e) {
    // deal.II's messages span many lines: keep one line (whitespace collapsed, shortened).
    std::string line;
    for (const char c : std::string(e.what())) {
      if (std::isspace(static_cast<unsigned char>(c))) {
        if (!line.empty() && line.back() != ' ') line += ' ';
      } else {
        line += c;
      }
    }
    if (line.size() > 300) line = line.substr(0, 300) + "...";
    throw_error(what, ": deal.II cannot build the triangulation: ", line);
  }
}

void build_hip_fe_model(ContactProblem& problem, const geometry::HexMesh& mesh,
                        const geometry::TriMesh& femur_bone, const geometry::Vec3& hjc_mm,
                        const HipFeOptions& options) {
  auto rigid_femur = std::make_shared<RigidMeshSurface>(femur_bone, "femur_bone");
  auto& triangulation = problem.triangulation();
  if (triangulation.n_cells() > 0) throw_error("fem hip model: the triangulation is not empty");
  create_hex_triangulation(mesh, triangulation, "hip volume mesh");

  const dealii::Point<3> hjc(hjc_mm[0], hjc_mm[1], hjc_mm[2]);
  if (options.spherical_manifold) {
    triangulation.set_all_manifold_ids(0);
    triangulation.set_manifold(0, dealii::SphericalManifold<3>(hjc));
  }

  const std::set<VolumeTag> tissues(mesh.hex_tags.begin(), mesh.hex_tags.end());
  const std::set<SurfaceTag> surfaces(mesh.quad_tags.begin(), mesh.quad_tags.end());
  const auto has = [&](SurfaceTag tag) { return surfaces.count(tag) > 0; };
  if (!tissues.count(VolumeTag::kFemoralCartilage) || !has(SurfaceTag::kFemoralCartilageArticular) ||
      !has(SurfaceTag::kFemoralCartilageBonded)) {
    throw_error("hip volume mesh: no femoral cartilage with articular and bonded faces");
  }
  const bool acetabular = tissues.count(VolumeTag::kAcetabularCartilage) &&
                          has(SurfaceTag::kAcetabularCartilageArticular);
  const bool labrum = tissues.count(VolumeTag::kLabrum) && has(SurfaceTag::kLabrumArticular);
  if (!acetabular && !labrum) {
    throw_error("hip volume mesh: no acetabular cartilage or labrum with an articular face");
  }

  const ElasticMaterial cartilage{literature::kCartilageYoungsModulusMPa,
                                  literature::kCartilagePoissonRatio};
  const ElasticMaterial labrum_material{literature::kLabrumYoungsModulusMPa,
                                        literature::kLabrumPoissonRatio};
  problem.model().bodies.clear();
  for (const VolumeTag tag : tissues) {
    const int rigid = tag == VolumeTag::kFemoralCartilage ? static_cast<int>(kFemurBody)
                                                          : static_cast<int>(kPelvisBody);
    const char* name = tag == VolumeTag::kFemoralCartilage      ? "femoral cartilage"
                       : tag == VolumeTag::kAcetabularCartilage ? "acetabular cartilage"
                                                                : "labrum";
    problem.model().bodies.push_back({name, material_of(tag),
                              tag == VolumeTag::kLabrum ? labrum_material : cartilage, rigid});
  }

  const dealii::Tensor<2, 3> identity = dealii::unit_symmetric_tensor<3>();
  problem.model().rigid_bodies.assign(2, RigidBody{});
  problem.model().rigid_bodies[kFemurBody] = {"femur", rigid_femur, {}, false, {}, {}, identity, hjc};
  problem.model().rigid_bodies[kPelvisBody] = {"pelvis", nullptr, {}, false, {}, {}, identity, hjc};

  problem.model().bonded_boundaries.clear();
  problem.model().bonded_boundaries.push_back(
      {boundary_of(SurfaceTag::kFemoralCartilageBonded), static_cast<int>(kFemurBody), {}});
  for (const SurfaceTag tag : {SurfaceTag::kAcetabularCartilageBonded, SurfaceTag::kLabrumBonded}) {
    if (has(tag)) problem.model().bonded_boundaries.push_back({boundary_of(tag), static_cast<int>(kPelvisBody), {}});
  }
  problem.model().symmetry_boundaries.clear();

  // Slave/master choice. Node-to-surface contact constrains the slave's nodes, so the slave should
  // be the side that resolves the pressure better: the rigid femur is always master (it has no
  // nodes); between the deformable tissues the acetabular side is slave. The acetabular cartilage
  // has the same moduli as the femoral cartilage but is a full 2 mm everywhere on its articular
  // face, where the femoral cartilage tapers to its blunted edge, so at equal edge length its
  // nodes sit where the pressure is; the labrum is stiffer (20 vs 12 MPa) but its articular
  // face is the smaller surface with a tip of high curvature, i.e. the finer side, and it must
  // conform to the femoral head, not the other way round.
  const auto femoral_articular = boundary_of(SurfaceTag::kFemoralCartilageArticular);
  problem.model().contact_pairs.clear();
  if (acetabular) {
    const auto slave = boundary_of(SurfaceTag::kAcetabularCartilageArticular);
    problem.model().contact_pairs.push_back({slave, -1, femoral_articular});
    problem.model().contact_pairs.push_back({slave, static_cast<int>(kFemurBody), 0});
  }
  if (labrum) {
    const auto slave = boundary_of(SurfaceTag::kLabrumArticular);
    problem.model().contact_pairs.push_back({slave, -1, femoral_articular});
    problem.model().contact_pairs.push_back({slave, static_cast<int>(kFemurBody), 0});
  }
}

std::vector<std::string> hip_fe_body_names(const ContactProblem& problem) {
  std::vector<std::string> names;
  for (const Body& body : problem.model().bodies) names.push_back(body.name);
  return names;
}

MotionStep make_hip_motion_step(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& force_n) {
  MotionStep step;
  for (unsigned int i = 0; i < 3; ++i) {
    for (unsigned int j = 0; j < 3; ++j) step.rotation[i][j] = rotation(i, j);
    step.force_n[i] = force_n[i];
  }
  return step;
}

Eigen::Vector3d constant_joint_force_n(double body_weight_n) {
  if (!(body_weight_n > 0.0)) throw_error("fem: body weight must be positive (got ", body_weight_n, " N)");
  return Eigen::Vector3d(0.0, 0.0, literature::kStandToSitPeakForcePercentBW / 100.0 * body_weight_n);
}

}  // namespace hipfai::fem
