// hipfai rom: exact range of motion of a mobile mesh (femur) about an axis through a centre (HJC)
// against a fixed mesh (pelvis), by the joint range finder (thesis §4.2): both directions in one
// pass, no stepping. Optionally a fan of axes in a plane (thesis Fig. 56) or a grid of axes on a
// hemisphere, with a CSV table.
#include "app/cli_util.h"
#include "app/command_registry.h"
#include "contact/range_finder.h"
#include "contact/start_pose.h"
#include "core/error.h"
#include "geometry/mesh_io.h"

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace hipfai::app {
namespace {

struct RomArgs {
  std::string fixed;
  std::string mobile;
  std::vector<double> centre;
  std::vector<double> axis;
  std::vector<double> fan_plane_normal;
  int fan_steps = 12;
  std::vector<double> sphere_pole;
  int polar_steps = 3;
  int azimuth_steps = 8;
  int threads = 0;
  double resolution_mm = 0.0;
  bool no_fixed_vertices = false;
  bool no_edge_edge = false;
  bool allow_start_overlap = false;
  double touching_mm = contact::kStartPoseTouchingMm;
  std::string csv;
};

const char* kind_name(contact::ContactKind kind) {
  switch (kind) {
    case contact::ContactKind::kMobileVertexOnFixedTriangle: return "mobile_vertex";
    case contact::ContactKind::kFixedVertexOnMobileTriangle: return "fixed_vertex";
    case contact::ContactKind::kEdgeOnEdge: return "edge_edge";
    case contact::ContactKind::kNone: break;
  }
  return "none";
}

std::string describe(double angle_deg, const contact::LimitingContact& limit) {
  char buffer[160];
  if (limit.kind == contact::ContactKind::kNone) {
    std::snprintf(buffer, sizeof(buffer), "%9.4f deg  (no contact within a full turn)", angle_deg);
  } else if (limit.kind == contact::ContactKind::kMobileVertexOnFixedTriangle) {
    std::snprintf(buffer, sizeof(buffer), "%9.4f deg  (mobile vertex %d on fixed triangle %d)",
                  angle_deg, limit.vertex, limit.triangle);
  } else if (limit.kind == contact::ContactKind::kEdgeOnEdge) {
    std::snprintf(buffer, sizeof(buffer), "%9.4f deg  (mobile edge %d-%d on fixed edge %d-%d)", angle_deg,
                  limit.mobile_edge[0], limit.mobile_edge[1], limit.fixed_edge[0], limit.fixed_edge[1]);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%9.4f deg  (fixed vertex %d on mobile triangle %d)",
                  angle_deg, limit.vertex, limit.triangle);
  }
  return buffer;
}

void check(const contact::RangeOfMotion& range) {
  if (range.status == contact::QueryStatus::kInvalidInput) throw_error("rom: ", range.message);
}

// One direction's limiting contact as CSV fields: kind, vertex, triangle, mobile edge, fixed edge.
// Only the fields of that kind of contact are written; the others are left empty (a vertex contact
// has no edges, an edge-edge contact no vertex/triangle, "none" nothing). Edges are "a-b", the
// indices of their two vertices in the mobile and the fixed mesh.
std::string contact_fields(const contact::LimitingContact& limit) {
  std::string fields = kind_name(limit.kind);
  fields += ',';
  const bool vertex_contact = limit.kind == contact::ContactKind::kMobileVertexOnFixedTriangle ||
                              limit.kind == contact::ContactKind::kFixedVertexOnMobileTriangle;
  if (vertex_contact) {
    fields += std::to_string(limit.vertex) + ',' + std::to_string(limit.triangle) + ",,";
  } else if (limit.kind == contact::ContactKind::kEdgeOnEdge) {
    fields += ",," + std::to_string(limit.mobile_edge[0]) + '-' + std::to_string(limit.mobile_edge[1]) + ',' +
              std::to_string(limit.fixed_edge[0]) + '-' + std::to_string(limit.fixed_edge[1]);
  } else {
    fields += ",,,";
  }
  return fields;
}

void write_csv(const std::string& path, const std::vector<contact::AxisRangeOfMotion>& rows) {
  write_text_atomically(path, [&](std::ostream& out) {
    out << "axis_x,axis_y,axis_z,angle_deg,azimuth_deg,anticlockwise_deg,clockwise_deg,"
           "anticlockwise_contact,anticlockwise_vertex,anticlockwise_triangle,"
           "anticlockwise_mobile_edge,anticlockwise_fixed_edge,"
           "clockwise_contact,clockwise_vertex,clockwise_triangle,clockwise_mobile_edge,clockwise_fixed_edge\n";
    out.precision(10);
    for (const auto& row : rows) {
      const auto& r = row.range;
      out << row.axis.x() << ',' << row.axis.y() << ',' << row.axis.z() << ',' << row.angle_deg
          << ',' << row.azimuth_deg << ',' << r.anticlockwise_deg << ',' << r.clockwise_deg << ','
          << contact_fields(r.anticlockwise_limit) << ',' << contact_fields(r.clockwise_limit) << '\n';
    }
  });
}

// The range finder assumes the start pose is free (range_finder.h): on bodies that already
// intersect it would report the rotation to the first crossing of any vertex, a small positive
// range that means nothing. Refuse, or with --allow-start-overlap warn and go on.
void refuse_start_overlap(const geometry::TriMesh& fixed, const geometry::TriMesh& mobile,
                          const Eigen::Vector3d& centre, const RomArgs& args) {
  contact::StartPoseOptions options;
  options.touching_mm = args.touching_mm;
  options.centre = centre;
  options.num_threads = args.threads == 1 ? 1 : 2;
  const contact::StartPoseOverlap overlap = contact::check_start_pose(fixed, mobile, options);
  if (overlap.status == contact::QueryStatus::kInvalidInput) throw_error("rom: ", overlap.message);
  if (!overlap.overlaps()) return;
  if (!args.allow_start_overlap) {
    throw_error("the bodies already intersect in the start pose: ", overlap.summary(),
                "; a range of motion from this pose is meaningless (use --allow-start-overlap to report the "
                "range to the first crossing anyway)");
  }
  std::fprintf(stderr,
               "hipfai: warning: the bodies already intersect in the start pose: %s; the ranges below run "
               "from this intersecting pose to the first new contact\n",
               overlap.summary().c_str());
}

void run(const RomArgs& args) {
  const Eigen::Vector3d centre = to_vec3(args.centre, "--center-mm");
  const bool fan = !args.fan_plane_normal.empty();
  const bool sphere = !args.sphere_pole.empty();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  if (!fan && !sphere) {
    if (args.axis.empty()) throw_error("--axis: required unless --fan-plane-normal or --sphere-pole is given");
    axis = to_vec3(args.axis, "--axis");
    if (!(axis.norm() > 0.0)) throw_error("--axis: the axis has zero length");
  }
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
  if (fan) direction = to_vec3(args.fan_plane_normal, "--fan-plane-normal");
  if (sphere) direction = to_vec3(args.sphere_pole, "--sphere-pole");
  if ((fan || sphere) && !(direction.norm() > 0.0)) {
    throw_error(fan ? "--fan-plane-normal" : "--sphere-pole", ": the vector has zero length");
  }
  const geometry::TriMesh fixed = geometry::read_mesh(args.fixed);
  const geometry::TriMesh mobile = geometry::read_mesh(args.mobile);
  refuse_start_overlap(fixed, mobile, centre, args);

  contact::RangeOfMotionOptions options;
  options.include_fixed_vertices = !args.no_fixed_vertices;
  options.include_edge_edge = !args.no_edge_edge;
  options.query.num_threads = args.threads;
  options.table.resolution_r_mm = options.table.resolution_z_mm = args.resolution_mm;

  std::vector<contact::AxisRangeOfMotion> rows;
  if (fan) {
    rows = contact::range_of_motion_fan(fixed, mobile, centre, direction, args.fan_steps, options);
  } else if (sphere) {
    rows = contact::range_of_motion_sphere(fixed, mobile, centre, direction, args.polar_steps,
                                           args.azimuth_steps, options);
  } else {
    contact::AxisRangeOfMotion row;
    row.axis = axis.normalized();
    row.range = contact::range_of_motion(fixed, mobile, centre, axis, options);
    rows.push_back(row);
  }
  for (const auto& row : rows) check(row.range);

  std::printf("range of motion of %s against %s, centre (%.3f, %.3f, %.3f) mm\n",
              args.mobile.c_str(), args.fixed.c_str(), centre.x(), centre.y(), centre.z());
  if (!fan && !sphere) {
    const auto& r = rows.front();
    std::printf("axis (%.6f, %.6f, %.6f), right-hand rule\n", r.axis.x(), r.axis.y(), r.axis.z());
    std::printf("  anticlockwise %s\n", describe(r.range.anticlockwise_deg, r.range.anticlockwise_limit).c_str());
    std::printf("  clockwise     %s\n", describe(r.range.clockwise_deg, r.range.clockwise_limit).c_str());
  } else {
    std::printf("%10s %10s %28s %14s %14s\n", fan ? "angle_deg" : "polar_deg", "azimuth", "axis",
                "anticlockwise", "clockwise");
    for (const auto& r : rows) {
      std::printf("%10.3f %10.3f  (%7.4f, %7.4f, %7.4f) %10.4f deg %10.4f deg\n", r.angle_deg,
                  r.azimuth_deg, r.axis.x(), r.axis.y(), r.axis.z(), r.range.anticlockwise_deg,
                  r.range.clockwise_deg);
    }
  }
  if (!args.csv.empty()) write_csv(args.csv, rows);
}

const CommandRegistrar rom_registrar("rom", [](CLI::App& parent) {
  auto* command = parent.add_subcommand(
      "rom", "Exact range of motion (both directions) of a mobile mesh about an axis, in one pass");
  auto args = std::make_shared<RomArgs>();
  command->add_option("--fixed", args->fixed, "Fixed mesh, e.g. the pelvis (STL, OBJ, PLY, VTP, MSH)")
      ->required()->check(CLI::ExistingFile);
  command->add_option("--mobile", args->mobile, "Mobile mesh at its start pose, e.g. the femur")
      ->required()->check(CLI::ExistingFile);
  add_vec3_option(command, "--center-mm", args->centre, "Rotation centre (the HJC), mm")->required();
  auto* axis = add_vec3_option(command, "--axis", args->axis, "Rotation axis (any length)");
  auto* fan = add_vec3_option(command, "--fan-plane-normal", args->fan_plane_normal,
                              "Sweep axes in the plane with this normal (thesis Fig. 56)");
  command->add_option("--fan-steps", args->fan_steps, "Axes in the fan, over 180 degrees")
      ->check(CLI::Range(1, 3600));
  auto* sphere = add_vec3_option(command, "--sphere-pole", args->sphere_pole,
                                 "Sweep a grid of axes on the hemisphere about this pole");
  command->add_option("--polar-steps", args->polar_steps, "Sphere grid: rings from pole to equator")
      ->check(CLI::Range(1, 180));
  command->add_option("--azimuth-steps", args->azimuth_steps, "Sphere grid: axes per ring")
      ->check(CLI::Range(1, 360));
  fan->excludes(axis);
  sphere->excludes(axis);
  sphere->excludes(fan);
  command->add_option("--resolution-mm", args->resolution_mm,
                      "Ring table resolution (default: mean edge length of each table's mesh)")
      ->check(CLI::Range(0.0, 1e6));
  command->add_flag("--no-fixed-vertices", args->no_fixed_vertices,
                    "Only mobile vertices against fixed triangles (skip the swapped pass)");
  command->add_flag("--no-edge-edge", args->no_edge_edge,
                    "Vertex contacts only (the thesis' finder; skip the exact edge-edge pass)");
  command->add_flag("--allow-start-overlap", args->allow_start_overlap,
                    "Bodies intersecting in the start pose: warn and report the ranges to the first "
                    "crossing instead of failing");
  command->add_option("--touching-mm", args->touching_mm,
                      "Start-pose check: vertices and edges at most this deep in the other body only touch")
      ->check(CLI::Range(0.0, 1e3));
  command->add_option("--threads", args->threads, "Threads (0 = all)")->check(CLI::Range(0, 256));
  command->add_option("--csv", args->csv,
                      "CSV table: one row per axis; per direction the contact kind and its vertex + "
                      "triangle (vertex contacts) or mobile + fixed edge as a-b (edge-edge), others empty");
  command->callback([args] { run(*args); });
});

}  // namespace
}  // namespace hipfai::app
