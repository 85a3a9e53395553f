#include "geometry/hip_generator.h"

#include "geometry/gmsh_runtime.h"

#include "core/error.h"
#include "geometry/hip_frame.h"

#include <gmsh.h>

#include <chrono>
#include <cstdlib>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <queue>
#include <unordered_map>
#include <utility>

namespace hipfai::geometry {
namespace {

namespace occ = gmsh::model::occ;
using DimTags = gmsh::vectorpair;

// Holds the lock and a fresh model for one construction.
class GmshSession {
 public:
  explicit GmshSession(const std::string& name) : lock_(lock_gmsh()) {
    gmsh::clear();
    gmsh::model::add(name);
    // gmsh's own log only on request (HIPFAI_GMSH_VERBOSE=1), to diagnose a failed construction.
    gmsh::option::setNumber("General.Terminal", std::getenv("HIPFAI_GMSH_VERBOSE") != nullptr ? 1 : 0);
  }
  ~GmshSession() {
    // After a failed call the gmsh API rethrows its error from the next call: never from here.
    try {
      gmsh::clear();
    } catch (...) {
    }
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  std::unique_lock<std::mutex> lock_;
};

DimTags ball(const Vec3& centre, double radius) {
  DimTags sphere = {{3, occ::addSphere(centre.x(), centre.y(), centre.z(), radius)}};
  // OCC spheres have their poles and seam on the Z axis through the centre; turned about a
  // generic axis, the seam no longer runs into the hip's features (the surface mesher fails on
  // seam curves cut into tiny pieces there). The solid itself is unchanged.
  occ::rotate(sphere, centre.x(), centre.y(), centre.z(), 0.3, 0.5, 0.81, 0.9);
  return sphere;
}

DimTags cylinder(const Vec3& base, const Vec3& axis, double radius) {
  return {{3, occ::addCylinder(base.x(), base.y(), base.z(), axis.x(), axis.y(), axis.z(), radius)}};
}

DimTags cut(const DimTags& object, const DimTags& tool) {
  DimTags out;
  std::vector<DimTags> map;
  occ::cut(object, tool, out, map);
  return out;
}

DimTags intersect(const DimTags& object, const DimTags& tool) {
  DimTags out;
  std::vector<DimTags> map;
  occ::intersect(object, tool, out, map);
  return out;
}

DimTags fuse(const DimTags& object, const DimTags& tool) {
  DimTags out;
  std::vector<DimTags> map;
  occ::fuse(object, tool, out, map);
  return out;
}

// Half-space {x : x . normal <= 0} as a large cylinder (OCC has no unbounded solids).
DimTags half_space_below(const Vec3& normal, double size) {
  return cylinder(Vec3::Zero(), -size * normal, size);
}

Vec3 unit_perpendicular(const Vec3& axis, const Vec3& hint) {
  return (hint - hint.dot(axis) * axis).normalized();
}

struct TissueSolids {
  std::vector<std::pair<std::string, DimTags>> tissues;
};

// The five tissues as OCC solids in the current model (see hip_generator.h for the recipe).
TissueSolids build_solids(const HipParameters& p) {
  const double radius = p.articular_radius_mm;
  const double socket_radius = radius + p.acetabular_cartilage_mm;
  const double big = 4.0 * (p.pelvis_block_x_mm + p.pelvis_block_y_mm + p.pelvis_block_z_mm);
  const Vec3 n = neck_axis(p);
  const Vec3 a = acetabular_axis(p);
  TissueSolids solids;

  // --- femur -----------------------------------------------------------------------------
  // Head ball: centre s n, radius R - t + s, so the pole (-n) is t below the R sphere and the
  // two spheres meet at the cartilage edge angle phi_e from n:
  //   R^2 + s^2 - 2 R s cos(phi_e) = (R - t + s)^2  =>  s = (R^2 - (R-t)^2) / (2 (R - t + R cos phi_e)).
  const double inner = radius - p.femoral_cartilage_mm;
  const double edge = p.femoral_cartilage_edge_deg * kDegToRad;
  const double shift = (radius * radius - inner * inner) / (2.0 * (inner + radius * std::cos(edge)));
  const double head_radius = inner + shift;
  const double junction = std::min(p.alpha_deg, p.normal_alpha_deg) * kDegToRad;

  // Bone head: head ball within the R sphere, cut by the plane normal to n through the circle at
  // the junction angle; neck side of that plane is left to the neck cylinder, so the contour
  // leaves the sphere inwards there (a 90 - junction deg kink, easy to measure).
  DimTags head = intersect(ball(shift * n, head_radius), ball(Vec3::Zero(), radius));
  head = intersect(head, cylinder(radius * std::cos(junction) * n, -(3.0 * radius) * n, 2.0 * radius));
  DimTags bone = fuse(head, cylinder(Vec3::Zero(), p.neck_length_mm * n, p.neck_radius_mm));
  // Shaft stub along -Z, starting above the end of the neck so the tilted neck end is buried.
  const Vec3 neck_end = p.neck_length_mm * n;
  const double above = p.neck_radius_mm + 2.0;
  bone = fuse(bone, cylinder(neck_end + above * Vec3::UnitZ(),
                             -(above + p.shaft_length_mm) * Vec3::UnitZ(), p.shaft_radius_mm));

  DimTags cartilage_tools = ball(shift * n, head_radius);
  if (p.alpha_deg > p.normal_alpha_deg) {
    // Cam ball of radius rc standing h out of the R sphere: centre distance D = R + h - rc; its
    // intersection circle with the R sphere has angular radius delta seen from the HJC
    // (law of cosines). Placing the centre at alpha - delta from n in the cam plane puts the
    // circle's far point at exactly alpha there.
    const double rc = p.cam_radius_mm;
    const double distance = radius + p.cam_height_mm - rc;
    const double delta = std::acos((radius * radius + distance * distance - rc * rc) /
                                   (2.0 * radius * distance));
    const double centre_angle = p.alpha_deg * kDegToRad - delta;
    const Vec3 u = cam_direction(p);
    const Vec3 centre = distance * (std::cos(centre_angle) * n + std::sin(centre_angle) * u);
    bone = fuse(bone, ball(centre, rc));
    cartilage_tools.push_back(ball(centre, rc).front());
  }
  // The cartilage lens: R ball minus the head ball (and minus the cam, which replaces it).
  const DimTags femoral_cartilage = cut(ball(Vec3::Zero(), radius), cartilage_tools);
  solids.tissues.emplace_back("femur_bone", bone);
  solids.tissues.emplace_back("femoral_cartilage", femoral_cartilage);

  // --- acetabulum ---------------------------------------------------------------------------
  const Vec3 block_centre(-p.pelvis_block_x_mm / 4.0, 0.0, 0.1 * p.pelvis_block_z_mm);
  const Vec3 block_min = block_centre - 0.5 * Vec3(p.pelvis_block_x_mm, p.pelvis_block_y_mm,
                                                   p.pelvis_block_z_mm);
  DimTags block = {{3, occ::addBox(block_min.x(), block_min.y(), block_min.z(),
                                   p.pelvis_block_x_mm, p.pelvis_block_y_mm, p.pelvis_block_z_mm)}};
  block = intersect(block, half_space_below(a, big));
  const DimTags acetabular_bone = cut(block, ball(Vec3::Zero(), socket_radius));

  // Inferior rim direction (in the opening plane, towards -Z) and the fossa axis 30 deg from it
  // towards the acetabular pole -a.
  const Vec3 inferior_rim = unit_perpendicular(a, -Vec3::UnitZ());
  const double fossa_tilt = 30.0 * kDegToRad;
  const Vec3 fossa_axis = (std::cos(fossa_tilt) * inferior_rim - std::sin(fossa_tilt) * a).normalized();
  DimTags shell = cut(ball(Vec3::Zero(), socket_radius), ball(Vec3::Zero(), radius));
  shell = intersect(shell, half_space_below(a, big));
  const double fossa_radius =
      (radius + 0.5 * p.acetabular_cartilage_mm) * std::sin(p.fossa_half_angle_deg * kDegToRad);
  const DimTags acetabular_cartilage =
      cut(shell, cylinder(Vec3::Zero(), (socket_radius + 20.0) * fossa_axis, fossa_radius));

  // Labrum: triangular section in the meridian plane spanned by e (in the opening plane) and a,
  // revolved about a. The tip lies on the R sphere at labrum_height above the rim plane.
  const Vec3 e = unit_perpendicular(a, Vec3::UnitZ());
  const double tip_angle = std::asin(p.labrum_height_mm / radius);
  const Vec3 pa = radius * e;
  const Vec3 pb = (radius + p.labrum_base_mm) * e;
  const Vec3 pt = radius * (std::cos(tip_angle) * e + std::sin(tip_angle) * a);
  const int origin_tag = occ::addPoint(0, 0, 0);
  const int a_tag = occ::addPoint(pa.x(), pa.y(), pa.z());
  const int b_tag = occ::addPoint(pb.x(), pb.y(), pb.z());
  const int t_tag = occ::addPoint(pt.x(), pt.y(), pt.z());
  const int base_line = occ::addLine(a_tag, b_tag);
  const int outer_line = occ::addLine(b_tag, t_tag);
  const int inner_arc = occ::addCircleArc(t_tag, origin_tag, a_tag);
  const int loop = occ::addCurveLoop({base_line, outer_line, inner_arc});
  const int section = occ::addPlaneSurface({loop});
  DimTags revolved;
  occ::revolve({{2, section}}, 0, 0, 0, a.x(), a.y(), a.z(), 2.0 * std::numbers::pi, revolved);
  occ::remove({{0, origin_tag}});
  DimTags labrum;
  for (const auto& dim_tag : revolved) {
    if (dim_tag.first == 3) labrum.push_back(dim_tag);
  }
  occ::remove({{2, section}}, true);
  labrum = cut(labrum, cylinder(Vec3::Zero(), (radius + p.labrum_base_mm + 20.0) * inferior_rim,
                                0.5 * p.notch_width_mm));
  // Where the femoral neck passes under the rim in the neutral pose, the labrum stops short of
  // it. With a shallow socket (CE 0-10 deg) the opening plane through the HJC is nearly
  // vertical, so the posteroinferior rim comes within the neck's cone (the neck leaves the head
  // sphere asin(neck_radius / R) from its axis) and a full-height labrum there would stand inside
  // the bone before any motion. In a hip the labrum ends at the acetabular notch, which the
  // transverse acetabular ligament bridges below the head (Seldes et al. 2001), and is never
  // inside the neck; removing the labrum within the neck radius plus a clearance keeps the
  // soft tissue outside the bone. Hips whose rim stays clear of the neck are unchanged.
  labrum = cut(labrum, cylinder(Vec3::Zero(), p.neck_length_mm * n,
                                p.neck_radius_mm + p.labrum_neck_clearance_mm));

  solids.tissues.emplace_back("acetabular_bone", acetabular_bone);
  solids.tissues.emplace_back("acetabular_cartilage", acetabular_cartilage);
  solids.tissues.emplace_back("labrum", labrum);
  occ::synchronize();
  for (const auto& [name, dim_tags] : solids.tissues) {
    if (dim_tags.empty()) throw_error("hip generator: ", name, ": OpenCASCADE produced no solid");
  }
  return solids;
}

void set_mesh_options(double edge_mm) {
  gmsh::option::setNumber("Mesh.MeshSizeMax", edge_mm);
  gmsh::option::setNumber("Mesh.MeshSizeMin", 0.1 * edge_mm);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
  gmsh::option::setNumber("Mesh.Algorithm", 6);  // Frontal-Delaunay: well-shaped triangles
  gmsh::option::setNumber("General.NumThreads", 1);
}

// Runs gmsh::model::mesh::generate(dim) and returns its error messages (empty on success). The
// mesher reports errors from inside OpenMP regions, where a thrown exception would terminate the
// process, so errors are logged (AbortOnError 0) and collected instead of thrown.
std::string generate_logging_errors(int dim) {
  gmsh::option::setNumber("General.AbortOnError", 0);
  gmsh::logger::start();
  gmsh::model::mesh::generate(dim);
  std::vector<std::string> log;
  gmsh::logger::get(log);
  gmsh::logger::stop();
  gmsh::option::setNumber("General.AbortOnError", 2);
  std::string errors;
  for (const auto& line : log) {
    if (line.rfind("Error", 0) == 0) errors += (errors.empty() ? "" : "; ") + line;
  }
  return errors;
}

// Surface mesh of every entity. Frontal-Delaunay gives the best triangles but can fail on the
// small seam curves OCC leaves on spheres at coarse sizes; MeshAdapt and Delaunay are the fallbacks.
void mesh_surfaces(double edge_mm) {
  std::string failures;
  for (int algorithm : {6, 1, 5}) {
    set_mesh_options(edge_mm);
    gmsh::option::setNumber("Mesh.Algorithm", algorithm);
    const std::string errors = generate_logging_errors(2);
    if (errors.empty()) return;
    failures += (failures.empty() ? "" : " | ") + errors;
    gmsh::model::mesh::clear();
  }
  throw failures;
}

// Makes neighbouring triangles traverse shared edges in opposite directions (breadth-first from
// one triangle per component), then flips a component whose enclosed volume is negative.
void orient_outward(TriMesh& mesh) {
  const std::size_t count = mesh.triangles.size();
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> edge_triangles;
  auto key = [](std::int32_t u, std::int32_t v) {
    const auto lo = static_cast<std::uint64_t>(std::min(u, v));
    const auto hi = static_cast<std::uint64_t>(std::max(u, v));
    return (lo << 32) | hi;
  };
  for (std::size_t t = 0; t < count; ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) edge_triangles[key(tri[k], tri[(k + 1) % 3])].push_back(t);
  }
  auto has_directed = [](const Triangle& tri, std::int32_t u, std::int32_t v) {
    for (int k = 0; k < 3; ++k) {
      if (tri[k] == u && tri[(k + 1) % 3] == v) return true;
    }
    return false;
  };
  std::vector<int> component(count, -1);
  int components = 0;
  for (std::size_t seed = 0; seed < count; ++seed) {
    if (component[seed] >= 0) continue;
    std::queue<std::size_t> queue;
    queue.push(seed);
    component[seed] = components;
    while (!queue.empty()) {
      const std::size_t t = queue.front();
      queue.pop();
      const Triangle tri = mesh.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const std::int32_t u = tri[k];
        const std::int32_t v = tri[(k + 1) % 3];
        for (std::size_t other : edge_triangles[key(u, v)]) {
          if (other == t || component[other] >= 0) continue;
          // A consistent neighbour traverses the edge as v -> u.
          if (has_directed(mesh.triangles[other], u, v)) std::swap(mesh.triangles[other][1], mesh.triangles[other][2]);
          component[other] = components;
          queue.push(other);
        }
      }
    }
    ++components;
  }
  // Signed volume per component (divergence theorem), flip the negative ones.
  std::vector<double> volume(static_cast<std::size_t>(components), 0.0);
  for (std::size_t t = 0; t < count; ++t) {
    const auto& tri = mesh.triangles[t];
    volume[static_cast<std::size_t>(component[t])] +=
        mesh.vertices[static_cast<std::size_t>(tri[0])].dot(
            mesh.vertices[static_cast<std::size_t>(tri[1])].cross(mesh.vertices[static_cast<std::size_t>(tri[2])])) / 6.0;
  }
  for (std::size_t t = 0; t < count; ++t) {
    if (volume[static_cast<std::size_t>(component[t])] < 0.0) std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
  }
}

// The surface triangles of `volumes` as one TriMesh (nodes shared between its surfaces).
struct NodeTable {
  std::unordered_map<std::size_t, std::size_t> slot;  // node tag -> index into coords / 3
  std::vector<double> coords;
};

NodeTable all_nodes() {
  NodeTable table;
  std::vector<std::size_t> tags;
  std::vector<double> parametric;
  gmsh::model::mesh::getNodes(tags, table.coords, parametric, -1, -1, true, false);
  for (std::size_t i = 0; i < tags.size(); ++i) table.slot.emplace(tags[i], i);
  return table;
}

TriMesh extract_surface(const DimTags& volumes, const std::string& name, const NodeTable& nodes_table) {
  DimTags surfaces;
  gmsh::model::getBoundary(volumes, surfaces, true, false, false);
  TriMesh mesh;
  std::unordered_map<std::size_t, std::int32_t> index_of;
  for (const auto& [dim, tag] : surfaces) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> element_tags, node_tags;
    gmsh::model::mesh::getElements(types, element_tags, node_tags, dim, std::abs(tag));
    for (std::size_t k = 0; k < types.size(); ++k) {
      if (types[k] != 2) throw_error("hip generator: ", name, ": unexpected element type ", types[k]);
      const auto& nodes = node_tags[k];
      for (std::size_t i = 0; i + 2 < nodes.size(); i += 3) {
        Triangle tri{};
        for (int c = 0; c < 3; ++c) {
          const std::size_t node = nodes[i + static_cast<std::size_t>(c)];
          auto [it, inserted] = index_of.try_emplace(node, static_cast<std::int32_t>(mesh.vertices.size()));
          if (inserted) {
            const auto found = nodes_table.slot.find(node);
            if (found == nodes_table.slot.end()) throw_error("hip generator: ", name, ": unknown mesh node");
            const double* xyz = &nodes_table.coords[3 * found->second];
            mesh.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
          }
          tri[static_cast<std::size_t>(c)] = it->second;
        }
        mesh.triangles.push_back(tri);
      }
    }
  }
  if (mesh.empty()) throw_error("hip generator: ", name, ": the surface mesh is empty");
  orient_outward(mesh);
  return mesh;
}

}  // namespace

HipGeneratorResult generate_hip(const HipParameters& parameters) {
  validate_hip_parameters(parameters);
  const auto start = std::chrono::steady_clock::now();
  HipGeneratorResult result;
  GmshSession session("hip");
  try {
    const TissueSolids solids = build_solids(parameters);
    mesh_surfaces(parameters.edge_mm);
    const NodeTable table = all_nodes();
    for (const auto& [name, volumes] : solids.tissues) {
      result.model.tissues.emplace(name, extract_surface(volumes, name, table));
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw_error("hip generator (ce ", parameters.ce_deg, ", alpha ", parameters.alpha_deg,
                "): gmsh failed: ", e.what());
  } catch (const std::string& message) {  // the gmsh API throws its last error as a string
    throw_error("hip generator (ce ", parameters.ce_deg, ", alpha ", parameters.alpha_deg,
                "): gmsh failed: ", message);
  }
  HipModel& model = result.model;
  model.parameters = parameters;
  model.hjc_mm = Vec3::Zero();
  model.axes = HipFrameAxes{};
  model.neck_axis = neck_axis(parameters);
  model.superior = Vec3::UnitZ();
  model.lateral = Vec3::UnitX();
  model.acetabular_axis = acetabular_axis(parameters);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.status = HipGeneratorResult::Status::ok;
  return result;
}

}  // namespace hipfai::geometry
