#include "studies/svg_plot.h"

#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace hipfai::studies {
namespace {

std::string read(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(SvgPlot, LineChartHasOnePolylinePerSeriesAndEscapesText) {
  LineChart chart;
  chart.title = "depth <mm> & angle";
  chart.series = {{"a", {0, 1, 2}, {0, 1, 4}, false}, {"b", {0, 1, 2}, {1, 1, 1}, true}};
  const auto path = std::filesystem::temp_directory_path() / "hipfai_chart.svg";
  write_svg(chart, path);
  const std::string svg = read(path);
  EXPECT_EQ(count(svg, "<polyline"), 2);
  EXPECT_EQ(count(svg, "<circle"), 6);
  EXPECT_NE(svg.find("depth &lt;mm&gt; &amp; angle"), std::string::npos);
}

TEST(SvgPlot, HeatMapDrawsEveryCellAndMarksMissingOnes) {
  HeatMap map;
  map.row_names = {"40", "20"};
  map.column_names = {"40", "60", "80"};
  map.values = {{0.0, 1.0, 2.0}, {0.5, std::nan(""), 3.0}};
  const auto path = std::filesystem::temp_directory_path() / "hipfai_heat.svg";
  write_svg(map, path);
  const std::string svg = read(path);
  EXPECT_EQ(count(svg, "<rect x="), 6);
  EXPECT_EQ(count(svg, ">n/a<"), 1);
}

// A closed convex mesh seen from any side shows about half its triangles (back faces culled).
TEST(SvgPlot, MeshViewCullsBackFaces) {
  const auto sphere = geometry::make_octasphere(geometry::Vec3::Zero(), 5.0, 3);
  const auto path = std::filesystem::temp_directory_path() / "hipfai_mesh.svg";
  write_mesh_svg({&sphere}, "none", 1.0, geometry::Vec3(0.3, -1, 0.2), geometry::Vec3::UnitZ(), "sphere", path);
  const int drawn = count(read(path), "<polygon");
  const int total = static_cast<int>(sphere.num_triangles());
  EXPECT_GT(drawn, total * 4 / 10);
  EXPECT_LT(drawn, total * 6 / 10);
}

}  // namespace
}  // namespace hipfai::studies
