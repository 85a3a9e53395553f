#include "studies/estimator_refine_report.h"

#include <iomanip>
#include <sstream>

namespace hipfai::studies {

std::string refine_csv(const RefineResult& result) {
  std::ostringstream csv;
  csv << std::setprecision(10) << "hip,score,rank\n";
  for (const RefineCandidate& candidate : result.candidates) {
    csv << candidate.dir.filename().string() << ',' << candidate.score << ',' << candidate.rank << '\n';
  }
  return csv.str();
}

std::string refine_summary(const RefineResult& result, const RefineOptions& options) {
  std::ostringstream text;
  text << "least certain " << result.picked.size() << " of " << result.candidates.size() << " candidates by "
       << stats::to_string(options.criterion);
  if (options.criterion == stats::UncertaintyCriterion::kIntervalWidth) {
    text << " (mean interval width of " << stats::to_string(options.method) << ")";
  } else {
    text << " (mean range of the methods' estimates)";
  }
  text << ":\n" << std::fixed << std::setprecision(4);
  for (std::size_t r = 0; r < result.picked.size(); ++r) {
    const RefineCandidate& candidate = result.candidates[result.picked[r]];
    text << std::setw(4) << r + 1 << "  " << candidate.dir.string() << "  score " << candidate.score << '\n';
  }
  return text.str();
}

}  // namespace hipfai::studies
