// hipfai — SVG figures for reports: line charts, annotated heat maps and depth-coloured meshes.
//
// Plain SVG (opens in any browser, embeds in Markdown/HTML); files are written atomically.
#pragma once

#include "geometry/tri_mesh.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

struct Series {
  std::string name;
  std::vector<double> x, y;
  bool dashed = false;
};

struct LineChart {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  bool log_x = false, log_y = false;  // log10 axes (scaling plots); non-positive values skipped
};

// Rows are drawn top to bottom, columns left to right; NaN cells are grey and labelled "n/a".
struct HeatMap {
  std::string title, row_label, column_label, unit;
  std::vector<std::string> row_names, column_names;
  std::vector<std::vector<double>> values;  // [row][column]
  bool diverging = false;                   // blue-white-red around 0 instead of white-to-red
  std::vector<std::vector<std::string>> cell_text;  // optional text per cell (replaces the value)
};

void write_svg(const LineChart& chart, const std::filesystem::path& path);
void write_svg(const HeatMap& map, const std::filesystem::path& path);

// Orthographic view of meshes along `view_direction` (up = `up`), triangles painted back to front,
// coloured by the per-vertex `field` of each mesh (white at 0 to red at `max_value`) with Lambert
// shading; meshes without the field are drawn light grey.
void write_mesh_svg(const std::vector<const geometry::TriMesh*>& meshes, const std::string& field,
                    double max_value, const geometry::Vec3& view_direction, const geometry::Vec3& up,
                    const std::string& title, const std::filesystem::path& path);

}  // namespace hipfai::studies
