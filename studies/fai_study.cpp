#include "studies/fai_study.h"

#include "contact/radial_mapping.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/stopwatch.h"
#include "studies/fai_report.h"
#include "studies/fai_unit.h"
#include "studies/pipeline/hip_source.h"

#ifdef HIPFAI_WITH_FEM
#include "studies/fai_ranks.h"
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <optional>
#include <tuple>

namespace hipfai::studies {

namespace {

using Clock = SteadyClock;

void normalise(std::vector<FaiModelSummary>& models) {
  double max_c = 0, max_r = 0;
  for (const auto& m : models) max_c = std::max(max_c, m.max_curvilinear_mm), max_r = std::max(max_r, m.max_radial_mm);
  for (auto& m : models) {
    m.normalised_difference = (max_c > 0 ? m.max_curvilinear_mm / max_c : 0.0) -
                              (max_r > 0 ? m.max_radial_mm / max_r : 0.0);
  }
}

// Every unit in this process, one after the other.
std::vector<std::optional<FaiModelRun>> run_units_here(const std::vector<FaiUnit>& units, const Motion& motion,
                                                       const FaiStudyOptions& options) {
  StageLog log;
  ProgressBar progress("fai study: " + std::to_string(units.size()) + " hips", units.size(), options.progress);
  std::vector<std::optional<FaiModelRun>> runs;
  for (const FaiUnit& unit : units) {
    runs.push_back(run_fai_unit(unit, motion, options, log));
    progress.advance();
  }
  return runs;
}

// The grid's models and the resolution table from the units' runs (nullopt: the unit failed and
// is left out, as a hip off the grid).
void gather_models(FaiStudyResult& result, const std::vector<FaiUnit>& units,
                   std::vector<std::optional<FaiModelRun>>& runs, const FaiStudyOptions& options) {
  std::map<std::tuple<double, double, double>, const FaiModelRun*> other_edges;
  for (std::size_t k = 0; k < units.size(); ++k) {
    if (!runs[k]) continue;
    if (units[k].edge_mm == options.edge_mm) {
      result.models.push_back(runs[k]->summary);
      result.runs.emplace(parametric_hip_id(units[k].ce_deg, units[k].alpha_deg), std::move(*runs[k]));
    } else {
      other_edges[{units[k].ce_deg, units[k].alpha_deg, units[k].edge_mm}] = &*runs[k];
    }
  }
  normalise(result.models);
  // Accuracy vs resolution: the archetypes at each edge, coarsest first.
  std::vector<double> edges = options.resolution_edges_mm;
  if (std::find(edges.begin(), edges.end(), options.edge_mm) == edges.end()) edges.push_back(options.edge_mm);
  std::sort(edges.rbegin(), edges.rend());
  for (const double edge : edges) {
    FaiResolutionRow row{edge, 0.0, 0.0, {}, 0};
    double penetration_ms = 0;
    int step_count = 0;
    for (const auto& [name, angles] : fai_archetypes()) {
      if (!find_fai_model(result.models, angles.first, angles.second)) continue;
      const FaiModelRun* used = nullptr;
      if (edge == options.edge_mm) {
        used = &result.runs.at(parametric_hip_id(angles.first, angles.second));
      } else {
        const auto it = other_edges.find({angles.first, angles.second, edge});
        if (it == other_edges.end()) continue;  // its unit failed
        used = it->second;
      }
      row.maxima[name] = {used->summary.max_curvilinear_mm, used->summary.max_radial_mm};
      penetration_ms += used->summary.penetration_ms;
      step_count += static_cast<int>(used->run.steps.size());
      row.femur_vertices = used->hip.tissues.at("femur_bone").num_vertices();
      row.seconds += used->seconds;
    }
    row.penetration_ms_per_step = step_count ? penetration_ms / step_count : 0.0;
    result.resolution.push_back(row);
  }
}

}  // namespace

const FaiModelSummary* find_fai_model(const std::vector<FaiModelSummary>& models, double ce_deg, double alpha_deg) {
  for (const auto& m : models) {
    if (m.ce_deg == ce_deg && m.alpha_deg == alpha_deg) return &m;
  }
  return nullptr;
}

const std::vector<std::pair<std::string, std::pair<double, double>>>& fai_archetypes() {
  static const std::vector<std::pair<std::string, std::pair<double, double>>> archetypes{
      {"normal", {20, 40}}, {"pincer", {40, 40}}, {"cam", {20, 80}}, {"combined cam-pincer", {40, 80}},
      {"dysplasia", {0, 40}}, {"combined dysplasia-impingement", {0, 80}}};
  return archetypes;
}

std::string pathology_of(double ce_deg, double alpha_deg) {
  const bool cam = alpha_deg > 50.0;
  if (ce_deg < 20.0) return cam ? "combined dysplasia-impingement" : "dysplasia";
  if (ce_deg >= 40.0) return cam ? "combined cam-pincer" : "pincer";
  return cam ? "cam" : "normal";
}

std::string curvilinear_band(double d) {
  if (d <= 0.0) return "none";
  if (d < 5) return "very low";
  if (d < 10) return "low";
  if (d < 15) return "intermediate";
  if (d < 20) return "high";
  return "very high";
}

std::string radial_band(double d) {
  if (d <= 0.0) return "none";
  if (d < 2) return "very low";
  if (d < 4) return "low";
  if (d < 6) return "intermediate";
  if (d < 8) return "high";
  return "very high";
}

std::string difference_band(double x) {
  if (x < -0.2) return "very low";
  if (x < 0.0) return "low";
  if (x < 0.2) return "intermediate";
  return "high";
}

FaiStudyResult compute_fai_study(const FaiStudyOptions& options) {
  const auto study_start = Clock::now();
  FaiStudyResult result;
  result.motion = standing_to_sitting(options.sub_motions, options.pose_sequence);
  const std::vector<FaiUnit> units = fai_study_units(options);
  std::vector<std::optional<FaiModelRun>> runs;
#ifdef HIPFAI_WITH_FEM
  if (options.spread == UnitSpread::kMpiRanks && join_mpi_world().size > 1) {
    FaiRankRun ranks = run_fai_units_over_ranks(units, result.motion, options);
    if (!ranks.holds_results) {
      result.holds_results = false;
      return result;
    }
    runs = std::move(ranks.runs);
    result.failed = std::move(ranks.failed);
  } else {
    runs = run_units_here(units, result.motion, options);
  }
#else
  runs = run_units_here(units, result.motion, options);
#endif
  gather_models(result, units, runs, options);
  result.total_seconds = seconds_since(study_start);
  return result;
}

FaiStudyResult run_fai_study(const FaiStudyOptions& options) {
  std::filesystem::create_directories(options.out_dir);
  FaiStudyResult result = compute_fai_study(options);
  // Nothing to write on the ranks other than 0, nor when every hip of a spread study failed.
  if (!result.holds_results || (result.models.empty() && !result.failed.empty())) return result;
  write_fai_study_outputs(result, options);
  return result;
}

}  // namespace hipfai::studies
