// hipfai — the figures of an assessment report (see assessment_figures.h).
#include "studies/pipeline/assessment_figures.h"

#include "core/atomic_file.h"
#include "core/literature.h"
#include "core/text_format.h"
#include "geometry/hip_frame.h"
#include "geometry/hip_measure.h"
#include "studies/reports/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace hipfai::studies {
namespace {

using geometry::Vec3;

// A drawing in millimetres on a plane, scaled into a square SVG (y up).
class PlaneDrawing {
 public:
  PlaneDrawing(Vec3 origin, Vec3 u, Vec3 v, double half_width_mm)
      : origin_(origin), u_(u.normalized()), v_(v.normalized()), half_(half_width_mm) {}

  void section(const std::vector<geometry::PlaneSegment>& segments, const char* colour) {
    for (const auto& s : segments) line(s.a, s.b, colour, 1.2);
  }
  void line(const Vec3& a, const Vec3& b, const char* colour, double width, bool dashed = false) {
    const auto [x0, y0] = map(a);
    const auto [x1, y1] = map(b);
    body_ << "<line x1='" << x0 << "' y1='" << y0 << "' x2='" << x1 << "' y2='" << y1 << "' stroke='" << colour
          << "' stroke-width='" << width << "'" << (dashed ? " stroke-dasharray='5,4'" : "") << "/>\n";
  }
  void circle(const Vec3& centre, double radius_mm, const char* colour, bool dashed) {
    const auto [x, y] = map(centre);
    body_ << "<circle cx='" << x << "' cy='" << y << "' r='" << radius_mm * scale() << "' fill='none' stroke='"
          << colour << "' stroke-width='1'" << (dashed ? " stroke-dasharray='4,3'" : "") << "/>\n";
  }
  void dot(const Vec3& p, const char* colour) {
    const auto [x, y] = map(p);
    body_ << "<circle cx='" << x << "' cy='" << y << "' r='3.5' fill='" << colour << "'/>\n";
  }
  void text(const Vec3& p, const std::string& words, const char* colour = "#222") {
    const auto [x, y] = map(p);
    body_ << "<text x='" << x + 4 << "' y='" << y - 4 << "' font-size='12' fill='" << colour << "'>" << words
          << "</text>\n";
  }
  std::string svg(const std::string& title, const std::vector<std::string>& notes) const {
    std::ostringstream out;
    const int height = kSize + 40 + 16 * static_cast<int>(notes.size());
    out << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kSize << "' height='" << height
        << "' font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n"
        << "<text x='10' y='20' font-size='14' font-weight='bold'>" << title << "</text>\n"
        << "<g transform='translate(0,30)'>\n" << body_.str() << "</g>\n";
    for (std::size_t i = 0; i < notes.size(); ++i) {
      out << "<text x='10' y='" << kSize + 30 + 16 * static_cast<int>(i) << "' font-size='12'>" << notes[i] << "</text>\n";
    }
    out << "</svg>\n";
    return out.str();
  }

 private:
  static constexpr int kSize = 520;
  double scale() const { return kSize / (2.0 * half_); }
  std::pair<double, double> map(const Vec3& p) const {
    const Vec3 d = p - origin_;
    return {kSize / 2.0 + u_.dot(d) * scale(), kSize / 2.0 - v_.dot(d) * scale()};
  }
  Vec3 origin_, u_, v_;
  double half_;
  std::ostringstream body_;
};

// Keeps the segments within `reach` of `centre` (the figure's window).
std::vector<geometry::PlaneSegment> near(const std::vector<geometry::PlaneSegment>& segments, const Vec3& centre,
                                         double reach) {
  std::vector<geometry::PlaneSegment> kept;
  for (const auto& s : segments) {
    if ((s.a - centre).norm() < reach || (s.b - centre).norm() < reach) kept.push_back(s);
  }
  return kept;
}

void write_coronal_ce(const AssessmentResult& r, const std::filesystem::path& path) {
  const auto& f = r.pelvis_frame;
  const Vec3 head = r.hjc_mm;
  const double half = 70.0;
  PlaneDrawing drawing(head, f.right, f.superior, half);
  drawing.section(near(geometry::plane_section(r.pelvis, head, f.anterior), head, 1.5 * half), "#555");
  drawing.section(near(geometry::plane_section(r.femur_neutral, head, f.anterior), head, 1.5 * half), "#2a6fb0");
  drawing.line(head, head + 45.0 * f.superior, "#222", 1.0, true);
  drawing.line(head, head + 20.0 * f.right, "#c0392b", 1.5);
  drawing.text(head + 20.0 * f.right, "right (lateral)", "#c0392b");
  drawing.text(head + 45.0 * f.superior, "superior");
  const auto& ce = r.before.measures.lateral_ce;
  drawing.line(head, head + 1.6 * (ce.rim_point_mm - head), "#d35400", 2.0);
  drawing.dot(ce.rim_point_mm, "#d35400");
  drawing.text(ce.rim_point_mm, "CE " + fixed(ce.ce_deg, 1) + "°", "#d35400");
  std::vector<std::string> notes = {"coronal plane of the anterior pelvic plane frame through the femoral head centre;",
                                    "grey: pelvis, blue: femur (neutral pose); seen from anterior"};
  if (r.after) notes.push_back("after the resections: lateral CE " + fixed(r.after->measures.lateral_ce.ce_deg, 1) + "°");
  write_file_atomically(path, drawing.svg("Lateral centre-edge angle (Wiberg)", notes));
}

void write_notzli_alpha(const AssessmentResult& r, const std::filesystem::path& path) {
  // Nötzli's plane in the neutral pose.
  const Eigen::Matrix3d& rn = r.neutral_rotation;
  const auto& alpha = r.before.measures.alpha;
  const Vec3 centre = r.hjc_mm + rn * (alpha.head_centre_mm - r.hjc_mm);
  const Vec3 n = (rn * r.neck_axis).normalized();
  const Vec3 u = (rn * alpha.plane_direction).normalized();
  const double half = 2.2 * alpha.head_radius_mm;
  PlaneDrawing drawing(centre + 0.6 * alpha.head_radius_mm * n, n, u, half);
  drawing.section(near(geometry::plane_section(r.femur_neutral, centre, n.cross(u)), centre, 1.6 * half), "#2a6fb0");
  if (r.femur_after_neutral) {
    drawing.section(near(geometry::plane_section(*r.femur_after_neutral, centre, n.cross(u)), centre, 1.6 * half),
                    "#27ae60");
  }
  drawing.circle(centre, alpha.head_radius_mm, "#888", true);
  drawing.line(centre, centre + 2.0 * alpha.head_radius_mm * n, "#222", 1.0, true);
  drawing.text(centre + 2.0 * alpha.head_radius_mm * n, "neck axis");
  const Vec3 departure = r.hjc_mm + rn * (alpha.departure_point_mm - r.hjc_mm);
  drawing.line(centre, centre + 1.3 * (departure - centre), "#d35400", 2.0);
  drawing.dot(departure, "#d35400");
  drawing.text(departure, "alpha " + fixed(alpha.alpha_deg, 1) + "°", "#d35400");
  std::vector<std::string> notes = {"femur cut by Nötzli's plane (neck axis and anterior); dashed: fitted head sphere",
                                    "blue: as scanned" + std::string(r.femur_after_neutral ? ", green: after the cam resection" : "")};
  if (r.after) notes.push_back("alpha after: " + fixed(r.after->measures.alpha.alpha_deg, 1) + "° in Nötzli's plane, largest " +
                               fixed(r.after->measures.alpha.max_alpha_deg, 1) + "°");
  write_file_atomically(path, drawing.svg("Alpha angle (Nötzli) in Nötzli's plane", notes));
}

void write_clock(const AssessmentResult& r, const std::filesystem::path& path) {
  const auto motions = r.before.rom.motions();
  std::ostringstream out;
  const int width = 820, height = 500;
  out << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
      << "' font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n"
      << "<text x='10' y='20' font-size='14' font-weight='bold'>Where the bones meet at each motion's limit "
         "(3 o'clock anterior, 12 superior)</text>\n";
  const char* palette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                           "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  for (int face = 0; face < 2; ++face) {
    const double cx = 200 + face * 400, cy = 230, radius = 150;
    out << "<circle cx='" << cx << "' cy='" << cy << "' r='" << radius << "' fill='none' stroke='#444'/>\n";
    out << "<text x='" << cx - 80 << "' y='" << cy + radius + 30 << "' font-size='13'>"
        << (face == 0 ? "acetabular rim" : "femoral head-neck junction") << "</text>\n";
    for (int hour = 1; hour <= 12; ++hour) {
      const double clock = 90.0 - (hour % 12) * 30.0;  // 12 at 90 deg, 3 at 0
      const double a = clock * geometry::kDegToRad;
      out << "<text x='" << cx + (radius + 14) * std::cos(a) - 5 << "' y='" << cy - (radius + 14) * std::sin(a) + 5
          << "' font-size='11' fill='#666'>" << hour << "</text>\n";
    }
    int index = 0;
    for (const auto* outcome : motions) {
      const char* colour = palette[index % 10];
      ++index;
      if (!outcome->limit || outcome->limit->unlimited) continue;
      const auto& clock = face == 0 ? outcome->limit->acetabular_clock : outcome->limit->femoral_clock;
      const double a = clock.angle_deg * geometry::kDegToRad;
      const double rr = radius * (0.55 + 0.04 * (index % 10));
      out << "<circle cx='" << cx + rr * std::cos(a) << "' cy='" << cy - rr * std::sin(a) << "' r='5' fill='" << colour
          << "'><title>" << outcome->limit->name << ": " << clock.label << "</title></circle>\n";
    }
  }
  int index = 0;
  for (const auto* outcome : motions) {
    const char* colour = palette[index % 10];
    const std::string name = outcome->limit ? outcome->limit->name : "(not reached)";
    out << "<circle cx='" << 20 + (index % 4) * 200 << "' cy='" << height - 54 + (index / 4) * 16 << "' r='4' fill='"
        << colour << "'/><text x='" << 28 + (index % 4) * 200 << "' y='" << height - 50 + (index / 4) * 16
        << "' font-size='11'>" << name << "</text>\n";
    ++index;
  }
  out << "</svg>\n";
  write_file_atomically(path, out.str());
}

void write_rom_bars(const AssessmentResult& r, const std::filesystem::path& path) {
  // Horizontal bars: one row per motion, before (blue) and after the resections (green); the
  // clinical normal (AAOS 1965) of the six basic motions as a black tick.
  const auto before = r.before.rom.motions();
  const double normal[] = {literature::kAaosFlexionDeg, literature::kAaosExtensionDeg, literature::kAaosAbductionDeg,
                           literature::kAaosAdductionDeg, literature::kAaosInternalRotationDeg,
                           literature::kAaosExternalRotationDeg};
  double largest = 90.0;
  auto value = [](const anatomy::MotionOutcome& o) { return o.limit ? std::min(o.limit->angle_deg, 360.0) : 0.0; };
  for (std::size_t i = 0; i < before.size(); ++i) {
    largest = std::max(largest, value(*before[i]));
    if (r.after) largest = std::max(largest, value(*r.after->rom.motions()[i]));
  }
  largest = 30.0 * std::ceil(largest / 30.0);
  const int left = 250, width = 480, row = r.after ? 30 : 22, top = 50;
  const int height = top + row * static_cast<int>(before.size()) + 60;
  const double scale = width / largest;
  std::ostringstream out;
  out << "<svg xmlns='http://www.w3.org/2000/svg' width='" << left + width + 40 << "' height='" << height
      << "' font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n"
      << "<text x='10' y='20' font-size='14' font-weight='bold'>Range of motion to bony impingement (deg)"
      << (r.after ? ", before and after resection" : "") << "</text>\n";
  for (double tick = 0.0; tick <= largest + 1e-9; tick += 30.0) {
    const double x = left + tick * scale;
    out << "<line x1='" << x << "' y1='" << top - 8 << "' x2='" << x << "' y2='" << height - 50
        << "' stroke='#ddd'/><text x='" << x - 8 << "' y='" << height - 36 << "' font-size='11'>" << tick << "</text>\n";
  }
  for (std::size_t i = 0; i < before.size(); ++i) {
    const double y = top + row * static_cast<double>(i);
    const std::string name = before[i]->limit ? before[i]->limit->name : "(start pose not reached)";
    out << "<text x='10' y='" << y + 12 << "' font-size='12'>" << name << "</text>\n";
    out << "<rect x='" << left << "' y='" << y << "' width='" << value(*before[i]) * scale
        << "' height='12' fill='#2a6fb0'><title>" << fixed(value(*before[i]), 1) << "</title></rect>\n";
    if (r.after) {
      const double after = value(*r.after->rom.motions()[i]);
      out << "<rect x='" << left << "' y='" << y + 13 << "' width='" << after * scale
          << "' height='12' fill='#27ae60'><title>" << fixed(after, 1) << "</title></rect>\n";
    }
    if (i < 6) {
      const double x = left + normal[i] * scale;
      out << "<line x1='" << x << "' y1='" << y - 2 << "' x2='" << x << "' y2='" << y + row - 4
          << "' stroke='black' stroke-width='2'/>\n";
    }
  }
  out << "<text x='10' y='" << height - 12 << "' font-size='11'>blue: as scanned" << (r.after ? "; green: after the resections" : "")
      << "; black tick: clinical normal range (AAOS 1965, soft-tissue limited)</text>\n</svg>\n";
  write_file_atomically(path, out.str());
}

void write_alpha_profile(const AssessmentResult& r, const std::filesystem::path& path) {
  LineChart chart;
  chart.title = "Alpha angle around the head-neck junction (clock profile)";
  chart.x_label = "clock angle about the neck axis (deg; 0 = 3:00 anterior, 90 = 12:00 superior)";
  chart.y_label = "alpha (deg)";
  Series before{"as scanned", {}, {}, false, true, false};
  for (const auto& [clock, alpha] : r.before.measures.alpha.profile) {
    before.x.push_back(clock);
    before.y.push_back(alpha);
  }
  chart.series.push_back(before);
  if (r.after) {
    Series after{"after resection", {}, {}, false, true, false};
    for (const auto& [clock, alpha] : r.after->measures.alpha.profile) {
      after.x.push_back(clock);
      after.y.push_back(alpha);
    }
    chart.series.push_back(after);
  }
  write_svg(chart, path);
}

}  // namespace

void write_assessment_figures(const AssessmentResult& result, const std::filesystem::path& dir) {
  write_coronal_ce(result, dir / "coronal_ce.svg");
  write_notzli_alpha(result, dir / "notzli_alpha.svg");
  write_clock(result, dir / "impingement_clock.svg");
  write_rom_bars(result, dir / "rom.svg");
  write_alpha_profile(result, dir / "alpha_profile.svg");
}

}  // namespace hipfai::studies
