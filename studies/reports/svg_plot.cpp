#include "studies/reports/svg_plot.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>

namespace hipfai::studies {

namespace {

constexpr const char* kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                    "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

std::string rgb(double r, double g, double b) {
  char text[16];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", static_cast<int>(std::clamp(r, 0.0, 1.0) * 255),
                static_cast<int>(std::clamp(g, 0.0, 1.0) * 255),
                static_cast<int>(std::clamp(b, 0.0, 1.0) * 255));
  return text;
}

// White -> yellow -> red -> dark red, t in [0, 1].
std::string sequential(double t) {
  t = std::clamp(t, 0.0, 1.0);
  if (t < 0.5) return rgb(1.0, 1.0, 1.0 - 2.0 * t * 0.9);
  return rgb(1.0 - (t - 0.5) * 0.9, 1.0 - (t - 0.5) * 2.0 * 0.95, 0.1);
}

// Blue (-1) -> white (0) -> red (+1).
std::string diverging(double t) {
  t = std::clamp(t, -1.0, 1.0);
  return t < 0 ? rgb(1.0 + t * 0.8, 1.0 + t * 0.6, 1.0) : rgb(1.0, 1.0 - t * 0.6, 1.0 - t * 0.8);
}

std::string number(double value, int precision = 3) {
  std::ostringstream out;
  out.precision(precision);
  out << value;
  return out.str();
}

// Round axis ticks: about `count` values covering [lo, hi].
std::vector<double> ticks(double lo, double hi, int count) {
  const double span = hi - lo;
  if (!(span > 0)) return {lo};
  const double raw = span / count;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double factor : {1.0, 2.0, 5.0, 10.0}) {
    step = factor * magnitude;
    if (raw <= step) break;
  }
  std::vector<double> out;
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step) out.push_back(v);
  return out;
}

void save(const std::filesystem::path& path, const std::string& svg) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  write_file_atomically(path, svg);
}

}  // namespace

namespace {

// A line chart's layout and axis ranges (transformed where the axis is logarithmic), and its
// mapping from data to the page.
struct ChartFrame {
  const LineChart& chart;
  bool has_left = false, has_right = false;
  // A right axis adds a column for its tick labels and label; the plot keeps its size and the
  // legend moves right with the chart's edge.
  double extra = 0, width = 0, height = 440, left = 70, right = 0, top = 40, bottom = 55;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0, r0 = 0, r1 = 0;  // x, left y and right y ranges
  double plot_w = 0, plot_h = 0;

  double tx(double v) const { return chart.log_x ? std::log10(v) : v; }
  double ty(double v) const { return chart.log_y ? std::log10(v) : v; }
  bool usable(double x, double y) const {
    return std::isfinite(x) && std::isfinite(y) && (!chart.log_x || x > 0) && (!chart.log_y || y > 0);
  }
  double px(double v) const { return left + (tx(v) - x0) / (x1 - x0) * plot_w; }
  double py(double v, bool on_right) const {
    const double lo = on_right ? r0 : y0, hi = on_right ? r1 : y1;
    return top + plot_h - (ty(v) - lo) / (hi - lo) * plot_h;
  }
};

double axis_value(double v, bool log) { return log ? std::pow(10.0, v) : v; }

void set_ranges(ChartFrame& f) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  f.x0 = kInf, f.x1 = -kInf;
  f.y0 = kInf, f.y1 = -kInf, f.r0 = kInf, f.r1 = -kInf;
  for (const auto& s : f.chart.series) {
    double& lo = s.right_axis ? f.r0 : f.y0;
    double& hi = s.right_axis ? f.r1 : f.y1;
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!f.usable(s.x[i], s.y[i])) continue;
      f.x0 = std::min(f.x0, f.tx(s.x[i])), f.x1 = std::max(f.x1, f.tx(s.x[i]));
      lo = std::min(lo, f.ty(s.y[i])), hi = std::max(hi, f.ty(s.y[i]));
    }
  }
  if (!std::isfinite(f.x0)) f.x0 = 0, f.x1 = 1;
  auto finish_range = [&](double& lo, double& hi) {
    if (!std::isfinite(lo)) lo = 0, hi = 1;
    if (!f.chart.log_y) lo = std::min(lo, 0.0);
    if (hi <= lo) hi = lo + 1;
    hi += 0.05 * (hi - lo);
  };
  if (f.x1 <= f.x0) f.x1 = f.x0 + 1;
  finish_range(f.y0, f.y1);
  finish_range(f.r0, f.r1);
}

ChartFrame chart_frame(const LineChart& chart) {
  ChartFrame f{chart};
  f.has_right = std::any_of(chart.series.begin(), chart.series.end(), [](const Series& s) { return s.right_axis; });
  f.has_left = std::any_of(chart.series.begin(), chart.series.end(), [](const Series& s) { return !s.right_axis; });
  f.extra = f.has_right ? 76 : 0;
  f.width = 720 + f.extra;
  f.right = 180 + f.extra;
  set_ranges(f);
  f.plot_w = f.width - f.left - f.right, f.plot_h = f.height - f.top - f.bottom;
  return f;
}

// Title, frame, the grid with the x and left y ticks, and the axis labels.
void write_axes(std::ostream& svg, const ChartFrame& f) {
  const LineChart& chart = f.chart;
  const double left = f.left, top = f.top, plot_w = f.plot_w, plot_h = f.plot_h;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << f.width << "' height='" << f.height
      << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n";
  svg << "<text x='" << f.width / 2 << "' y='22' text-anchor='middle' font-size='15'>" << escape(chart.title)
      << "</text>\n";
  svg << "<rect x='" << left << "' y='" << top << "' width='" << plot_w << "' height='" << plot_h
      << "' fill='none' stroke='black'/>\n";
  for (double t : ticks(f.x0, f.x1, 6)) {
    const double x = left + (t - f.x0) / (f.x1 - f.x0) * plot_w;
    svg << "<line x1='" << x << "' y1='" << top + plot_h << "' x2='" << x << "' y2='" << top
        << "' stroke='#ddd'/><text x='" << x << "' y='" << top + plot_h + 16
        << "' text-anchor='middle'>" << number(axis_value(t, chart.log_x)) << "</text>\n";
  }
  for (double t : ticks(f.y0, f.y1, 6)) {
    const double y = top + plot_h - (t - f.y0) / (f.y1 - f.y0) * plot_h;
    svg << "<line x1='" << left << "' y1='" << y << "' x2='" << left + plot_w << "' y2='" << y
        << "' stroke='#ddd'/><text x='" << left - 6 << "' y='" << y + 4 << "' text-anchor='end'>"
        << number(axis_value(t, chart.log_y)) << "</text>\n";
  }
  svg << "<text x='" << left + plot_w / 2 << "' y='" << f.height - 15 << "' text-anchor='middle'>"
      << escape(chart.x_label) << "</text>\n";
  svg << "<text transform='translate(18," << top + plot_h / 2 << ") rotate(-90)' text-anchor='middle'>"
      << escape(chart.y_label) << "</text>\n";
}

// Right axis: short tick marks on the frame (the grid follows the left axis), labels in the colour
// of its series when only one series uses it; otherwise black, and the legend marks its series.
void write_right_axis(std::ostream& svg, const ChartFrame& f, const std::string& colour) {
  const double axis_x = f.left + f.plot_w;
  for (double t : ticks(f.r0, f.r1, 6)) {
    const double y = f.top + f.plot_h - (t - f.r0) / (f.r1 - f.r0) * f.plot_h;
    svg << "<line x1='" << axis_x << "' y1='" << y << "' x2='" << axis_x + 5 << "' y2='" << y
        << "' stroke='" << colour << "'/><text x='" << axis_x + 8 << "' y='" << y + 4
        << "' text-anchor='start' fill='" << colour << "'>" << number(axis_value(t, f.chart.log_y))
        << "</text>\n";
  }
  svg << "<text transform='translate(" << axis_x + f.extra - 8 << ',' << f.top + f.plot_h / 2
      << ") rotate(-90)' text-anchor='middle' fill='" << colour << "'>" << escape(f.chart.y2_label)
      << "</text>\n";
}

// Series `s`: its line (unless markers only) and points, and its legend entry.
void write_series(std::ostream& svg, const ChartFrame& f, std::size_t s, std::size_t right_count) {
  const auto& series = f.chart.series[s];
  const double legend_x = f.width - f.right + f.extra;
  const char* colour = kPalette[s % std::size(kPalette)];
  const std::size_t n = std::min(series.x.size(), series.y.size());
  if (!series.markers) {
    svg << "<polyline fill='none' stroke='" << colour << "' stroke-width='2'"
        << (series.dashed ? " stroke-dasharray='6,4'" : "") << " points='";
    for (std::size_t i = 0; i < n; ++i) {
      if (f.usable(series.x[i], series.y[i])) {
        svg << f.px(series.x[i]) << ',' << f.py(series.y[i], series.right_axis) << ' ';
      }
    }
    svg << "'/>\n";
  }
  const char* radius = series.markers ? "3" : "2.5";
  for (std::size_t i = 0; i < n; ++i) {
    if (f.usable(series.x[i], series.y[i])) {
      svg << "<circle cx='" << f.px(series.x[i]) << "' cy='" << f.py(series.y[i], series.right_axis) << "' r='"
          << radius << "' fill='" << colour << "'/>\n";
    }
  }
  const double ly = f.top + 14 + 18 * static_cast<double>(s);
  if (series.markers) {
    svg << "<circle cx='" << legend_x + 24 << "' cy='" << ly << "' r='3' fill='" << colour << "'/>";
  } else {
    svg << "<line x1='" << legend_x + 12 << "' y1='" << ly << "' x2='" << legend_x + 36 << "' y2='" << ly
        << "' stroke='" << colour << "' stroke-width='2'" << (series.dashed ? " stroke-dasharray='6,4'" : "")
        << "/>";
  }
  svg << "<text x='" << legend_x + 42 << "' y='" << ly + 4 << "'>" << escape(series.name)
      << (series.right_axis && f.has_left && right_count > 1 ? " (right)" : "") << "</text>\n";
}

}  // namespace

void write_svg(const LineChart& chart, const std::filesystem::path& path) {
  const ChartFrame f = chart_frame(chart);
  std::ostringstream svg;
  write_axes(svg, f);
  std::size_t right_count = 0;
  std::string right_colour = "black";
  for (std::size_t s = 0; s < chart.series.size(); ++s) {
    if (chart.series[s].right_axis) ++right_count, right_colour = kPalette[s % std::size(kPalette)];
  }
  if (right_count != 1) right_colour = "black";
  if (f.has_right) write_right_axis(svg, f, right_colour);
  for (std::size_t s = 0; s < chart.series.size(); ++s) write_series(svg, f, s, right_count);
  const double legend_x = f.width - f.right + f.extra;
  for (std::size_t k = 0; k < chart.notes.size(); ++k) {
    const double ny = f.top + 14 + 18 * static_cast<double>(chart.series.size()) + 8 + 14 * static_cast<double>(k);
    svg << "<text x='" << legend_x + 12 << "' y='" << ny << "' font-size='11'>" << escape(chart.notes[k])
        << "</text>\n";
  }
  svg << "</svg>\n";
  save(path, svg.str());
}

void write_svg(const HeatMap& map, const std::filesystem::path& path) {
  const double cell_w = 90, cell_h = 50, left = 110, top = 60;
  const double width = left + cell_w * static_cast<double>(map.column_names.size()) + 40;
  const double height = top + cell_h * static_cast<double>(map.row_names.size()) + 60;
  double max_abs = 0.0;
  for (const auto& row : map.values) {
    for (double v : row) {
      if (std::isfinite(v)) max_abs = std::max(max_abs, std::abs(v));
    }
  }
  if (max_abs == 0.0) max_abs = 1.0;
  std::ostringstream svg;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
      << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n";
  svg << "<text x='" << width / 2 << "' y='22' text-anchor='middle' font-size='15'>" << escape(map.title)
      << (map.unit.empty() ? "" : " (" + escape(map.unit) + ")") << "</text>\n";
  for (std::size_t c = 0; c < map.column_names.size(); ++c) {
    svg << "<text x='" << left + cell_w * (static_cast<double>(c) + 0.5) << "' y='" << top - 8
        << "' text-anchor='middle'>" << escape(map.column_names[c]) << "</text>\n";
  }
  for (std::size_t r = 0; r < map.row_names.size(); ++r) {
    const double y = top + cell_h * static_cast<double>(r);
    svg << "<text x='" << left - 8 << "' y='" << y + cell_h / 2 + 4 << "' text-anchor='end'>"
        << escape(map.row_names[r]) << "</text>\n";
    for (std::size_t c = 0; c < map.column_names.size(); ++c) {
      const double v = r < map.values.size() && c < map.values[r].size()
                           ? map.values[r][c]
                           : std::numeric_limits<double>::quiet_NaN();
      const double x = left + cell_w * static_cast<double>(c);
      const std::string fill = !std::isfinite(v) ? "#cccccc"
                               : map.diverging   ? diverging(v / max_abs)
                                                 : sequential(v / max_abs);
      std::string text = std::isfinite(v) ? number(v) : "n/a";
      if (r < map.cell_text.size() && c < map.cell_text[r].size() && !map.cell_text[r][c].empty()) {
        text = map.cell_text[r][c];
      }
      svg << "<rect x='" << x << "' y='" << y << "' width='" << cell_w << "' height='" << cell_h
          << "' fill='" << fill << "' stroke='white'/><text x='" << x + cell_w / 2 << "' y='"
          << y + cell_h / 2 + 4 << "' text-anchor='middle'>" << escape(text) << "</text>\n";
    }
  }
  svg << "<text x='" << left + cell_w * static_cast<double>(map.column_names.size()) / 2 << "' y='"
      << height - 20 << "' text-anchor='middle'>" << escape(map.column_label) << "</text>\n";
  svg << "<text transform='translate(16," << top + cell_h * static_cast<double>(map.row_names.size()) / 2
      << ") rotate(-90)' text-anchor='middle'>" << escape(map.row_label) << "</text>\n</svg>\n";
  save(path, svg.str());
}

void write_mesh_svg(const std::vector<const geometry::TriMesh*>& meshes, const std::string& field,
                    double max_value, const geometry::Vec3& view_direction, const geometry::Vec3& up,
                    const std::string& title, const std::filesystem::path& path) {
  const geometry::Vec3 w = view_direction.normalized();                  // looking along w
  const geometry::Vec3 v = (up - up.dot(w) * w).normalized();              // screen up
  const geometry::Vec3 u = w.cross(v);                                     // screen right
  struct Face {
    double depth;
    double x[3], y[3];
    std::string colour;
  };
  std::vector<Face> faces;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto* mesh : meshes) {
    const auto found = mesh->vertex_fields.find(field);
    const std::vector<double>* values = found == mesh->vertex_fields.end() ? nullptr : &found->second;
    for (std::size_t t = 0; t < mesh->num_triangles(); ++t) {
      const geometry::Vec3 n = geometry::triangle_unit_normal(*mesh, t);
      if (n.dot(w) >= 0.0) continue;  // back face
      Face face{};
      double value = 0.0;
      for (int k = 0; k < 3; ++k) {
        const auto index = static_cast<std::size_t>(mesh->triangles[t][k]);
        const geometry::Vec3& p = mesh->vertices[index];
        face.x[k] = p.dot(u);
        face.y[k] = -p.dot(v);
        face.depth += p.dot(w) / 3.0;
        if (values) value = std::max(value, (*values)[index]);
        x0 = std::min(x0, face.x[k]), x1 = std::max(x1, face.x[k]);
        y0 = std::min(y0, face.y[k]), y1 = std::max(y1, face.y[k]);
      }
      const double shade = 0.45 + 0.55 * std::abs(n.dot(w));
      if (values && value > 0.0) {
        const double t01 = max_value > 0 ? std::clamp(value / max_value, 0.0, 1.0) : 1.0;
        face.colour = rgb(shade, shade * (1.0 - 0.85 * t01), shade * (1.0 - t01));
      } else {
        face.colour = rgb(shade * 0.92, shade * 0.9, shade * 0.86);
      }
      faces.push_back(face);
    }
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.depth > b.depth; });
  const double size = 640, margin = 40;
  const double scale = (size - 2 * margin) / std::max({x1 - x0, y1 - y0, 1e-9});
  std::ostringstream svg;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << size << "' height='" << size + 40
      << "' font-family='sans-serif' font-size='13'>\n<rect width='100%' height='100%' fill='white'/>\n"
      << "<text x='" << size / 2 << "' y='22' text-anchor='middle'>" << escape(title) << "</text>\n";
  svg.precision(5);
  for (const Face& face : faces) {
    svg << "<polygon points='";
    for (int k = 0; k < 3; ++k) {
      svg << margin + (face.x[k] - x0) * scale << ',' << 40 + margin + (face.y[k] - y0) * scale << ' ';
    }
    svg << "' fill='" << face.colour << "' stroke='" << face.colour << "' stroke-width='0.3'/>\n";
  }
  svg << "<text x='" << margin << "' y='" << size + 30 << "'>white/grey: 0 mm, red: " << number(max_value)
      << " mm and deeper</text>\n</svg>\n";
  save(path, svg.str());
}

}  // namespace hipfai::studies
