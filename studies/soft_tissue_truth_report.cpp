// hipfai — the tables of the soft-tissue known-truth study (see soft_tissue_truth_report.h).
#include "studies/soft_tissue_truth_report.h"

#include "core/atomic_file.h"
#include "core/text_format.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace hipfai::studies {
namespace {

// Relative difference in %, or "-" when both are zero.
std::string percent(double generated, double synthesised) {
  if (generated == 0.0 && synthesised == 0.0) return "-";
  if (generated == 0.0) return "new";
  return fixed(100.0 * (synthesised - generated) / generated, 1);
}

// The FE measures compared, in column order: name, and the value of a run's peaks.
struct PeakMeasure {
  std::string name, label;
  double (*of)(const SoftTissueFePeaks&, std::size_t tissue);
  std::size_t tissue;
};
std::vector<PeakMeasure> fe_measures() {
  std::vector<PeakMeasure> measures{
      {"fe_ball_pressure_mpa", "ball-averaged peak pressure", [](const SoftTissueFePeaks& p, std::size_t) { return p.ball_pressure_mpa; }, 0},
      {"fe_pressure_mpa", "peak pressure", [](const SoftTissueFePeaks& p, std::size_t) { return p.pressure_mpa; }, 0}};
  for (const FeTissue tissue : kFeTissues) {
    measures.push_back({std::string("fe_ball_von_mises_") + to_string(tissue) + "_mpa",
                        std::string("ball-averaged peak von Mises, ") + fe_body_name(tissue),
                        [](const SoftTissueFePeaks& p, std::size_t i) { return p.ball_von_mises_mpa[i]; },
                        static_cast<std::size_t>(tissue)});
  }
  for (const FeTissue tissue : kFeTissues) {
    measures.push_back({std::string("fe_von_mises_") + to_string(tissue) + "_mpa",
                        std::string("peak von Mises, ") + fe_body_name(tissue),
                        [](const SoftTissueFePeaks& p, std::size_t i) { return p.von_mises_mpa[i]; },
                        static_cast<std::size_t>(tissue)});
  }
  return measures;
}

// Within `fraction` of a non-zero generated value (two zeros: the same, both nothing).
bool within(double generated, double synthesised, double fraction) {
  if (generated == 0.0) return synthesised == 0.0;
  return std::abs(synthesised - generated) <= fraction * std::abs(generated);
}

std::string csv_header(const std::vector<PeakMeasure>& measures, bool with_fe) {
  std::ostringstream csv;
  csv << "hip,generated_femoral_cartilage_mm3,synthesised_femoral_cartilage_mm3,generated_acetabular_cartilage_mm3,"
         "synthesised_acetabular_cartilage_mm3,generated_labrum_mm3,synthesised_labrum_mm3,"
         "synthesised_femoral_mean_thickness_mm,synthesised_acetabular_mean_thickness_mm,generated_curvilinear_mm,"
         "synthesised_curvilinear_mm,generated_radial_mm,synthesised_radial_mm,synthesis_seconds";
  if (with_fe) {
    for (const char* which : {"generated_", "synthesised_"}) {
      for (const PeakMeasure& m : measures) csv << ',' << which << m.name;
      csv << ',' << which << "fe_unconverged_steps," << which << "fe_seconds";
    }
  }
  csv << '\n';
  return csv.str();
}

void write_csv_row(std::ostream& csv, const SoftTissueTruthRow& r, const std::vector<PeakMeasure>& measures,
                   bool with_fe) {
  csv << r.hip << ',' << r.generated_femoral_cartilage_mm3 << ',' << r.synthesised_femoral_cartilage_mm3 << ','
      << r.generated_acetabular_cartilage_mm3 << ',' << r.synthesised_acetabular_cartilage_mm3 << ','
      << r.generated_labrum_mm3 << ',' << r.synthesised_labrum_mm3 << ',' << r.synthesised_femoral_mean_thickness_mm
      << ',' << r.synthesised_acetabular_mean_thickness_mm << ',' << r.generated_curvilinear_mm << ','
      << r.synthesised_curvilinear_mm << ',' << r.generated_radial_mm << ',' << r.synthesised_radial_mm << ','
      << r.synthesis_seconds;
  if (with_fe) {
    for (const auto* peaks : {&r.generated_fe, &r.synthesised_fe}) {
      if (!*peaks) {
        csv << std::string(measures.size() + 2, ',');  // not solved (fe_error in the report)
        continue;
      }
      for (const PeakMeasure& m : measures) csv << ',' << m.of(**peaks, m.tissue);
      csv << ',' << (*peaks)->unconverged << ',' << (*peaks)->seconds;
    }
  }
  csv << '\n';
}

// The row of the volumes and depths table.
void write_table_row(std::ostream& table, const SoftTissueTruthRow& r) {
  table << "| " << r.hip << " | " << fixed(r.generated_femoral_cartilage_mm3, 0) << " / "
        << fixed(r.synthesised_femoral_cartilage_mm3, 0) << " | " << fixed(r.generated_acetabular_cartilage_mm3, 0)
        << " / " << fixed(r.synthesised_acetabular_cartilage_mm3, 0) << " | " << fixed(r.generated_labrum_mm3, 0)
        << " / " << fixed(r.synthesised_labrum_mm3, 0) << " | " << fixed(r.generated_curvilinear_mm, 2) << " / "
        << fixed(r.synthesised_curvilinear_mm, 2) << " (" << percent(r.generated_curvilinear_mm, r.synthesised_curvilinear_mm)
        << ") | " << fixed(r.generated_radial_mm, 2) << " / " << fixed(r.synthesised_radial_mm, 2) << " ("
        << percent(r.generated_radial_mm, r.synthesised_radial_mm) << ") |\n";
}

// How often the synthesised tissues give the generated ones' penetration pattern and maxima.
struct DepthAgreement {
  int same_curvilinear = 0, same_radial = 0, within_curvilinear = 0, within_radial = 0, both_c = 0, both_r = 0;

  void add(const SoftTissueTruthRow& r) {
    const bool gc = r.generated_curvilinear_mm > 0.0, sc = r.synthesised_curvilinear_mm > 0.0;
    const bool gr = r.generated_radial_mm > 0.0, sr = r.synthesised_radial_mm > 0.0;
    same_curvilinear += gc == sc;
    same_radial += gr == sr;
    if (gc && sc) {
      ++both_c;
      within_curvilinear += std::abs(r.synthesised_curvilinear_mm - r.generated_curvilinear_mm) <= 0.1 * r.generated_curvilinear_mm;
    }
    if (gr && sr) {
      ++both_r;
      within_radial += std::abs(r.synthesised_radial_mm - r.generated_radial_mm) <= 0.1 * r.generated_radial_mm;
    }
  }
};

// One hip's row of the FE table; counts its measures within 15 % into `held` and returns whether
// all its ball-averaged peaks are.
bool write_fe_row(std::ostream& fe_table, const SoftTissueTruthRow& r, const std::vector<PeakMeasure>& measures,
                  std::vector<int>& held) {
  const SoftTissueFePeaks& g = *r.generated_fe;
  const SoftTissueFePeaks& y = *r.synthesised_fe;
  bool ball = true;
  for (std::size_t m = 0; m < measures.size(); ++m) {
    const bool ok = within(measures[m].of(g, measures[m].tissue), measures[m].of(y, measures[m].tissue), 0.15);
    held[m] += ok;
    if (m == 0 || (m >= 2 && m < 5)) ball = ball && ok;
  }
  fe_table << "| " << r.hip << " | " << g.unconverged << " / " << y.unconverged << " |";
  for (std::size_t m = 0; m < 5; ++m) {
    const double a = measures[m].of(g, measures[m].tissue), b = measures[m].of(y, measures[m].tissue);
    fe_table << ' ' << fixed(a, 3) << " / " << fixed(b, 3) << " (" << percent(a, b) << ") |";
  }
  fe_table << '\n';
  return ball;
}

// FE: per measure, the hips whose synthesised peak is within 15 % of the generated one.
std::string fe_section(const SoftTissueTruthResult& result, const std::vector<PeakMeasure>& measures) {
  const std::size_t n = result.rows.size();
  std::ostringstream fe_section;
  std::ostringstream fe_table;
  fe_table << "| hip | steps not converged (gen / syn) |";
  for (std::size_t k = 0; k < 5; ++k) fe_table << ' ' << measures[k].label << " MPa (gen / syn, Δ %) |";
  fe_table << "\n|---|---|---|---|---|---|---|\n";
  std::vector<int> held(measures.size(), 0);
  int all_ball = 0, unconverged = 0, failed = 0;
  double fe_seconds = 0.0;
  std::string failures;
  for (const auto& r : result.rows) {
    if (!r.generated_fe || !r.synthesised_fe) {
      ++failed;
      failures += "- " + r.hip + ": " + r.fe_error + "\n";
      fe_table << "| " << r.hip << " | FE failed (below) | | | | | |\n";
      continue;
    }
    unconverged += r.generated_fe->unconverged + r.synthesised_fe->unconverged;
    fe_seconds += r.generated_fe->seconds + r.synthesised_fe->seconds;
    all_ball += write_fe_row(fe_table, r, measures, held);
  }
  fe_section << "## FE over standing-to-sitting, level " << to_string(*result.options.fe_level) << "\n\n"
             << "Both tissue sets of every hip through `hipfai fem run` (" << unconverged
             << " steps not converged in all; FE time " << fixed(fe_seconds, 0)
             << " s summed over the runs, from the cache where they were already solved). Peaks over the motion; "
                "the ball-averaged ones (over a 1 mm ball, the FE's own robust peak) first.\n\n"
             << "| FE peak within 15 % (goal: all) | hips |\n|---|---|\n"
             << "| all four ball-averaged peaks (pressure, von Mises of each tissue) | " << all_ball << " of " << n << " |\n";
  for (std::size_t m = 0; m < measures.size(); ++m) {
    fe_section << "| " << measures[m].label << " | " << held[m] << " of " << n << " |\n";
  }
  fe_section << '\n' << fe_table.str() << '\n';
  if (failed > 0) fe_section << failed << " hip(s) without a comparison (counted as not within):\n\n" << failures << '\n';
  return fe_section.str();
}

// The hips a run spread over MPI ranks could not compare (none in a one-process run: a failure
// stops it), each with why.
std::string failed_hips(const SoftTissueTruthResult& result) {
  if (result.failed.empty()) return {};
  std::string text = std::to_string(result.failed.size()) + " hip(s) failed and are left out of every count:\n\n";
  for (const UnitFailure& f : result.failed) text += "- " + f.unit + ": " + f.message + "\n";
  return text + "\n";
}

}  // namespace

std::filesystem::path write_soft_tissue_truth(const SoftTissueTruthResult& result) {
  const double tol = result.contact_tolerance_mm;
  const std::vector<PeakMeasure> measures = fe_measures();
  const bool with_fe = result.options.fe_level.has_value();
  std::ostringstream csv;
  csv << csv_header(measures, with_fe);
  std::ostringstream table;
  table << "| hip | femoral cartilage mm³ (gen / syn) | acetabular cartilage mm³ | labrum mm³ | curvilinear mm (gen / syn, "
           "Δ %) | radial mm (gen / syn, Δ %) |\n|---|---|---|---|---|---|\n";
  DepthAgreement agreement;
  for (const auto& r : result.rows) {
    write_csv_row(csv, r, measures, with_fe);
    write_table_row(table, r);
    agreement.add(r);
  }
  const std::size_t n = result.rows.size();
  const std::string fe = with_fe ? fe_section(result, measures) : std::string();
  std::ostringstream md;
  md << "# Synthesised soft tissue against known truth\n\n"
     << n << " generated hips (" << (result.options.quick ? "quick: 3 mm edges, 10 sub-motions"
                                                          : fixed(result.options.edge_mm, 1) + " mm edges, " +
                                                                std::to_string(result.options.sub_motions) + " sub-motions")
     << "): each stripped to femur_bone and acetabular_bone, cartilage and labrum synthesised from them "
        "(`hipfai soft-tissue --frame model.json`), and the thesis' two penetration depths over standing-to-sitting "
        "computed on the generated and on the synthesised tissues (contact tolerance "
     << fixed(tol, 3) << " mm; a depth counts when above it).\n\n"
     << "| check | result | goal |\n|---|---|---|\n"
     << "| curvilinear penetrate / no-penetrate pattern (thesis Table 8) | " << agreement.same_curvilinear << " of " << n
     << " hips the same | all |\n"
     << "| radial penetrate / no-penetrate pattern | " << agreement.same_radial << " of " << n << " hips the same | all |\n"
     << "| curvilinear maxima within 10 % (hips where both penetrate) | " << agreement.within_curvilinear << " of " << agreement.both_c
     << " | all |\n"
     << "| radial maxima within 10 % (hips where both penetrate) | " << agreement.within_radial << " of " << agreement.both_r << " | all |\n\n"
     << failed_hips(result) << fe << table.str() << "\nWhole study " << fixed(result.seconds, 1) << " s. Per hip: `soft_tissue_truth.csv`; the "
     << "models: `hips/<hip>/generated`, `hips/<hip>/synthesised`.\n";
  write_file_atomically(result.options.out_dir / "soft_tissue_truth.csv", csv.str());
  const auto path = result.options.out_dir / "soft_tissue_truth.md";
  write_file_atomically(path, md.str());
  return path;
}

}  // namespace hipfai::studies
