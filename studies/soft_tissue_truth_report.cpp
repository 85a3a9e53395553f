// hipfai — the tables of the soft-tissue known-truth study (see soft_tissue_truth_report.h).
#include "studies/soft_tissue_truth_report.h"

#include "core/atomic_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace hipfai::studies {
namespace {

std::string fixed(double value, int digits) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

// Relative difference in %, or "-" when both are zero.
std::string percent(double generated, double synthesised) {
  if (generated == 0.0 && synthesised == 0.0) return "-";
  if (generated == 0.0) return "new";
  return fixed(100.0 * (synthesised - generated) / generated, 1);
}

}  // namespace

std::filesystem::path write_soft_tissue_truth(const SoftTissueTruthResult& result) {
  const double tol = result.contact_tolerance_mm;
  std::ostringstream csv;
  csv << "hip,generated_femoral_cartilage_mm3,synthesised_femoral_cartilage_mm3,generated_acetabular_cartilage_mm3,"
         "synthesised_acetabular_cartilage_mm3,generated_labrum_mm3,synthesised_labrum_mm3,"
         "synthesised_femoral_mean_thickness_mm,synthesised_acetabular_mean_thickness_mm,generated_curvilinear_mm,"
         "synthesised_curvilinear_mm,generated_radial_mm,synthesised_radial_mm,synthesis_seconds\n";
  std::ostringstream table;
  table << "| hip | femoral cartilage mm³ (gen / syn) | acetabular cartilage mm³ | labrum mm³ | curvilinear mm (gen / syn, "
           "Δ %) | radial mm (gen / syn, Δ %) |\n|---|---|---|---|---|---|\n";
  int same_curvilinear = 0, same_radial = 0, within_curvilinear = 0, within_radial = 0, both_c = 0, both_r = 0;
  for (const auto& r : result.rows) {
    csv << r.hip << ',' << r.generated_femoral_cartilage_mm3 << ',' << r.synthesised_femoral_cartilage_mm3 << ','
        << r.generated_acetabular_cartilage_mm3 << ',' << r.synthesised_acetabular_cartilage_mm3 << ','
        << r.generated_labrum_mm3 << ',' << r.synthesised_labrum_mm3 << ',' << r.synthesised_femoral_mean_thickness_mm
        << ',' << r.synthesised_acetabular_mean_thickness_mm << ',' << r.generated_curvilinear_mm << ','
        << r.synthesised_curvilinear_mm << ',' << r.generated_radial_mm << ',' << r.synthesised_radial_mm << ','
        << r.synthesis_seconds << '\n';
    table << "| " << r.hip << " | " << fixed(r.generated_femoral_cartilage_mm3, 0) << " / "
          << fixed(r.synthesised_femoral_cartilage_mm3, 0) << " | " << fixed(r.generated_acetabular_cartilage_mm3, 0)
          << " / " << fixed(r.synthesised_acetabular_cartilage_mm3, 0) << " | " << fixed(r.generated_labrum_mm3, 0)
          << " / " << fixed(r.synthesised_labrum_mm3, 0) << " | " << fixed(r.generated_curvilinear_mm, 2) << " / "
          << fixed(r.synthesised_curvilinear_mm, 2) << " (" << percent(r.generated_curvilinear_mm, r.synthesised_curvilinear_mm)
          << ") | " << fixed(r.generated_radial_mm, 2) << " / " << fixed(r.synthesised_radial_mm, 2) << " ("
          << percent(r.generated_radial_mm, r.synthesised_radial_mm) << ") |\n";
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
  const std::size_t n = result.rows.size();
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
     << "| curvilinear penetrate / no-penetrate pattern (thesis Table 8) | " << same_curvilinear << " of " << n
     << " hips the same | all |\n"
     << "| radial penetrate / no-penetrate pattern | " << same_radial << " of " << n << " hips the same | all |\n"
     << "| curvilinear maxima within 10 % (hips where both penetrate) | " << within_curvilinear << " of " << both_c
     << " | all |\n"
     << "| radial maxima within 10 % (hips where both penetrate) | " << within_radial << " of " << both_r << " | all |\n\n"
     << table.str() << "\nWhole study " << fixed(result.seconds, 1) << " s. Per hip: `soft_tissue_truth.csv`; the "
     << "models: `hips/<hip>/generated`, `hips/<hip>/synthesised`.\n";
  write_file_atomically(result.options.out_dir / "soft_tissue_truth.csv", csv.str());
  const auto path = result.options.out_dir / "soft_tissue_truth.md";
  write_file_atomically(path, md.str());
  return path;
}

}  // namespace hipfai::studies
