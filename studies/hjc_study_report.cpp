// hipfai — the files of `study hjc` from its result (see hjc_study_report.h).
#include "studies/hjc_study_report.h"

#include "core/atomic_file.h"
#include "core/literature.h"
#include "core/text_format.h"
#include "core/version.h"
#include "studies/reports/svg_plot.h"
#include "studies/results/results_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <sstream>

namespace hipfai::studies {
namespace {

using geometry::Vec3;

// The methods compared with dref (thesis Figs. 68-71).
const std::vector<std::string> kCompared{"femoralheadsphere", "acetabulumsphere", "doublesphere", "dconst"};

double mean_of(const std::vector<double>& v) {
  return v.empty() ? std::numeric_limits<double>::quiet_NaN()
                   : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double sd_of(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean_of(v);
  double s = 0.0;
  for (const double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

// ---- bones-only mode ---------------------------------------------------------------------------

const HjcBonesVariant& variant_named(const HjcBonesResult& bones, const std::string& femur) {
  return *std::find_if(bones.variants.begin(), bones.variants.end(),
                       [&](const HjcBonesVariant& v) { return v.femur == femur; });
}

void write_bones_centres(std::ostream& md, const HjcStudyResult& result) {
  const geometry::HjcResult& hjc = result.bones.hjc;
  md << "# HJC on bones: " << result.options.femur.filename().string() << " + "
     << result.options.pelvis.filename().string() << "\n\nCode " << kGitSha << ". Femoral head: " << hjc.head_source
     << ", " << hjc.head_vertices << " vertices; lunate surface: " << hjc.lunate_source << ", " << hjc.lunate_vertices
     << " vertices. Centres in the input meshes' coordinates (mm).\n\n"
     << "| method | centre (mm) | radius (mm) | fit RMS (mm) | fit max (mm) | residual motion RMS / max (mm) | "
        "distance to the mean centre (mm) |\n|---|---|---|---|---|---|---|\n";
  Vec3 mean_centre = Vec3::Zero();
  for (const auto& m : hjc.methods) mean_centre += m.center_mm;
  mean_centre /= static_cast<double>(hjc.methods.size());
  double spread = 0.0;
  for (const auto& a : hjc.methods)
    for (const auto& b : hjc.methods) spread = std::max(spread, (a.center_mm - b.center_mm).norm());
  for (const auto& m : hjc.methods) {
    const bool functional = m.name == "dconst" || m.name == "dref";
    md << "| " << m.name << " | (" << fixed_or(m.center_mm.x(), 2, "-") << ", " << fixed_or(m.center_mm.y(), 2, "-") << ", "
       << fixed_or(m.center_mm.z(), 2, "-") << ") | " << (functional ? "-" : fixed_or(m.radius_mm, 2, "-")) << " | " << fixed_or(m.rms_mm, 3, "-")
       << " | " << fixed_or(m.max_mm, 3, "-") << " | "
       << (functional ? fixed_or(m.residual_motion_rms_mm, 3, "-") + " / " + fixed_or(m.residual_motion_max_mm, 3, "-") : "-") << " | "
       << fixed_or((m.center_mm - mean_centre).norm(), 2, "-") << " |\n";
  }
  md << "\nSpread (largest distance between two centres): **" << fixed_or(spread, 2, "-") << " mm**. For the sphere fits the "
     << "residual is the distance to the fitted sphere; for dconst/dref it is the inter-articular distance minus its "
     << "target after the per-pose shifts (the head is not a perfect sphere).\n\n";
}

void write_bones_frame(std::ostream& md, const Eigen::Matrix3d& frame) {
  auto axis = [&](int i) {
    return fixed_or(frame(0, i), 3, "-") + ", " + fixed_or(frame(1, i), 3, "-") + ", " + fixed_or(frame(2, i), 3, "-");
  };
  md << "## Bone-to-bone range of motion per method (exact range finder)\n\n"
     << "Approximate hip frame (no anatomical landmarks in the CT): Z = femur principal axis towards the head ("
     << axis(2) << "), X = from the pelvis centroid towards the "
     << "head, orthogonal to Z (" << axis(0) << "), Y = Z x X (" << axis(1) << "). Rotations start from the scanned "
     << "pose, which is not the anatomical neutral pose. Bones only: cartilage and labrum absent, so these are the "
     << "bony limits, larger than a living hip's. Whole femur: every contact counts, the head's in its own socket "
     << "too. Head removed: the femur without its head (radius + 1.5 mm about the femoralheadsphere centre), the "
     << "neck and trochanter against the pelvis: the impingement range of bony ROM simulations.\n";
}

void write_bones_rom_table(std::ostream& md, const HjcBonesVariant& variant, const geometry::HjcResult& hjc) {
  md << "\n### " << variant.femur << "\n\n| method |";
  for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; md << ' ' << name << " |"; }
  md << "\n|---|---|---|---|---|---|---|\n";
  for (const auto& m : hjc.methods) {
    md << "| " << m.name << " |";
    for (const auto& [name, amplitude] : hjc_study_rotations()) {
      (void)amplitude;
      md << ' ' << fixed_or(variant.rom_deg.at(m.name).at(name), 1, "-") << " (" << variant.site.at(m.name).at(name) << ") |";
    }
    md << '\n';
  }
  md << "| spread over methods |";
  for (const auto& [name, amplitude] : hjc_study_rotations()) {
    (void)amplitude;
    double lo = 1e9, hi = -1e9;
    for (const auto& m : hjc.methods) {
      lo = std::min(lo, variant.rom_deg.at(m.name).at(name));
      hi = std::max(hi, variant.rom_deg.at(m.name).at(name));
    }
    md << ' ' << fixed_or(hi - lo, 1, "-") << " |";
  }
  md << "\n| clinical norm (AAOS 1965) |";
  for (const auto& [name, amplitude] : hjc_study_rotations()) md << ' ' << fixed_or(amplitude, 0, "-") << " |";
  md << '\n';
}

std::string bones_markdown(const HjcStudyResult& result) {
  std::ostringstream md;
  write_bones_centres(md, result);
  write_bones_frame(md, result.bones.frame);
  for (const auto& variant : result.bones.variants) write_bones_rom_table(md, variant, result.bones.hjc);
  md << "\n(h): the first contact lies within the head radius + 4 mm of the centre: the head (whole femur) or the "
        "head-neck junction (head removed) against the socket or its rim; (r): farther out, neck or trochanter "
        "against the pelvis.\n\nClinical norms: American Academy of Orthopaedic Surgeons, Joint Motion: Method of Measuring and "
        "Recording (1965); supine rotations measured in 120 adults: ER "
     << fixed_or(literature::kSupineExternalRotationDeg, 1, "-") << ", IR " << fixed_or(literature::kSupineInternalRotationDeg, 1, "-")
     << " deg (Kouyoumdjian et al. 2012, Orthop Traumatol Surg Res 98:17). core/literature.h.\n";
  return md.str();
}

void write_bones_csv(const HjcBonesResult& bones, const std::filesystem::path& path) {
  const HjcBonesVariant& impingement = variant_named(bones, "head removed");
  const HjcBonesVariant& whole = variant_named(bones, "whole femur");
  std::ostringstream csv;
  csv << "method,center_x_mm,center_y_mm,center_z_mm,radius_mm,fit_rms_mm,fit_max_mm,residual_motion_rms_mm";
  for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; csv << ',' << name << "_rom_deg"; }
  for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; csv << ',' << name << "_rom_whole_femur_deg"; }
  csv << '\n';
  csv.precision(8);
  for (const auto& m : bones.hjc.methods) {
    csv << m.name << ',' << m.center_mm.x() << ',' << m.center_mm.y() << ',' << m.center_mm.z() << ',' << m.radius_mm
        << ',' << m.rms_mm << ',' << m.max_mm << ',' << m.residual_motion_rms_mm;
    for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; csv << ',' << impingement.rom_deg.at(m.name).at(name); }
    for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; csv << ',' << whole.rom_deg.at(m.name).at(name); }
    csv << '\n';
  }
  write_file_atomically(path, csv.str());
}

void write_bones_h5(const HjcStudyResult& result, const std::filesystem::path& path) {
  const HjcBonesVariant& impingement = variant_named(result.bones, "head removed");
  ResultsFile h5(path);
  h5.set_attribute("/", "units", "mm, deg");
  h5.set_attribute("/", "git_sha", kGitSha);
  h5.set_attribute("/", "femur", result.options.femur.string());
  h5.set_attribute("/", "pelvis", result.options.pelvis.string());
  std::vector<std::string> names;
  std::vector<double> centres, roms;
  for (const auto& m : result.bones.hjc.methods) {
    names.push_back(m.name);
    centres.insert(centres.end(), {m.center_mm.x(), m.center_mm.y(), m.center_mm.z(), m.rms_mm, m.max_mm});
    for (const auto& [name, amplitude] : hjc_study_rotations()) { (void)amplitude; roms.push_back(impingement.rom_deg.at(m.name).at(name)); }
  }
  h5.write_strings("/methods", names);
  h5.write("/centres", centres, 5, "mm");
  h5.set_attribute("/centres", "columns", "x,y,z,fit_rms,fit_max");
  h5.write("/rom_deg", roms, 6, "deg");
  h5.set_attribute("/rom_deg", "femur", "head removed (impingement range; whole-femur ranges in bones.csv)");
  h5.set_attribute("/rom_deg", "columns", "flexion,extension,internal_rotation,external_rotation,adduction,abduction");
  h5.commit();
}

std::filesystem::path write_bones_report(const HjcStudyResult& result, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const std::filesystem::path report = dir / "bones.md";
  write_file_atomically(report, bones_markdown(result));
  write_bones_csv(result.bones, dir / "bones.csv");
  write_bones_h5(result, dir / "bones.h5");
  return report;
}

// ---- generated subjects ------------------------------------------------------------------------

// Eq. 13 for one subject: |depth_i - depth_ref| over every step of every rotation. Curvilinear in
// mm; radial in % of the reference where the reference is > 0, and in mm.
struct Differences {
  std::vector<double> curvilinear_mm, radial_percent, radial_mm;
};

Differences differences(const HjcSubjectResult& s, const std::string& label, const std::string& reference,
                        const std::string& only_rotation = "") {
  Differences d;
  const auto& a = s.depths.at(label);
  const auto& b = s.depths.at(reference);
  for (const auto& [rotation, amplitude] : hjc_study_rotations()) {
    (void)amplitude;
    if (!only_rotation.empty() && rotation != only_rotation) continue;
    const auto& x = a.at(rotation);
    const auto& y = b.at(rotation);
    for (std::size_t k = 0; k < x.angle_deg.size(); ++k) {
      d.curvilinear_mm.push_back(std::abs(x.curvilinear_mm[k] - y.curvilinear_mm[k]));
      const double dr = std::abs(x.radial_mm[k] - y.radial_mm[k]);
      d.radial_mm.push_back(dr);
      if (y.radial_mm[k] > 0.0) d.radial_percent.push_back(100.0 * dr / y.radial_mm[k]);
    }
  }
  return d;
}

// Eq. 13 per subject, then the mean over subjects (SDs: the mean of the subjects' SDs).
struct OverallDifferences {
  double radial_percent, radial_percent_sd, curvilinear_mm, curvilinear_sd, radial_mm;
};

OverallDifferences overall(const std::vector<HjcSubjectResult>& subjects, const std::string& label,
                           const std::string& reference) {
  std::vector<double> rp, cm, rm, rps, cms;
  for (const auto& s : subjects) {
    const Differences d = differences(s, label, reference);
    rp.push_back(mean_of(d.radial_percent));
    rps.push_back(sd_of(d.radial_percent));
    cm.push_back(mean_of(d.curvilinear_mm));
    cms.push_back(sd_of(d.curvilinear_mm));
    rm.push_back(mean_of(d.radial_mm));
  }
  return {mean_of(rp), mean_of(rps), mean_of(cm), mean_of(cms), mean_of(rm)};
}

// Per method compared, one value per subject or rotation: the Fig. 68-71 heat maps.
using FigureValues = std::vector<std::vector<double>>;

void write_centre_errors(std::ostream& md, const HjcStudyResult& result) {
  const auto& methods = geometry::hjc_method_names();
  md << "# HJC sensitivity study (thesis §4.4) with a known centre\n\n"
     << "Code " << kGitSha << ". " << result.subjects.size() << " generated subjects at " << result.options.edge_mm
     << " mm edges; each subject's centres estimated on its articular surfaces perturbed like a segmentation (noise "
     << kHjcSegmentationNoiseMm << " mm RMS, asphericity " << kHjcSegmentationAsphericityMm << " mm, uneven joint space "
     << kHjcSegmentationUnevenGapMm << " mm; studies/hjc_study.h). Six medical rotations to the AAOS normal range in "
     << result.options.step_deg << " deg steps; per step the maximum curvilinear (femur bone vs labrum) and radial "
     << "(femoral cartilage vs acetabular cartilage + labrum) depth.\n\n## Centre errors of the subjects (mm, vs the true centre)\n\n| subject |";
  for (const auto& m : methods) md << ' ' << m << " |";
  md << "\n|---|---|---|---|---|---|\n";
  for (const auto& s : result.subjects) {
    md << "| " << s.id << " |";
    for (const auto& m : methods) md << ' ' << fixed_or((s.centres_mm.at(m) - s.true_centre_mm).norm(), 2, "-") << " |";
    md << '\n';
  }
}

void write_dref_differences(std::ostream& md, const HjcStudyResult& result, FigureValues& fig68, FigureValues& fig69) {
  md << "\n## Differences to dref over all six rotations (thesis Eq. 13, Figs. 68-69)\n\n"
     << "Mean over subjects of each subject's mean |depth - depth_dref| (SD: mean of the subjects' SDs). Thesis "
     << "(10 MRI subjects): radial about " << fixed_or(literature::kThesisHjcRadialDiffPercent, 0, "-")
     << " % on average; femoralheadsphere and doublesphere < " << fixed_or(literature::kThesisHjcSphereRadialDiffPercent, 0, "-")
     << " % and < " << fixed_or(literature::kThesisHjcSphereCurvilinearDiffMm, 2, "-") << " mm curvilinear; dconst about "
     << fixed_or(literature::kThesisHjcDconstRadialDiffPercent, 0, "-") << " % and "
     << fixed_or(literature::kThesisHjcDconstCurvilinearDiffMm, 2, "-") << " mm.\n\n"
     << "| method | radial (% of dref) | radial (mm) | curvilinear (mm) | thesis radial | thesis curvilinear |\n"
     << "|---|---|---|---|---|---|\n";
  fig68.assign(kCompared.size(), {});
  fig69.assign(kCompared.size(), {});
  for (std::size_t i = 0; i < kCompared.size(); ++i) {
    const OverallDifferences o = overall(result.subjects, kCompared[i], "dref");
    const bool small = kCompared[i] == "femoralheadsphere" || kCompared[i] == "doublesphere";
    const bool dconst = kCompared[i] == "dconst";
    md << "| " << kCompared[i] << " | " << fixed_or(o.radial_percent, 1, "-") << " +- " << fixed_or(o.radial_percent_sd, 1, "-") << " | "
       << fixed_or(o.radial_mm, 3, "-") << " | " << fixed_or(o.curvilinear_mm, 3, "-") << " +- " << fixed_or(o.curvilinear_sd, 3, "-") << " | "
       << (small    ? "< " + fixed_or(literature::kThesisHjcSphereRadialDiffPercent, 0, "-") + " %"
           : dconst ? "~" + fixed_or(literature::kThesisHjcDconstRadialDiffPercent, 0, "-") + " %"
                    : "~" + fixed_or(literature::kThesisHjcRadialDiffPercent, 0, "-") + " % (all methods)")
       << " | "
       << (small    ? "< " + fixed_or(literature::kThesisHjcSphereCurvilinearDiffMm, 2, "-") + " mm"
           : dconst ? fixed_or(literature::kThesisHjcDconstCurvilinearDiffMm, 2, "-") + " mm"
                    : std::string("-"))
       << " |\n";
    for (const auto& s : result.subjects) {
      const Differences d = differences(s, kCompared[i], "dref");
      fig68[i].push_back(mean_of(d.radial_percent));
      fig69[i].push_back(mean_of(d.curvilinear_mm));
    }
  }
}

void write_truth_differences(std::ostream& md, const HjcStudyResult& result) {
  md << "\n## Differences to the true centre over all six rotations\n\n"
     << "| centre | radial (% of truth) | radial (mm) | curvilinear (mm) |\n|---|---|---|---|\n";
  for (const auto& m : geometry::hjc_method_names()) {
    const OverallDifferences o = overall(result.subjects, m, "truth");
    md << "| " << m << " | " << fixed_or(o.radial_percent, 1, "-") << " +- " << fixed_or(o.radial_percent_sd, 1, "-") << " | "
       << fixed_or(o.radial_mm, 3, "-") << " | " << fixed_or(o.curvilinear_mm, 3, "-") << " +- " << fixed_or(o.curvilinear_sd, 3, "-") << " |\n";
  }
  md << "\n## Effect of a known centre error (true centre displaced along +-X, +-Y, +-Z of the hip frame)\n\n"
     << "| centre error | radial (% of truth) | radial (mm) | curvilinear (mm) | max curvilinear difference (mm) |\n|---|---|---|---|---|\n";
  for (const double offset : result.options.centre_offsets_mm) {
    std::vector<double> rp, rm, cm;
    double cmax = 0.0;
    for (const auto& s : result.subjects) {
      for (const auto& [name, direction] : hjc_offset_directions()) {
        (void)direction;
        const Differences d = differences(s, hjc_offset_label(name, offset), "truth");
        rp.push_back(mean_of(d.radial_percent));
        rm.push_back(mean_of(d.radial_mm));
        cm.push_back(mean_of(d.curvilinear_mm));
        for (const double x : d.curvilinear_mm) cmax = std::max(cmax, x);
      }
    }
    md << "| " << fixed_or(offset, 0, "-") << " mm | " << fixed_or(mean_of(rp), 1, "-") << " | " << fixed_or(mean_of(rm), 3, "-") << " | "
       << fixed_or(mean_of(cm), 3, "-") << " | " << fixed_or(cmax, 2, "-") << " |\n";
  }
}

// "[min, max]" of the finite values, "-" when there is none.
std::string finite_range(const std::vector<double>& v, int digits) {
  double lo = 1e300, hi = -1e300;
  for (const double x : v) if (std::isfinite(x)) { lo = std::min(lo, x); hi = std::max(hi, x); }
  return lo > hi ? std::string("-") : "[" + fixed_or(lo, digits, "-") + ", " + fixed_or(hi, digits, "-") + "]";
}

// One row of the per-rotation table (Eq. 14-15): per compared method the mean over subjects of
// the mean difference to dref and its [min, max]; then the mean over methods. Returns that mean
// (radial %, NaN where undefined; curvilinear mm).
std::pair<double, double> write_rotation_row(std::ostream& md, const HjcStudyResult& result,
                                             const std::string& rotation, FigureValues& fig70, FigureValues& fig71) {
  md << "| " << rotation << " |";
  std::vector<double> all_rp, all_cm;
  for (std::size_t i = 0; i < kCompared.size(); ++i) {
    std::vector<double> rp, cm;
    for (const auto& s : result.subjects) {
      const Differences d = differences(s, kCompared[i], "dref", rotation);
      rp.push_back(mean_of(d.radial_percent));
      cm.push_back(mean_of(d.curvilinear_mm));
    }
    std::vector<double> rp_finite;
    for (const double x : rp) if (std::isfinite(x)) rp_finite.push_back(x);
    const double rpm = mean_of(rp_finite), cmm = mean_of(cm);
    fig70[i].push_back(rpm);
    fig71[i].push_back(cmm);
    if (std::isfinite(rpm)) all_rp.push_back(rpm);
    all_cm.push_back(cmm);
    md << ' ' << fixed_or(rpm, 1, "-") << ' ' << finite_range(rp_finite, 1) << " | " << fixed_or(cmm, 3, "-") << ' ' << finite_range(cm, 2) << " |";
  }
  const double mr = mean_of(all_rp), mc = mean_of(all_cm);
  md << ' ' << fixed_or(mr, 1, "-") << " | " << fixed_or(mc, 3, "-") << " |\n";
  return {mr, mc};
}

// Eq. 14-15 per rotation (Figs. 70-71) and the sensitivity ranking.
void write_per_rotation(std::ostream& md, const HjcStudyResult& result, FigureValues& fig70, FigureValues& fig71) {
  md << "\n## Per rotation (thesis Eq. 14-15, Figs. 70-71): mean over subjects of the mean difference to dref, [min, max]\n\n"
     << "| rotation |";
  for (const auto& m : kCompared) md << ' ' << m << " radial % | " << m << " curv. mm |";
  md << " mean radial % | mean curv. mm |\n|---|";
  for (std::size_t i = 0; i < kCompared.size() * 2 + 2; ++i) md << "---|";
  md << '\n';
  fig70.assign(kCompared.size(), {});
  fig71.assign(kCompared.size(), {});
  std::vector<std::pair<double, std::string>> rank_radial, rank_curvilinear;
  for (const auto& [rotation, amplitude] : hjc_study_rotations()) {
    (void)amplitude;
    const auto [mr, mc] = write_rotation_row(md, result, rotation, fig70, fig71);
    rank_radial.push_back({std::isfinite(mr) ? mr : -1.0, rotation});
    rank_curvilinear.push_back({mc, rotation});
  }
  std::sort(rank_radial.rbegin(), rank_radial.rend());
  std::sort(rank_curvilinear.rbegin(), rank_curvilinear.rend());
  md << "\nSensitivity ranking, most sensitive first (thesis: flexion among the most sensitive, adduction and "
        "external rotation the least). Radial: ";
  for (std::size_t i = 0; i < rank_radial.size(); ++i) md << (i ? " > " : "") << rank_radial[i].second;
  md << ". Curvilinear: ";
  for (std::size_t i = 0; i < rank_curvilinear.size(); ++i) md << (i ? " > " : "") << rank_curvilinear[i].second;
  md << ".\n\nA radial percentage is undefined where dref's radial depth is 0 ('-'). Figures: fig67_radial.svg, "
        "fig67_curvilinear.svg (first subject, extension), fig68.svg, fig69.svg (per subject), fig70.svg, fig71.svg "
        "(per rotation).\n";
}

// Fig. 67 analogue: the depths of the first subject through extension about each centre.
void write_fig67(const HjcSubjectResult& s, const std::filesystem::path& dir) {
  for (const bool radial : {true, false}) {
    LineChart chart;
    chart.title = std::string("Fig. 67 analogue: ") + (radial ? "radial" : "curvilinear") + " depth, extension, " + s.id;
    chart.x_label = "extension (deg)";
    chart.y_label = "maximum depth (mm)";
    for (const std::string label : {"dref", "acetabulumsphere", "doublesphere", "femoralheadsphere", "dconst", "truth"}) {
      const auto& d = s.depths.at(label).at("extension");
      chart.series.push_back({label, d.angle_deg, radial ? d.radial_mm : d.curvilinear_mm, label == "truth"});
    }
    write_svg(chart, dir / (radial ? "fig67_radial.svg" : "fig67_curvilinear.svg"));
  }
}

void write_heat_map(const std::string& title, const std::string& column_label, const std::vector<std::string>& columns,
                    const FigureValues& values, const std::string& unit, const std::filesystem::path& path) {
  HeatMap map;
  map.title = title;
  map.row_label = "method";
  map.column_label = column_label;
  map.unit = unit;
  map.row_names = kCompared;
  map.column_names = columns;
  map.values = values;
  write_svg(map, path);
}

void write_figures(const HjcStudyResult& result, const FigureValues& fig68, const FigureValues& fig69,
                   const FigureValues& fig70, const FigureValues& fig71, const std::filesystem::path& dir) {
  write_fig67(result.subjects.front(), dir);
  std::vector<std::string> subject_names;
  for (const auto& x : result.subjects) subject_names.push_back(x.id);
  std::vector<std::string> rotation_names;
  for (const auto& [rotation, amplitude] : hjc_study_rotations()) { (void)amplitude; rotation_names.push_back(rotation); }
  write_heat_map("Fig. 68 analogue: mean radial difference to dref", "subject", subject_names, fig68, "%", dir / "fig68.svg");
  write_heat_map("Fig. 69 analogue: mean curvilinear difference to dref", "subject", subject_names, fig69, "mm", dir / "fig69.svg");
  write_heat_map("Fig. 70 analogue: radial difference to dref per rotation", "rotation", rotation_names, fig70, "%", dir / "fig70.svg");
  write_heat_map("Fig. 71 analogue: curvilinear difference to dref per rotation", "rotation", rotation_names, fig71, "mm", dir / "fig71.svg");
}

void write_steps_csv(const HjcStudyResult& result, const std::filesystem::path& path) {
  std::ostringstream steps;
  steps << "subject,centre,center_x_mm,center_y_mm,center_z_mm,rotation,angle_deg,curvilinear_mm,radial_mm\n";
  steps.precision(8);
  for (const auto& s : result.subjects) {
    for (const auto& [label, rotations] : s.depths) {
      const Vec3& c = s.centres_mm.at(label);
      for (const auto& [rotation, d] : rotations) {
        for (std::size_t k = 0; k < d.angle_deg.size(); ++k) {
          steps << s.id << ',' << label << ',' << c.x() << ',' << c.y() << ',' << c.z() << ',' << rotation << ','
                << d.angle_deg[k] << ',' << d.curvilinear_mm[k] << ',' << d.radial_mm[k] << '\n';
        }
      }
    }
  }
  write_file_atomically(path, steps.str());
}

void write_results_h5(const HjcStudyResult& result, const std::filesystem::path& path) {
  ResultsFile h5(path);
  h5.set_attribute("/", "units", "mm, deg");
  h5.set_attribute("/", "git_sha", kGitSha);
  h5.set_attribute("/", "study", "hjc sensitivity (thesis 4.4)");
  for (const auto& s : result.subjects) {
    for (const auto& [label, rotations] : s.depths) {
      std::string group = "/" + s.id + "/" + label;
      for (char& ch : group) if (ch == ' ') ch = '_';
      const Vec3& c = s.centres_mm.at(label);
      h5.write(group + "/center_mm", {c.x(), c.y(), c.z()}, 3, "mm");
      for (const auto& [rotation, d] : rotations) {
        std::vector<double> table;
        for (std::size_t k = 0; k < d.angle_deg.size(); ++k) table.insert(table.end(), {d.angle_deg[k], d.curvilinear_mm[k], d.radial_mm[k]});
        h5.write(group + "/" + rotation, table, 3, "deg, mm, mm");
        h5.set_attribute(group + "/" + rotation, "columns", "angle_deg,curvilinear_mm,radial_mm");
      }
    }
  }
  h5.commit();
}

std::filesystem::path write_subjects_report(const HjcStudyResult& result, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  std::ostringstream md;
  FigureValues fig68, fig69, fig70, fig71;
  write_centre_errors(md, result);
  write_dref_differences(md, result, fig68, fig69);
  write_truth_differences(md, result);
  write_per_rotation(md, result, fig70, fig71);
  write_figures(result, fig68, fig69, fig70, fig71, dir);
  const std::filesystem::path report = dir / "report.md";
  write_file_atomically(report, md.str());
  write_steps_csv(result, dir / "steps.csv");
  write_results_h5(result, dir / "results.h5");
  return report;
}

}  // namespace

std::filesystem::path write_hjc_study_report(const HjcStudyResult& result, const std::filesystem::path& dir) {
  return result.options.femur.empty() ? write_subjects_report(result, dir) : write_bones_report(result, dir);
}

}  // namespace hipfai::studies
