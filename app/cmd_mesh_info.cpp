// hipfai mesh-info FILE [--json]: reads a surface mesh and reports its size, geometry and the
// defects (holes, non-manifold edges, flipped triangles, ...) that would make a study on it wrong.
#include "app/command_registry.h"
#include "core/error.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

namespace hipfai::app {
namespace {

struct MeshInfoOptions {
  std::string file;
  bool json = false;
};

nlohmann::ordered_json report_json(const std::string& file, geometry::MeshFormat format,
                                   const geometry::TriMesh& mesh, const geometry::MeshReport& r) {
  nlohmann::ordered_json out;
  out["file"] = file;
  out["format"] = geometry::to_string(format);
  out["units"] = "mm";
  out["num_vertices"] = r.num_vertices;
  out["num_triangles"] = r.num_triangles;
  out["unreferenced_vertices"] = r.unreferenced_vertices;
  out["bounding_box_mm"] = {{"min", {r.bounds.min.x(), r.bounds.min.y(), r.bounds.min.z()}},
                            {"max", {r.bounds.max.x(), r.bounds.max.y(), r.bounds.max.z()}}};
  out["surface_area_mm2"] = r.surface_area_mm2;
  out["signed_volume_mm3"] = r.signed_volume_mm3;
  out["mean_edge_length_mm"] = r.mean_edge_length_mm;
  out["num_edges"] = r.num_edges;
  out["boundary_edges"] = r.boundary_edges;
  out["non_manifold_edges"] = r.non_manifold_edges;
  out["non_manifold_vertices"] = r.non_manifold_vertices;
  out["degenerate_triangles"] = r.degenerate_triangles;
  out["sliver_triangles"] = r.sliver_triangles;
  out["duplicate_triangles"] = r.duplicate_triangles;
  out["inconsistent_edges"] = r.inconsistent_edges;
  out["connected_components"] = r.connected_components;
  out["closed"] = r.closed;
  out["orientation_consistent"] = r.orientation_consistent;
  out["outward"] = r.outward;
  out["watertight_manifold"] = r.watertight_manifold;
  nlohmann::ordered_json fields = nlohmann::ordered_json::array();
  for (const auto& [name, values] : mesh.vertex_fields) fields.push_back(name);
  out["vertex_fields"] = fields;
  return out;
}

std::string yes_no(bool value) { return value ? "yes" : "no"; }

void print_table(const std::string& file, geometry::MeshFormat format,
                 const geometry::TriMesh& mesh, const geometry::MeshReport& r, double read_s) {
  auto row = [](const char* label, const std::string& value) {
    std::printf("  %-24s %s\n", label, value.c_str());
  };
  auto number = [](double value, const char* format_string) {
    char buffer[96];
    std::snprintf(buffer, sizeof(buffer), format_string, value);
    return std::string(buffer);
  };
  auto vec = [&](const geometry::Vec3& v) {
    char buffer[128];
    std::snprintf(buffer, sizeof(buffer), "(%.3f, %.3f, %.3f)", v.x(), v.y(), v.z());
    return std::string(buffer);
  };
  std::printf("%s (%s, read in %.3f s)\n", file.c_str(), geometry::to_string(format).c_str(), read_s);
  row("vertices", std::to_string(r.num_vertices) + " (" + std::to_string(r.unreferenced_vertices) +
                      " unreferenced)");
  row("triangles", std::to_string(r.num_triangles));
  row("edges", std::to_string(r.num_edges));
  row("bounding box min (mm)", vec(r.bounds.min));
  row("bounding box max (mm)", vec(r.bounds.max));
  row("extent (mm)", vec(r.bounds.extent()));
  row("surface area (mm^2)", number(r.surface_area_mm2, "%.3f"));
  row("signed volume (mm^3)", number(r.signed_volume_mm3, "%.3f"));
  row("mean edge length (mm)", number(r.mean_edge_length_mm, "%.4f"));
  row("boundary edges", std::to_string(r.boundary_edges));
  row("non-manifold edges", std::to_string(r.non_manifold_edges));
  row("non-manifold vertices", std::to_string(r.non_manifold_vertices));
  row("degenerate triangles", std::to_string(r.degenerate_triangles));
  row("sliver triangles", std::to_string(r.sliver_triangles) + " (min angle < 1e-3 rad)");
  row("duplicate triangles", std::to_string(r.duplicate_triangles));
  row("inconsistent edges", std::to_string(r.inconsistent_edges));
  row("connected components", std::to_string(r.connected_components));
  row("closed", yes_no(r.closed));
  row("orientation consistent", yes_no(r.orientation_consistent));
  row("outward", yes_no(r.outward));
  row("watertight manifold", yes_no(r.watertight_manifold));
  std::string fields;
  for (const auto& [name, values] : mesh.vertex_fields) fields += (fields.empty() ? "" : ", ") + name;
  row("vertex fields", fields.empty() ? "(none)" : fields);
}

void run_mesh_info(const MeshInfoOptions& options) {
  const geometry::MeshFormat format = geometry::mesh_format_from_path(options.file);
  const auto start = std::chrono::steady_clock::now();
  const geometry::TriMesh mesh = geometry::read_mesh(options.file);
  const double read_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const geometry::MeshReport report = geometry::check_mesh(mesh);
  if (options.json) {
    std::cout << report_json(options.file, format, mesh, report).dump(2) << '\n';
  } else {
    print_table(options.file, format, mesh, report, read_s);
  }
}

const CommandRegistrar mesh_info_registrar{"mesh-info", [](CLI::App& parent) {
  auto options = std::make_shared<MeshInfoOptions>();
  CLI::App* command = parent.add_subcommand(
      "mesh-info",
      "Read a surface mesh (.stl, .obj, .ply, .vtp, .msh) and report its size, geometry and defects");
  command->add_option("FILE", options->file, "Mesh file")->required()->check(CLI::ExistingFile);
  command->add_flag("--json", options->json, "Print the report as JSON");
  command->callback([options] { run_mesh_info(*options); });
}};

}  // namespace
}  // namespace hipfai::app
