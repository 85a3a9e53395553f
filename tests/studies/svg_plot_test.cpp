#include "studies/reports/svg_plot.h"

#include "geometry/primitive_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

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

struct PlotArea {
  double x = 0, y = 0, width = 0, height = 0;
};

// The plot frame is the only rect with an x attribute in a line chart.
PlotArea plot_area(const std::string& svg) {
  std::smatch m;
  PlotArea area;
  if (std::regex_search(svg, m, std::regex("<rect x='([-0-9.e+]+)' y='([-0-9.e+]+)' width='([-0-9.e+]+)' "
                                           "height='([-0-9.e+]+)' fill='none'"))) {
    area = {std::stod(m[1]), std::stod(m[2]), std::stod(m[3]), std::stod(m[4])};
  }
  return area;
}

struct Point {
  double x, y;
};

// Centres of the data circles of the given colour (legend markers excluded: they sit right of the plot).
std::vector<Point> circles(const std::string& svg, const std::string& colour, const PlotArea& area) {
  std::vector<Point> out;
  const std::regex re("<circle cx='([-0-9.e+]+)' cy='([-0-9.e+]+)' r='[0-9.]+' fill='" + colour + "'/>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator(); ++it) {
    const Point p{std::stod((*it)[1]), std::stod((*it)[2])};
    if (p.x <= area.x + area.width + 1e-9) out.push_back(p);
  }
  return out;
}

// Vertices of the polylines of the given colour.
std::vector<Point> polyline_points(const std::string& svg, const std::string& colour) {
  std::vector<Point> out;
  const std::regex re("<polyline fill='none' stroke='" + colour + "'[^>]* points='([^']*)'");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator(); ++it) {
    std::istringstream in((*it)[1].str());
    double x = 0, y = 0;
    char comma = 0;
    while (in >> x >> comma >> y) out.push_back({x, y});
  }
  return out;
}

constexpr const char* kFirstColour = "#1f77b4";
constexpr const char* kSecondColour = "#d62728";

// Thesis Fig. 60 style: depth in mm (left) and stress in MPa (right), the stress 100x smaller here so a
// shared axis would squash it to the bottom.
TEST(SvgPlot, RightAxisSeriesIsScaledAgainstItsOwnRange) {
  LineChart chart;
  chart.title = "motion";
  chart.x_label = "step";
  chart.y_label = "depth (mm)";
  chart.y2_label = "von Mises stress (MPa)";
  Series depth{"depth", {0, 1, 2, 3, 4}, {0, 100, 400, 200, 300}};
  Series stress{"stress", {0, 1, 2, 3, 4}, {0.5, 1, 4, 2, 3}};
  stress.right_axis = true;
  chart.series = {depth, stress};
  const auto path = std::filesystem::temp_directory_path() / "hipfai_chart_two_axes.svg";
  write_svg(chart, path);
  const std::string svg = read(path);
  EXPECT_NE(svg.find(">depth (mm)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">von Mises stress (MPa)</text>"), std::string::npos);
  const PlotArea area = plot_area(svg);
  ASSERT_GT(area.height, 0.0);
  const double bottom = area.y + area.height;
  // Both axes start at 0 and end 5 % above their maximum: value v maps to bottom - v / (1.05 max) * h.
  const auto expected_y = [&](double v, double max) { return bottom - v / (1.05 * max) * area.height; };
  for (const bool on_right : {false, true}) {
    const std::string colour = on_right ? kSecondColour : kFirstColour;
    const auto& ys = on_right ? stress.y : depth.y;
    const double max = on_right ? 4.0 : 400.0;
    const auto line = polyline_points(svg, colour);
    const auto dots = circles(svg, colour, area);
    ASSERT_EQ(line.size(), ys.size()) << colour;
    ASSERT_EQ(dots.size(), ys.size()) << colour;
    for (std::size_t i = 0; i < ys.size(); ++i) {
      EXPECT_NEAR(line[i].y, expected_y(ys[i], max), 0.01) << colour << " point " << i;
      EXPECT_NEAR(dots[i].y, line[i].y, 1e-9);
      EXPECT_GE(line[i].x, area.x);
      EXPECT_LE(line[i].x, area.x + area.width);
      EXPECT_GE(line[i].y, area.y);
      EXPECT_LE(line[i].y, bottom);
    }
  }
  // The stress maximum is near the top of the plot although it is 100x smaller than the depths.
  const auto stress_line = polyline_points(svg, kSecondColour);
  EXPECT_LT(stress_line[2].y, area.y + 0.1 * area.height);
  // Right-axis tick labels in the stress colour, right of the plot and left of the legend.
  std::smatch tick;
  ASSERT_TRUE(std::regex_search(svg, tick, std::regex("<text x='([-0-9.e+]+)' y='[-0-9.e+]+' "
                                                      "text-anchor='start' fill='#d62728'>4</text>")));
  const double tick_x = std::stod(tick[1]);
  EXPECT_GT(tick_x, area.x + area.width);
  std::smatch legend;
  ASSERT_TRUE(std::regex_search(svg, legend, std::regex("<text x='([-0-9.e+]+)' y='[-0-9.e+]+'>depth</text>")));
  EXPECT_GT(std::stod(legend[1]), tick_x + 60);  // room for a label such as "1.5e+03"
  EXPECT_NE(svg.find(">stress</text>"), std::string::npos);  // the coloured axis identifies it
}

// With several right-axis series the right ticks are black and the legend says which series use them.
TEST(SvgPlot, SeveralRightAxisSeriesAreMarkedInTheLegend) {
  LineChart chart;
  chart.y2_label = "stress (MPa)";
  Series a{"a", {0, 1}, {0, 100}}, b{"b", {0, 1}, {0, 1}}, c{"c", {0, 1}, {0, 2}};
  b.right_axis = c.right_axis = true;
  chart.series = {a, b, c};
  const auto path = std::filesystem::temp_directory_path() / "hipfai_chart_two_right.svg";
  write_svg(chart, path);
  const std::string svg = read(path);
  EXPECT_NE(svg.find(">a</text>"), std::string::npos);
  EXPECT_NE(svg.find(">b (right)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">c (right)</text>"), std::string::npos);
  EXPECT_NE(svg.find("text-anchor='middle' fill='black'>stress (MPa)</text>"), std::string::npos);
  // The right range comes from b and c: c's maximum 2 sits 5 % below the top.
  const PlotArea area = plot_area(svg);
  const auto line = polyline_points(svg, "#2ca02c");
  ASSERT_EQ(line.size(), 2u);
  EXPECT_NEAR(line[1].y, area.y + area.height - area.height / 1.05, 0.01);
}

TEST(SvgPlot, MarkerSeriesDrawsCirclesWithoutLineAndSkipsNonFinitePoints) {
  LineChart chart;
  chart.x_label = "depth (mm)";
  chart.y_label = "stress (MPa)";
  Series hips{"hips", {0.5, 1.0, std::nan(""), 2.0, 3.0}, {10, 20, 30, INFINITY, 40}};
  hips.markers = true;
  chart.series = {hips};
  const auto path = std::filesystem::temp_directory_path() / "hipfai_chart_scatter.svg";
  write_svg(chart, path);
  const std::string svg = read(path);
  EXPECT_EQ(count(svg, "<polyline"), 0);
  const PlotArea area = plot_area(svg);
  ASSERT_GT(area.height, 0.0);
  const auto dots = circles(svg, kFirstColour, area);
  ASSERT_EQ(dots.size(), 3u);  // the NaN x and the infinite y are skipped
  EXPECT_EQ(count(svg, "<circle"), 4);  // plus the legend marker
  EXPECT_EQ(count(svg, "r='3'"), 4);
  for (const auto& p : dots) {
    EXPECT_GE(p.x, area.x);
    EXPECT_LE(p.x, area.x + area.width);
    EXPECT_GE(p.y, area.y);
    EXPECT_LE(p.y, area.y + area.height);
  }
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
}

TEST(SvgPlot, NotesAreWrittenUnderTheLegend) {
  LineChart chart;
  chart.series = {{"a", {0, 1}, {0, 1}}, {"b", {0, 1}, {1, 0}}};
  chart.notes = {"r = 0.93, p = 1e-12", "n = 40 & <hips>"};
  const auto path = std::filesystem::temp_directory_path() / "hipfai_chart_notes.svg";
  write_svg(chart, path);
  const std::string svg = read(path);
  std::smatch legend, first, second;
  ASSERT_TRUE(std::regex_search(svg, legend, std::regex("y='([-0-9.e+]+)'>b</text>")));
  ASSERT_TRUE(std::regex_search(svg, first, std::regex("y='([-0-9.e+]+)'[^>]*>r = 0.93, p = 1e-12</text>")));
  ASSERT_TRUE(std::regex_search(svg, second, std::regex("y='([-0-9.e+]+)'[^>]*>n = 40 &amp; &lt;hips&gt;</text>")));
  EXPECT_GT(std::stod(first[1]), std::stod(legend[1]));
  EXPECT_GT(std::stod(second[1]), std::stod(first[1]));
}

// Charts without the new options keep their former layout: no second axis, no "(right)", same size.
TEST(SvgPlot, ChartWithoutRightAxisKeepsFormerLayout) {
  LineChart chart;
  chart.y_label = "depth (mm)";
  chart.y2_label = "unused";
  chart.series = {{"a", {0, 1, 2}, {0, 1, 4}, false}, {"b", {0, 1, 2}, {1, 1, 1}, true}};
  const auto path = std::filesystem::temp_directory_path() / "hipfai_chart_plain.svg";
  write_svg(chart, path);
  const std::string svg = read(path);
  EXPECT_NE(svg.find("width='720' height='440'"), std::string::npos);
  EXPECT_NE(svg.find("<rect x='70' y='40' width='470' height='345'"), std::string::npos);
  EXPECT_EQ(svg.find("unused"), std::string::npos);
  EXPECT_EQ(svg.find("(right)"), std::string::npos);
  EXPECT_EQ(count(svg, "text-anchor='start'"), 0);
  EXPECT_EQ(count(svg, "r='2.5'"), 6);
  EXPECT_NE(svg.find("<line x1='552' y1='54' x2='576' y2='54' stroke='#1f77b4' stroke-width='2'/>"
                     "<text x='582' y='58'>a</text>"),
            std::string::npos);
  // Left axis: 0 at the bottom, 4 (the maximum) 5 % below the top.
  const auto line = polyline_points(svg, kFirstColour);
  ASSERT_EQ(line.size(), 3u);
  EXPECT_NEAR(line[0].y, 385.0, 1e-9);
  EXPECT_NEAR(line[2].y, 385.0 - 345.0 / 1.05, 1e-3);  // coordinates carry 6 digits
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
