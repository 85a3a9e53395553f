// hipfai — the tables of the assessment's known-truth study (see assessment_truth_report.h).
#include "studies/assessment_truth_report.h"

#include "core/atomic_file.h"
#include "core/text_format.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace hipfai::studies {

std::filesystem::path write_assessment_truth(const AssessmentTruthResult& result) {
  std::ostringstream csv;
  csv << "hip,model_ce_deg,measured_ce_deg,model_alpha_deg,bone_alpha_reference_deg,measured_alpha_deg,"
         "measured_alpha_max_deg,acetabular_inclination_deg,acetabular_version_deg,fadir_internal_rotation_deg,"
         "moved_measure_diff_deg,moved_rom_diff_deg,mirrored_measure_diff_deg,mirrored_rom_diff_deg,"
         "mirrored_side_left,assess_seconds\n";
  double worst_ce = 0.0, worst_alpha_model = 0.0, worst_alpha_bone = 0.0, worst_measure = 0.0, worst_rom = 0.0;
  int left = 0;
  double seconds = 0.0;
  for (const auto& r : result.rows) {
    csv << r.hip << ',' << r.model_ce_deg << ',' << r.measured_ce_deg << ',' << r.model_alpha_deg << ','
        << r.bone_alpha_reference_deg << ',' << r.measured_alpha_deg << ',' << r.measured_alpha_max_deg << ','
        << r.acetabular_inclination_deg << ',' << r.acetabular_version_deg << ',' << r.fadir_internal_rotation_deg << ','
        << r.moved_measure_diff_deg << ',' << r.moved_rom_diff_deg << ',' << r.mirrored_measure_diff_deg << ','
        << r.mirrored_rom_diff_deg << ',' << (r.mirrored_side_left ? 1 : 0) << ',' << r.assess_seconds << '\n';
    worst_ce = std::max(worst_ce, std::abs(r.measured_ce_deg - r.model_ce_deg));
    worst_alpha_model = std::max(worst_alpha_model, std::abs(r.measured_alpha_deg - r.model_alpha_deg));
    worst_alpha_bone = std::max(worst_alpha_bone, std::abs(r.measured_alpha_deg - r.bone_alpha_reference_deg));
    worst_measure = std::max({worst_measure, r.moved_measure_diff_deg, r.mirrored_measure_diff_deg});
    worst_rom = std::max({worst_rom, r.moved_rom_diff_deg, r.mirrored_rom_diff_deg});
    left += r.mirrored_side_left ? 1 : 0;
    seconds += r.assess_seconds;
  }
  const std::size_t n = result.rows.size();
  std::ostringstream md;
  md << "# The assessment against known truth\n\n"
     << n << " generated hips (" << (result.options.quick ? "quick: 3 mm edges" : fixed(result.options.edge_mm, 1) + " mm edges")
     << "), bones only (femur_bone, acetabular_bone), frame = their model.json (`hipfai assess --frame model.json`); "
        "each again moved by a random rigid transform, and again mirrored into a left hip and moved (seed "
     << result.options.seed << ").\n\n"
     << "| check | largest difference | goal |\n|---|---|---|\n"
     << "| lateral CE vs the generator's | " << fixed(worst_ce, 3) << "° | 1° |\n"
     << "| alpha (Nötzli) vs the generator's method on the bone alone | " << fixed(worst_alpha_bone, 3) << "° | 1° |\n"
     << "| alpha (Nötzli) on the bone vs the generator's on bone + cartilage | " << fixed(worst_alpha_model, 3)
     << "° | (not the same surface: see below) |\n"
     << "| measures, moved or mirrored vs original | " << fixed(worst_measure, 4) << "° | 0.1° |\n"
     << "| ten clinical ranges of motion, moved or mirrored vs original | " << fixed(worst_rom, 4) << "° | 0.01° |\n"
     << "| mirrored hips found left | " << left << " of " << n << " | all |\n\n"
     << "The generator measures alpha on its articular surface (bone and cartilage); on the bone alone the contour "
        "leaves the bone's own sphere at a different angle (the cartilage thins to nothing at its edge), so the "
        "bones-only reference is the generator's measurement method applied to the bone. Mean time per assessment "
     << fixed(n ? seconds / n : 0.0, 2) << " s; whole study " << fixed(result.seconds, 1) << " s. Per hip: `known_truth.csv`.\n";
  write_file_atomically(result.options.out_dir / "known_truth.csv", csv.str());
  const auto path = result.options.out_dir / "known_truth.md";
  write_file_atomically(path, md.str());
  return path;
}

}  // namespace hipfai::studies
