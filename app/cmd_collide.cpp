// hipfai collide: one pose, one method, every penetrating vertex with its depth.
#include "app/cli_util.h"
#include "app/command_registry.h"
#include "contact/cylindrical_segmenting.h"
#include "contact/radial_segmenting.h"
#include "contact/start_pose.h"
#include "geometry/hip_frame.h"
#include "geometry/mesh_io.h"
#include "studies/pipeline/radial_mapping_name.h"

#include <iomanip>
#include <iostream>
#include <map>

namespace hipfai::app {
namespace {

struct CollideArgs {
  std::string fixed, mobile, method = "radial", mapping = "cube", out, vtp;
  std::vector<double> centre, axis;
  double angle_deg = 0.0;
  long long table_size = 0;
  bool swap = false, fixed_inside_mobile = false;
  int threads = 0;
  double touching_mm = contact::kStartPoseTouchingMm;
};

void run(const CollideArgs& args) {
  const geometry::TriMesh fixed = geometry::read_mesh(args.fixed);
  geometry::TriMesh mobile = geometry::read_mesh(args.mobile);
  const Eigen::Vector3d centre = to_vec3(args.centre, "--center-mm");
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  if (!args.axis.empty()) axis = to_vec3(args.axis, "--axis");
  if (axis.norm() < 1e-12) throw_error("--axis: the axis has zero length");
  axis.normalize();
  if (args.method == "cylindrical" && args.axis.empty()) {
    throw_error("--axis: required by the cylindrical method");
  }
  // Depths at a pose stay well defined when the bodies already intersect at angle 0, but they then
  // include that overlap, which is rarely meant: say so (warning, not an error).
  contact::StartPoseOptions start_options;
  start_options.touching_mm = args.touching_mm;
  start_options.centre = centre;
  start_options.num_threads = args.threads == 1 ? 1 : 2;
  const contact::StartPoseOverlap start = contact::check_start_pose(fixed, mobile, start_options);
  if (start.status == contact::QueryStatus::kInvalidInput) throw_error(start.message);
  if (start.overlaps()) {
    std::cerr << "hipfai: warning: the bodies already intersect in the start pose (angle 0): " << start.summary()
              << "; the depths include this overlap\n";
  }
  // Pose the mobile mesh: A degrees about the axis through the centre, right-hand rule.
  geometry::rotate_about_axis(mobile, centre, axis, args.angle_deg * geometry::kDegToRad);

  // With --swap the vertices of the fixed mesh are tested against the posed mobile triangles.
  const geometry::TriMesh& vertices_of = args.swap ? fixed : mobile;
  const geometry::TriMesh& triangles_of = args.swap ? mobile : fixed;
  contact::PenetrationResult result;
  if (args.method == "cylindrical") {
    contact::CylindricalQueryOptions options;
    options.num_threads = args.threads;
    result = contact::cylindrical_segmenting(triangles_of, vertices_of, centre, axis, options);
  } else {
    contact::RadialTableOptions table_options;
    table_options.mapping = *studies::radial_mapping_from_name(args.mapping);  // checked by IsMember
    table_options.table_size =
        args.table_size > 0 ? args.table_size
                            : std::max<long long>(64, static_cast<long long>(triangles_of.num_triangles()));
    contact::RadialQueryOptions options;
    options.num_threads = args.threads > 0 ? args.threads : 2;
    options.configuration = args.fixed_inside_mobile ? contact::RadialConfiguration::kFixedInsideMobile
                                                     : contact::RadialConfiguration::kMobileInsideFixed;
    if (args.swap) options.configuration = contact::swapped(options.configuration);
    const auto table = contact::build_radial_table(triangles_of, centre, table_options);
    result = contact::radial_segmenting(table, triangles_of, vertices_of, options);
  }
  if (result.status == contact::QueryStatus::kInvalidInput) throw_error(result.message);

  const std::string vertex_column = args.swap ? "fixed_vertex" : "mobile_vertex";
  const std::string triangle_column = args.swap ? "mobile_triangle" : "fixed_triangle";
  const bool cylindrical = args.method == "cylindrical";
  if (!args.out.empty()) {
    write_text_atomically(args.out, [&](std::ostream& out) {
      out << vertex_column << ',' << triangle_column << ",depth_mm" << (cylindrical ? ",angle_deg" : "")
          << '\n'
          << std::setprecision(17);
      for (const auto& pair : result.pairs) {
        out << pair.mobile_vertex << ',' << pair.fixed_triangle << ',' << pair.depth_mm;
        if (cylindrical) out << ',' << pair.angle_deg;
        out << '\n';
      }
    });
  }
  if (!args.vtp.empty()) {
    geometry::TriMesh coloured = vertices_of;
    std::vector<double>& depth = coloured.vertex_fields["depth_mm"];
    depth.assign(coloured.num_vertices(), 0.0);
    for (const auto& pair : result.pairs) depth[static_cast<std::size_t>(pair.mobile_vertex)] = pair.depth_mm;
    geometry::write_mesh(coloured, args.vtp);
  }
  std::cout << args.method << (args.swap ? " (roles swapped)" : "") << ": "
            << result.pairs.size() << " penetrating vertices of " << vertices_of.num_vertices()
            << ", max depth " << std::setprecision(6) << result.max_depth_mm() << " mm\n";
}

const CommandRegistrar collide_registrar("collide", [](CLI::App& parent) {
  auto* command = parent.add_subcommand(
      "collide", "Penetrating vertices and depths of a mobile mesh rotated about an axis");
  auto args = std::make_shared<CollideArgs>();
  command->add_option("--fixed", args->fixed, "Fixed mesh (STL, OBJ, PLY, VTP, MSH)")
      ->required()->check(CLI::ExistingFile);
  command->add_option("--mobile", args->mobile, "Mobile mesh, posed by the rotation")
      ->required()->check(CLI::ExistingFile);
  add_vec3_option(command, "--center-mm", args->centre, "Rotation centre / radial origin, mm")->required();
  add_vec3_option(command, "--axis", args->axis, "Rotation axis (any length)");
  command->add_option("--angle-deg", args->angle_deg, "Rotation of the mobile mesh, right-hand rule")
      ->check(CLI::Range(-360.0, 360.0));
  command->add_option("--method", args->method, "cylindrical (curvilinear depth) or radial")
      ->check(CLI::IsMember({"cylindrical", "radial"}));
  command->add_option("--mapping", args->mapping, "Radial mapping function")
      ->check(CLI::IsMember({"spherical", "cartesian", "cube"}));
  command->add_option("--table-size", args->table_size, "Radial table cells (default: #fixed triangles)")
      ->check(CLI::Range(6LL, 100000000LL));
  command->add_flag("--swap", args->swap, "Exchange roles: fixed-mesh vertices against mobile triangles");
  command->add_flag("--fixed-inside-mobile", args->fixed_inside_mobile,
                    "Radial: the fixed mesh lies inside the mobile one (default: mobile inside fixed)");
  command->add_option("--touching-mm", args->touching_mm,
                      "Start-pose check: vertices and edges at most this deep in the other body only touch")
      ->check(CLI::Range(0.0, 1e3));
  command->add_option("--threads", args->threads, "Threads (0 = all)")->check(CLI::Range(0, 256));
  command->add_option("--out", args->out, "CSV of pairs: vertex, triangle, depth_mm[, angle_deg]");
  command->add_option("--vtp", args->vtp, "VTP of the tested mesh with a per-vertex depth_mm field");
  command->callback([args] { run(*args); });
});

}  // namespace
}  // namespace hipfai::app
