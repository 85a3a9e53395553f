// hipfai — SVG figures for reports: line charts, annotated heat maps and depth-coloured meshes.
//
// Plain SVG (opens in any browser, embeds in Markdown/HTML); files are written atomically.
#pragma once

#include "geometry/tri_mesh.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hipfai::studies {

// Points whose x or y is not finite (or not positive on a log axis) are skipped: a line joins the
// usable neighbours across the gap rather than breaking there.
struct Series {
  std::string name;
  std::vector<double> x, y;
  bool dashed = false;
  bool markers = false;     // scatter: a small circle per point (series colour), no connecting line
  bool right_axis = false;  // scaled against the second y axis on the right (LineChart::y2_label)
};

// Colours follow the series order (10-colour palette). The left y axis spans the series without
// `right_axis`; if any series has `right_axis`, a second y axis with its own range (from those series
// only; starting at 0 like the left one unless log_y) and ticks is drawn on the right, its tick labels
// and label in that series' colour when exactly one series uses it (otherwise black, and the legend
// names of its series get " (right)"), and the chart grows wider so the legend stays clear of it.
// Without right-axis series the output is as before. The legend column fits about 22 characters.
struct LineChart {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  bool log_x = false, log_y = false;  // log10 axes (scaling plots; log_y applies to both y axes);
                                      // non-positive values skipped
  std::string y2_label;               // label of the right y axis (used only with right-axis series)
  std::vector<std::string> notes;     // lines of small text under the legend, e.g. "r = 0.93, p = 1e-12"
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
