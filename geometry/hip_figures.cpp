#include "geometry/hip_figures.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <cmath>
#include <sstream>

namespace hipfai::geometry {
namespace {

const char* tissue_colour(const std::string& name) {
  if (name == "femur_bone" || name == "acetabular_bone") return "#8c7b5a";
  if (name == "femoral_cartilage" || name == "acetabular_cartilage") return "#3b7dd8";
  if (name == "labrum") return "#d8473b";
  return "#444444";
}

// A drawing in plane coordinates (mm): right = `right`, up = `up`, origin at `origin`.
class SectionSvg {
 public:
  SectionSvg(const Vec3& origin, const Vec3& right, const Vec3& up, double half_width_mm)
      : origin_(origin), right_(right), up_(up), half_(half_width_mm) {
    body_.precision(4);  // 0.01 mm in the drawing: enough, and files a third the size
  }

  void section(const TriMesh& mesh, const std::string& name) {
    const Vec3 normal = right_.cross(up_).normalized();
    body_ << "<g stroke='" << tissue_colour(name) << "' stroke-width='0.35' fill='none'>"
          << "<title>" << name << "</title>\n";
    for (const auto& segment : plane_section(mesh, origin_, normal)) {
      line(segment.a, segment.b, "");
    }
    body_ << "</g>\n";
  }

  void line(const Vec3& a, const Vec3& b, const std::string& style) {
    const auto [x1, y1] = project(a);
    const auto [x2, y2] = project(b);
    body_ << "<line x1='" << x1 << "' y1='" << y1 << "' x2='" << x2 << "' y2='" << y2 << "' " << style
          << "/>\n";
  }

  void circle(const Vec3& centre, double radius, const std::string& style) {
    const auto [x, y] = project(centre);
    body_ << "<circle cx='" << x << "' cy='" << y << "' r='" << radius << "' " << style << "/>\n";
  }

  void text(const Vec3& at, const std::string& content) {
    const auto [x, y] = project(at);
    body_ << "<text x='" << x << "' y='" << y << "' font-size='3.5' font-family='sans-serif'>"
          << content << "</text>\n";
  }

  // The drawing as a nested <svg> of `size` user units at (x, y) of an enclosing sheet.
  std::string nested(double x, double y, double size, const std::string& title) const {
    std::ostringstream out;
    out << "<svg x='" << x << "' y='" << y << "' width='" << size << "' height='" << size << "' viewBox='" << -half_
        << ' ' << -half_ << ' ' << 2 * half_ << ' ' << 2 * half_ << "'>\n<title>" << title << "</title>\n"
        << body_.str() << "</svg>\n";
    return out.str();
  }

  void write(const std::filesystem::path& path, const std::string& title) const {
    write_file_atomically(path, [&](std::ostream& out) {
      out << "<svg xmlns='http://www.w3.org/2000/svg' viewBox='" << -half_ << ' ' << -half_ << ' '
          << 2 * half_ << ' ' << 2 * half_ << "' width='800' height='800'>\n"
          << "<title>" << title << "</title>\n<rect x='" << -half_ << "' y='" << -half_
          << "' width='" << 2 * half_ << "' height='" << 2 * half_ << "' fill='white'/>\n"
          << body_.str() << "</svg>\n";
    });
  }

 private:
  std::pair<double, double> project(const Vec3& p) const {
    const Vec3 v = p - origin_;
    return {v.dot(right_), -v.dot(up_)};  // SVG y grows downwards
  }

  Vec3 origin_, right_, up_;
  double half_;
  std::ostringstream body_;
};

std::string fixed(double value, int digits = 1) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(digits);
  out << value;
  return out.str();
}

}  // namespace

namespace {

constexpr double kHalfMm = 70.0;
const char* const kConstruction = "stroke='black' stroke-width='0.3' stroke-dasharray='1.5,1'";

SectionSvg frontal_panel(const HipModel& model, const CeMeasurement& ce) {
  const Vec3 hjc = model.hjc_mm;
  SectionSvg svg(hjc, model.lateral, model.superior, kHalfMm);
  for (const auto& [name, mesh] : model.tissues) svg.section(mesh, name);
  svg.line(hjc, hjc + 45.0 * model.superior, kConstruction);
  if (ce.status == MeasureStatus::kOk) {
    const Vec3 towards = (ce.rim_point_mm - hjc).normalized();
    svg.line(hjc, hjc + 45.0 * towards, kConstruction);
    svg.circle(ce.rim_point_mm, 0.8, "fill='black'");
    svg.text(hjc + 48.0 * model.superior, "CE = " + fixed(ce.ce_deg) + " deg (measured)");
  }
  svg.text(hjc - 60.0 * model.superior - 60.0 * model.lateral, "frontal section Y = 0, seen from anterior");
  return svg;
}

SectionSvg notzli_panel(const HipModel& model, const AlphaMeasurement& alpha) {
  const Vec3 u = alpha.status == MeasureStatus::kOk ? alpha.plane_direction : model.superior;
  const Vec3 centre = alpha.status == MeasureStatus::kOk ? alpha.head_centre_mm : model.hjc_mm;
  SectionSvg svg(centre, model.neck_axis, u, kHalfMm);
  for (const auto& [name, mesh] : model.tissues) svg.section(mesh, name);
  svg.line(centre - 30.0 * model.neck_axis, centre + 60.0 * model.neck_axis, kConstruction);
  if (alpha.status == MeasureStatus::kOk) {
    svg.circle(centre, alpha.head_radius_mm, "fill='none' stroke='black' stroke-width='0.2'");
    const Vec3 towards = (alpha.departure_point_mm - centre).normalized();
    svg.line(centre, centre + 40.0 * towards, kConstruction);
    svg.circle(alpha.departure_point_mm, 0.8, "fill='black'");
    svg.text(centre + 42.0 * towards, "alpha = " + fixed(alpha.alpha_deg) + " deg (measured)");
  }
  svg.text(centre - 60.0 * u - 60.0 * model.neck_axis,
           "Notzli's plane: through the neck axis, towards " + clock_label(alpha.plane_deg) + " (anterior)");
  return svg;
}

}  // namespace

void write_hip_figures(const HipModel& model, const CeMeasurement& ce, const AlphaMeasurement& alpha,
                       const std::filesystem::path& dir) {
  frontal_panel(model, ce).write(dir / "frontal.svg", "frontal section");
  notzli_panel(model, alpha).write(dir / "axial.svg", "axial section");
}

void write_morphology_sheet(const std::vector<MorphologyPanel>& panels, const std::filesystem::path& path) {
  constexpr double kPanel = 400.0, kLabel = 30.0;
  const double width = kPanel * static_cast<double>(panels.size());
  const double height = 2.0 * kPanel + kLabel;
  std::ostringstream out;
  out << "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 " << width << ' ' << height << "' width='" << width
      << "' height='" << height << "'>\n<title>characteristic hip morphologies</title>\n<rect width='" << width
      << "' height='" << height << "' fill='white'/>\n";
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const MorphologyPanel& p = panels[i];
    const HipModel& model = *p.model;
    const auto ce = measure_ce_angle({&model.tissue("acetabular_bone"), &model.tissue("acetabular_cartilage")},
                                     model.hjc_mm, model.lateral, model.superior);
    const auto alpha = measure_alpha_angle({&model.tissue("femur_bone"), &model.tissue("femoral_cartilage")},
                                           model.hjc_mm, model.neck_axis, model.superior, Vec3::UnitY());
    const double x = kPanel * static_cast<double>(i);
    out << "<text x='" << x + 10 << "' y='20' font-size='16' font-family='sans-serif'>" << p.label << " (CE "
        << fixed(model.parameters.ce_deg, 0) << ", alpha " << fixed(model.parameters.alpha_deg, 0) << ")</text>\n"
        << frontal_panel(model, ce).nested(x, kLabel, kPanel, p.label + ": frontal section")
        << notzli_panel(model, alpha).nested(x, kLabel + kPanel, kPanel, p.label + ": Notzli's plane");
  }
  out << "</svg>\n";
  write_file_atomically(path, out.str());
}

}  // namespace hipfai::geometry
