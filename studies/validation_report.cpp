#include "studies/validation_report.h"

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/numbers.h"
#include "core/text_format.h"
#include "studies/fai_reference.h"
#include "studies/fai_study.h"
#include "studies/pipeline/hip_source.h"
#include "studies/reports/svg_plot.h"
#include "studies/results/fe_step_record.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

namespace hipfai::studies {

namespace {

using hipfai::kNaN;
const std::vector<std::string> kDepths{"curvilinear", "radial"};

// The primary FE measure: the ball-averaged peak von Mises of the whole model (the largest over
// the tissues). The thesis correlates with "the maximum von Mises stress"; a Gauss-point maximum
// sits at the singular bonded corners and grows with refinement, the ball average converges
// (fem/peak_measures.h, docs/fem-levels.md).
const std::string kPrimary = fe_measure_name(VonMisesMeasure{VonMisesStat::kBall, std::nullopt});

std::string scientific(double value) {
  if (!std::isfinite(value)) return "–";
  std::ostringstream out;
  if (value >= 1e-3) out << std::setprecision(3) << value;
  else out << std::scientific << std::setprecision(2) << value;
  return out.str();
}

std::string id_of(double ce, double alpha) { return parametric_hip_id(ce, alpha); }

struct Moments {
  double mean = kNaN, sd = kNaN, min = kNaN, max = kNaN;
  int n = 0;
};

Moments moments(const std::vector<double>& values) {
  Moments m;
  m.n = static_cast<int>(values.size());
  if (values.empty()) return m;
  m.mean = std::accumulate(values.begin(), values.end(), 0.0) / values.size();
  double ss = 0;
  for (double v : values) ss += (v - m.mean) * (v - m.mean);
  m.sd = values.size() > 1 ? std::sqrt(ss / (values.size() - 1)) : kNaN;  // sample SD
  m.min = *std::min_element(values.begin(), values.end());
  m.max = *std::max_element(values.begin(), values.end());
  return m;
}

double max_finite(const std::vector<double>& values) {
  double m = kNaN;
  for (double v : values) {
    if (std::isfinite(v) && !(v <= m)) m = v;
  }
  return m;
}

const ValidationCorrelation* find(const std::vector<ValidationCorrelation>& rows, double ce, double alpha,
                                  const std::string& depth, const std::string& measure) {
  for (const auto& row : rows) {
    if (row.ce_deg == ce && row.alpha_deg == alpha && row.depth == depth && row.measure == measure) return &row;
  }
  return nullptr;
}

bool on_thesis_grid(double ce, double alpha) {
  const auto on = [](double v, double lo, double hi) {
    return v >= lo - 1e-9 && v <= hi + 1e-9 && std::abs(v / 10.0 - std::round(v / 10.0)) < 1e-9;
  };
  return on(ce, 0, 40) && on(alpha, 40, 80);
}

std::string our_cell(const ValidationCorrelation* row) {
  if (row == nullptr) return "–";
  if (row->status == "ok") return fixed_or(row->summary.pearson.r, 2, "–") + ", " + scientific(row->summary.pearson.p_value);
  return row->status;
}

std::string thesis_cell(const ThesisCorrelation& cell) {
  return cell.penetrates ? fixed_or(cell.r, 2, "–") + ", " + scientific(cell.p) : "n.p.";
}

// Table 8 or 9 for one measure in the thesis' layout: rows CE, columns alpha.
void write_table(std::ostream& md, const std::vector<ValidationCorrelation>& rows, const std::vector<double>& ces,
                 const std::vector<double>& alphas, const std::string& depth, const std::string& measure,
                 bool with_thesis) {
  md << "| CE \\ alpha |";
  for (double a : alphas) md << ' ' << a << "° |";
  md << "\n|---|";
  for (std::size_t i = 0; i < alphas.size(); ++i) md << "---|";
  md << '\n';
  for (double ce : ces) {
    md << "| CE " << ce << "° |";
    for (double alpha : alphas) {
      const ValidationCorrelation* row = find(rows, ce, alpha, depth, measure);
      md << ' ' << our_cell(row);
      if (with_thesis && on_thesis_grid(ce, alpha)) {
        const ThesisCorrelation thesis =
            depth == "curvilinear" ? thesis_table8(ce, alpha) : thesis_table9(ce, alpha);
        md << " <br>thesis " << thesis_cell(thesis);
        if (thesis.penetrates && row != nullptr && row->status == "ok") {
          md << " <br>Δr " << (row->summary.pearson.r >= thesis.r ? "+" : "") << fixed_or(row->summary.pearson.r - thesis.r, 2, "–");
        }
      }
      md << " |";
    }
    md << '\n';
  }
  md << '\n';
}

std::vector<double> sorted_unique(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  return values;
}

void write_fig60(const ValidationData& data, const ValidationHipSeries& hip, const std::vector<ValidationCorrelation>& rows,
                 const std::filesystem::path& path) {
  const std::size_t primary =
      std::find(data.measures.begin(), data.measures.end(), kPrimary) - data.measures.begin();
  LineChart chart;
  chart.title = "CE " + fixed_or(hip.ce_deg, 0, "–") + "° / alpha " + fixed_or(hip.alpha_deg, 0, "–") +
                "°: maximum depths and von Mises over standing-to-sitting";
  chart.x_label = "rotation along the motion (deg)";
  chart.y_label = "maximum penetration depth (mm)";
  chart.y2_label = "von Mises, ball-averaged model peak (MPa)";
  chart.series.push_back({"curvilinear depth", hip.angle_deg, hip.curvilinear_mm, false});
  chart.series.push_back({"radial depth", hip.angle_deg, hip.radial_mm, true});
  if (primary < hip.fe.size()) {
    Series vm{"von Mises (right axis)", hip.angle_deg, hip.fe[primary], false};
    vm.right_axis = true;
    chart.series.push_back(vm);
  }
  for (const std::string& depth : kDepths) {
    const ValidationCorrelation* row = find(rows, hip.ce_deg, hip.alpha_deg, depth, kPrimary);
    chart.notes.push_back(row != nullptr && row->status == "ok"
                              ? depth + ": r " + fixed_or(row->summary.pearson.r, 2, "–") + " (p " +
                                    scientific(row->summary.pearson.p_value) + ")"
                              : depth + ": " + our_cell(row));
  }
  write_svg(chart, path);
}

void write_scatter(const ValidationData& data, const std::string& depth, const std::filesystem::path& path) {
  const std::size_t primary =
      std::find(data.measures.begin(), data.measures.end(), kPrimary) - data.measures.begin();
  LineChart chart;
  chart.title = "All steps of all hips: " + depth + " depth vs von Mises";
  chart.x_label = "maximum " + depth + " penetration depth (mm)";
  chart.y_label = "von Mises, ball-averaged model peak (MPa)";
  std::map<double, Series> by_ce;
  for (const ValidationHipSeries& hip : data.hips) {
    if (primary >= hip.fe.size()) continue;
    Series& s = by_ce[hip.ce_deg];
    s.name = "CE " + fixed_or(hip.ce_deg, 0, "–") + "°";
    s.markers = true;
    const std::vector<double>& d = hip.depth(depth);
    for (std::size_t k = 0; k < d.size(); ++k) {
      s.x.push_back(d[k]);
      s.y.push_back(hip.fe[primary][k]);
    }
  }
  for (auto& [ce, series] : by_ce) chart.series.push_back(series);
  write_svg(chart, path);
}

void write_rmap(const std::vector<ValidationCorrelation>& rows, const std::vector<double>& ces,
                const std::vector<double>& alphas, const std::string& depth, const std::filesystem::path& path) {
  HeatMap map;
  map.title = "r, " + depth + " depth vs von Mises";
  map.row_label = "CE (deg)";
  map.column_label = "alpha (deg)";
  map.unit = "r";
  map.diverging = true;
  for (double ce : ces) map.row_names.push_back(fixed_or(ce, 0, "–"));
  for (double a : alphas) map.column_names.push_back(fixed_or(a, 0, "–"));
  for (double ce : ces) {
    std::vector<double> values;
    std::vector<std::string> text;
    for (double alpha : alphas) {
      const ValidationCorrelation* row = find(rows, ce, alpha, depth, kPrimary);
      const bool ok = row != nullptr && row->status == "ok";
      values.push_back(ok ? row->summary.pearson.r : kNaN);
      text.push_back(ok ? fixed_or(row->summary.pearson.r, 2, "–") : (row ? row->status : "–"));
    }
    map.values.push_back(values);
    map.cell_text.push_back(text);
  }
  write_svg(map, path);
}

// ParaView multiblock of the end pose: the FE's VTU and the tissues with their depth fields.
std::string write_fig61_vtm(const std::filesystem::path& dir, const std::string& name) {
  if (!std::filesystem::is_directory(dir)) return {};
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".vtu" || ext == ".vtp") files.push_back(entry.path().filename().string());
  }
  if (files.empty()) return {};
  std::sort(files.begin(), files.end());
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\">\n  <vtkMultiBlockDataSet>\n";
  for (std::size_t i = 0; i < files.size(); ++i) {
    xml << "    <DataSet index=\"" << i << "\" name=\"" << std::filesystem::path(files[i]).stem().string()
        << "\" file=\"" << files[i] << "\"/>\n";
  }
  xml << "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
  const std::string file = name + "_end_pose.vtm";
  write_file_atomically(dir / file, xml.str());
  return file;
}

}  // namespace

std::vector<ValidationCorrelation> correlate_validation(const ValidationData& data) {
  std::vector<ValidationCorrelation> rows;
  for (const ValidationHipSeries& hip : data.hips) {
    for (const std::string& depth : kDepths) {
      const std::vector<double>& d = hip.depth(depth);
      const bool penetrates = max_finite(d) > 0.0;
      for (std::size_t m = 0; m < data.measures.size(); ++m) {
        ValidationCorrelation row;
        row.ce_deg = hip.ce_deg;
        row.alpha_deg = hip.alpha_deg;
        row.depth = depth;
        row.measure = data.measures[m];
        std::vector<double> x, y;
        for (std::size_t k = 0; k < d.size(); ++k) {
          if (std::isfinite(d[k]) && std::isfinite(hip.fe[m][k])) {
            x.push_back(d[k]);
            y.push_back(hip.fe[m][k]);
          }
        }
        row.summary = stats::correlate(x, y);
        row.status = penetrates ? row.summary.status : "n.p.";
        rows.push_back(row);
      }
    }
  }
  return rows;
}

ValidationClassification classify_leave_one_out(const ValidationData& data) {
  ValidationClassification result;
  const std::size_t n = data.hips.size();
  // Features: maximum curvilinear, maximum radial, their normalised difference (thesis §4.3.2.4).
  double max_c = 0, max_r = 0;
  for (const auto& hip : data.hips) {
    max_c = std::max(max_c, std::isfinite(max_finite(hip.curvilinear_mm)) ? max_finite(hip.curvilinear_mm) : 0.0);
    max_r = std::max(max_r, std::isfinite(max_finite(hip.radial_mm)) ? max_finite(hip.radial_mm) : 0.0);
  }
  std::vector<std::array<double, 3>> features;
  for (const auto& hip : data.hips) {
    const double c = std::max(0.0, max_finite(hip.curvilinear_mm));
    const double r = std::max(0.0, max_finite(hip.radial_mm));
    features.push_back({c, r, (max_c > 0 ? c / max_c : 0.0) - (max_r > 0 ? r / max_r : 0.0)});
    result.truth.push_back(pathology_of(hip.ce_deg, hip.alpha_deg));
  }
  for (const char* name : {"normal", "dysplasia", "cam", "pincer", "combined cam-pincer",
                           "combined dysplasia-impingement"}) {
    result.classes.emplace_back(name);
  }
  result.confusion.assign(result.classes.size(), std::vector<int>(result.classes.size(), 0));
  for (std::size_t i = 0; i < n; ++i) {
    // Scale each feature by its range over the other hips.
    std::array<double, 3> lo{}, hi{};
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      for (int f = 0; f < 3; ++f) lo[f] = std::min(lo[f], features[j][f]), hi[f] = std::max(hi[f], features[j][f]);
    }
    double best = std::numeric_limits<double>::infinity();
    std::size_t nearest = n;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      double d2 = 0;
      for (int f = 0; f < 3; ++f) {
        const double range = hi[f] > lo[f] ? hi[f] - lo[f] : 1.0;
        const double diff = (features[i][f] - features[j][f]) / range;
        d2 += diff * diff;
      }
      if (d2 < best) best = d2, nearest = j;  // ties: the first in data order
    }
    const std::string assigned = nearest < n ? result.truth[nearest] : std::string("normal");
    result.assigned.push_back(assigned);
    const auto index = [&](const std::string& name) {
      return static_cast<std::size_t>(std::find(result.classes.begin(), result.classes.end(), name) -
                                      result.classes.begin());
    };
    ++result.confusion[index(result.truth[i])][index(assigned)];
    result.correct += assigned == result.truth[i];
  }
  return result;
}

namespace {

void write_correlation_csv(const std::vector<ValidationCorrelation>& rows, const std::filesystem::path& path) {
  std::ostringstream csv;
  csv << "ce_deg,alpha_deg,depth,measure,n,r,p,spearman,ci_low,ci_high,status\n";
  csv << std::setprecision(10);
  for (const auto& row : rows) {
    const bool ok = row.status == "ok";
    auto cell = [&](double v) { return ok && std::isfinite(v) ? [&] { std::ostringstream o; o << std::setprecision(10) << v; return o.str(); }() : std::string(); };
    csv << row.ce_deg << ',' << row.alpha_deg << ',' << row.depth << ',' << row.measure << ',' << row.summary.n
        << ',' << cell(row.summary.pearson.r) << ',' << cell(row.summary.pearson.p_value) << ','
        << cell(row.summary.spearman.r) << ','
        << (ok && row.summary.interval.defined ? cell(row.summary.interval.low) : std::string()) << ','
        << (ok && row.summary.interval.defined ? cell(row.summary.interval.high) : std::string()) << ','
        << row.status << '\n';
  }
  write_file_atomically(path, csv.str());
}

// The FE level of the run that wrote timings.csv.
std::string fe_level_of(const ValidationData& data) {
  return data.timings.empty() ? std::string("unknown") : data.timings.front().fe_level;
}

int steps_of(const ValidationData& data) { return static_cast<int>(data.hips.front().angle_deg.size()); }

void write_introduction(std::ostream& md, const ValidationData& data) {
  md << "# FAI validation: penetration depth vs the FE ground truth\n\n";
  md << data.hips.size() << " hips, " << steps_of(data) << " steps of standing-to-sitting each; FE level **"
     << fe_level_of(data) << "**. Made by `hipfai report correlation` from `steps.csv` and `timings.csv` in this folder.\n\n";
  md << "Per hip, the per-step maximum penetration depth is correlated with each FE measure over the steps "
        "(Pearson r with its two-sided p from Student's t with n − 2 degrees of freedom, as the thesis; "
        "Spearman's rho and the Fisher-z 95 % interval are in `correlation.csv`). \"n.p.\": the hip never "
        "penetrates; \"constant\": the FE measure does not vary. FE steps that did not converge are left out.\n\n";
  md << "**Primary FE measure: `" << kPrimary << "`**, the ball-averaged peak von Mises stress of the whole "
        "model (the largest over labrum and cartilages). The thesis correlates with \"the maximum von Mises "
        "stress\"; our Gauss-point maximum (`von_mises_max_model_mpa`) sits at the singular bonded corners of "
        "the labrum and grows with mesh refinement, while the ball average converges (docs/fem-levels.md). "
        "Every other measure (per tissue: ball, max, p95; contact pressure: max, ball, mean) has its own "
        "tables below.\n\n";
}

// The primary measure's mean r per depth and over both, against the thesis; then every measure's.
void write_summary(std::ostream& md, const ValidationData& data, const std::vector<ValidationCorrelation>& rows,
                   CorrelationReportResult& result) {
  md << "## Summary (primary measure)\n\n";
  md << "| depth | hips with r | mean r | SD (sample) | range | thesis mean | thesis SD | thesis range |\n";
  md << "|---|---|---|---|---|---|---|---|\n";
  std::vector<double> all;
  for (const std::string& depth : kDepths) {
    std::vector<double> rs;
    for (const auto& row : rows) {
      if (row.depth == depth && row.measure == kPrimary && row.status == "ok") rs.push_back(row.summary.pearson.r);
    }
    all.insert(all.end(), rs.begin(), rs.end());
    const Moments m = moments(rs);
    const ThesisCorrelationSummary t =
        depth == "curvilinear" ? thesis_summary_curvilinear() : thesis_summary_radial();
    md << "| " << depth << " | " << m.n << " | " << fixed_or(m.mean, 2, "–") << " | " << fixed_or(m.sd, 2, "–") << " | "
       << fixed_or(m.min, 2, "–") << " – " << fixed_or(m.max, 2, "–") << " | " << fixed_or(t.mean, 2, "–") << " | " << fixed_or(t.sd, 2, "–")
       << " | " << fixed_or(t.min, 2, "–") << " – " << fixed_or(t.max, 2, "–") << " |\n";
    (depth == "curvilinear" ? result.mean_r_curvilinear : result.mean_r_radial) = m.mean;
  }
  {
    const Moments m = moments(all);
    const ThesisCorrelationSummary t = thesis_summary_all();
    md << "| all | " << m.n << " | " << fixed_or(m.mean, 2, "–") << " | " << fixed_or(m.sd, 2, "–") << " | " << fixed_or(m.min, 2, "–")
       << " – " << fixed_or(m.max, 2, "–") << " | " << fixed_or(t.mean, 2, "–") << " | " << fixed_or(t.sd, 2, "–") << " | "
       << fixed_or(t.min, 2, "–") << " – " << fixed_or(t.max, 2, "–") << " |\n\n";
    result.mean_r_all = m.mean;
    result.ok_cells = m.n;
  }
  md << "Mean r of every measure (cells with status ok):\n\n| measure | curvilinear: hips, mean r | radial: hips, mean r |\n|---|---|---|\n";
  for (const std::string& measure : data.measures) {
    md << "| `" << measure << "` |";
    for (const std::string& depth : kDepths) {
      std::vector<double> rs;
      for (const auto& row : rows) {
        if (row.depth == depth && row.measure == measure && row.status == "ok") rs.push_back(row.summary.pearson.r);
      }
      const Moments m = moments(rs);
      md << ' ' << m.n << ", " << fixed_or(m.mean, 2, "–") << " |";
    }
    md << '\n';
  }
  md << '\n';
}

void write_tables_8_and_9(std::ostream& md, const ValidationData& data, const std::vector<ValidationCorrelation>& rows,
                          const std::vector<double>& ces, const std::vector<double>& alphas) {
  const bool has_primary = std::find(data.measures.begin(), data.measures.end(), kPrimary) != data.measures.end();
  for (const std::string& depth : kDepths) {
    const bool curvilinear = depth == "curvilinear";
    md << "## " << (curvilinear ? "Table 8" : "Table 9") << ": " << depth
       << " depth vs FE, r and p per hip (ours, thesis, difference)\n\n";
    md << (curvilinear ? "Curvilinear depth: femur bone vs labrum (cylindrical segmenting)."
                       : "Radial depth: femur vs acetabular cartilage + labrum (radial segmenting).")
       << " Cells: our r, p; the thesis' r, p (or n.p.); Δr = ours − thesis.\n\n";
    if (has_primary) {
      md << "### `" << kPrimary << "` (primary)\n\n";
      write_table(md, rows, ces, alphas, depth, kPrimary, true);
    }
    for (const std::string& measure : data.measures) {
      if (measure == kPrimary) continue;
      md << "### `" << measure << "`\n\n";
      write_table(md, rows, ces, alphas, depth, measure, true);
    }
  }
}

void write_across_hips(std::ostream& md, const ValidationData& data) {
  md << "## Across hips: maximum depth vs maximum FE measure (not in the thesis)\n\n";
  md << "One point per hip: the largest depth over the motion against the largest FE value over the motion.\n\n";
  md << "| depth | measure | hips | r | p | Spearman rho | 95 % CI of r | status |\n|---|---|---|---|---|---|---|---|\n";
  for (const std::string& depth : kDepths) {
    for (std::size_t m = 0; m < data.measures.size(); ++m) {
      std::vector<double> x, y;
      for (const auto& hip : data.hips) {
        const double d = max_finite(hip.depth(depth)), v = max_finite(hip.fe[m]);
        if (std::isfinite(d) && std::isfinite(v)) x.push_back(d), y.push_back(v);
      }
      const stats::CorrelationSummary s = stats::correlate(x, y);
      const bool ok = s.status == "ok";
      md << "| " << depth << " | `" << data.measures[m] << "` | " << s.n << " | "
         << (ok ? fixed_or(s.pearson.r, 2, "–") : "–") << " | " << (ok ? scientific(s.pearson.p_value) : "–") << " | "
         << (ok ? fixed_or(s.spearman.r, 2, "–") : "–") << " | "
         << (ok && s.interval.defined ? fixed_or(s.interval.low, 2, "–") + " – " + fixed_or(s.interval.high, 2, "–") : "–")
         << " | " << s.status << " |\n";
    }
  }
  md << '\n';
}

void write_figures(std::ostream& md, const ValidationData& data, const std::vector<ValidationCorrelation>& rows,
                   const std::vector<double>& ces, const std::vector<double>& alphas, const std::filesystem::path& dir) {
  const bool has_primary = std::find(data.measures.begin(), data.measures.end(), kPrimary) != data.measures.end();
  md << "## Figures\n\n";
  if (has_primary) {
    for (const auto& [ce, alpha] : std::vector<std::pair<double, double>>{{40, 60}, {40, 40}, {20, 80}, {40, 80}}) {
      for (const auto& hip : data.hips) {
        if (hip.ce_deg != ce || hip.alpha_deg != alpha) continue;
        const std::string file = "fig60_" + id_of(ce, alpha) + ".svg";
        write_fig60(data, hip, rows, dir / file);
        md << "![Fig. 60, CE " << ce << "° / alpha " << alpha << "°](" << file << ")\n\n";
      }
    }
    for (const std::string& depth : kDepths) {
      write_scatter(data, depth, dir / ("scatter_" + depth + ".svg"));
      md << "![" << depth << " depth vs von Mises](scatter_" << depth << ".svg)\n\n";
      write_rmap(rows, ces, alphas, depth, dir / ("rmap_" + depth + ".svg"));
      md << "![r map, " << depth << "](rmap_" << depth << ".svg)\n\n";
    }
  }
  const std::string vtm = write_fig61_vtm(dir / "fig61", id_of(40, 60));
  if (!vtm.empty()) {
    md << "Fig. 61 for ParaView: `fig61/" << vtm << "` — the CE 40° / alpha 60° hip at the end pose of the motion: "
          "`fe.vtu` (FE mesh on the rotated configuration with displacement, von Mises per cell, contact pressure) "
          "and one VTP per tissue with the last step's curvilinear and radial depth fields (femur side rotated "
          "to the end pose).\n\n";
  }
}

void write_classification(std::ostream& md, const ValidationData& data) {
  const ValidationClassification classification = classify_leave_one_out(data);
  md << "## Classification from the two depths (leave-one-out)\n\n";
  md << "Each hip is assigned the pathology (thesis Fig. 63: from CE and alpha) of its nearest other hip in "
        "(maximum curvilinear, maximum radial, normalised difference), each feature scaled by the other hips' "
        "range; the hip itself never takes part in its own rule. "
     << classification.correct << " of " << data.hips.size() << " assigned correctly.\n\n";
  md << "| true \\ assigned |";
  for (const auto& c : classification.classes) md << ' ' << c << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < classification.classes.size(); ++i) md << "---|";
  md << '\n';
  for (std::size_t i = 0; i < classification.classes.size(); ++i) {
    md << "| " << classification.classes[i] << " |";
    for (int count : classification.confusion[i]) md << ' ' << count << " |";
    md << '\n';
  }
  md << "\nHips that never penetrate (normal, dysplasia) have identical features (0, 0, 0): the depths cannot "
        "tell them apart, as the thesis notes (§4.3.4); they are assigned the class of the first such hip.\n\n";
}

void write_stage_times(std::ostream& md, const ValidationData& data) {
  const std::string level = fe_level_of(data);
  const int steps = steps_of(data);
  if (!data.timings.empty()) {
    double generate = 0, tables = 0, query = 0, fe = 0, fe_steps = 0, dofs = 0;
    int failed = 0, reused = 0, generated = 0;
    for (const auto& t : data.timings) {
      generate += t.generate_s, tables += t.penetration_tables_ms, query += t.penetration_query_ms;
      fe += t.fe_s, fe_steps += t.fe_step_s, dofs += t.fe_dofs, failed += t.fe_steps_failed;
      reused += t.fe_reused, generated += t.generate_s > 0;
    }
    const double n_hips = data.timings.size(), n_steps = n_hips * steps;
    md << "## Time per stage: what accuracy costs\n\n";
    md << "| stage | total | per hip | per step |\n|---|---|---|---|\n";
    md << "| generate hip (gmsh; " << generated << " generated, the rest cached) | " << fixed_or(generate, 1, "–") << " s | "
       << fixed_or(generated > 0 ? generate / generated : 0.0, 1, "–") << " s | – |\n";
    md << "| penetration tables (cylindrical + radial) | " << fixed_or(tables / 1e3, 2, "–") << " s | "
       << fixed_or(tables / n_hips, 1, "–") << " ms | – |\n";
    md << "| penetration queries (curvilinear + radial) | " << fixed_or(query / 1e3, 3, "–") << " s | "
       << fixed_or(query / n_hips, 1, "–") << " ms | " << fixed_or(query / n_steps, 2, "–") << " ms |\n";
    md << "| FE, level " << level << " (mean " << fixed_or(dofs / n_hips, 0, "–") << " DOFs; whole runs incl. meshing) | "
       << fixed_or(fe, 0, "–") << " s | " << fixed_or(fe / n_hips, 1, "–") << " s | " << fixed_or(fe_steps / n_steps, 2, "–") << " s |\n\n";
    if (query > 0) {
      md << "One FE step costs " << fixed_or(fe_steps / n_steps / (query / n_steps / 1e3), 0, "–")
         << " times one penetration step (both depths). FE steps not converged: " << failed << " of "
         << fixed_or(n_steps, 0, "–") << "; FE runs taken from the cache in the run that wrote timings.csv: " << reused
         << ". Times of cached FE runs are those measured when they were solved.\n\n";
    }
  }
}

}  // namespace

CorrelationReportResult write_correlation_report(const std::filesystem::path& dir) {
  const ValidationData data = read_validation_results(dir);
  const std::vector<ValidationCorrelation> rows = correlate_validation(data);
  CorrelationReportResult result;
  result.correlation_csv = dir / "correlation.csv";
  result.report = dir / "report.md";
  write_correlation_csv(rows, result.correlation_csv);

  std::vector<double> ces, alphas;
  for (const auto& hip : data.hips) ces.push_back(hip.ce_deg), alphas.push_back(hip.alpha_deg);
  ces = sorted_unique(ces);
  alphas = sorted_unique(alphas);
  std::ostringstream md;
  write_introduction(md, data);
  write_summary(md, data, rows, result);
  write_tables_8_and_9(md, data, rows, ces, alphas);
  write_across_hips(md, data);
  write_figures(md, data, rows, ces, alphas, dir);
  write_classification(md, data);
  write_stage_times(md, data);
  write_file_atomically(result.report, md.str());
  return result;
}

}  // namespace hipfai::studies
