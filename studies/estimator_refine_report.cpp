#include "studies/estimator_refine_report.h"

#include <iomanip>
#include <sstream>

#include <cmath>

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

std::string refine_rounds_csv(const RefineLoopResult& result) {
  std::ostringstream csv;
  csv << "round,training_hips,added,failed,fe_s,seconds";
  for (const stats::EstimatorMethod method : stats::kEstimatorMethods) {
    csv << ",held_out_" << stats::to_string(method) << "_case1,held_out_" << stats::to_string(method) << "_case2";
  }
  csv << '\n';
  for (const RefineRound& round : result.rounds) {
    std::string added;
    for (const auto& dir : round.added) {
      if (!added.empty()) added += ';';
      added += dir.filename().string();
    }
    csv << round.round << ',' << round.training_hips << ',' << added << ',' << round.failed.size() << ','
        << std::setprecision(6) << round.fe_seconds << ',' << round.seconds;
    for (const auto& method : round.held_out_error) {
      for (const double error : method) csv << ',' << (std::isfinite(error) ? std::to_string(error) : std::string());
    }
    csv << '\n';
  }
  return csv.str();
}

std::string refine_rounds_summary(const RefineLoopResult& result) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(2);
  int before = 0;
  for (const RefineRound& round : result.rounds) {
    text << "round " << round.round << ": " << round.training_hips << " hips";
    if (round.round > 0) text << " (+" << round.training_hips - before << ")";
    if (result.held_out_hips > 0) {
      text << ", held-out error (" << result.held_out_hips << " hips) case 1 / case 2:";
      for (std::size_t m = 0; m < round.held_out_error.size(); ++m) {
        text << ' ' << stats::to_string(stats::kEstimatorMethods[m]) << ' ' << round.held_out_error[m][0] << " / "
             << round.held_out_error[m][1] << " %" << (m + 1 < round.held_out_error.size() ? "," : "");
      }
    }
    text << '\n';
    for (const auto& failed : round.failed) text << "  FE failed: " << failed << '\n';
    before = round.training_hips;
  }
  return text.str();
}

}  // namespace hipfai::studies
