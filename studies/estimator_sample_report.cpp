#include "studies/estimator_sample_report.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text_format.h"
#include "studies/validation_study.h"

#include <algorithm>
#include <cmath>

#include <charconv>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace hipfai::studies {
namespace {

std::string cell(double value) { return std::isfinite(value) ? shortest(value) : std::string(); }

std::string step_table(const SamplePlan& plan, const SampleFeResult& result, SampleSet set) {
  std::ostringstream csv;
  // CE and alpha have their own columns (always present); the other varied parameters go in front.
  const auto own_column = [](SampledParameter p) { return p == SampledParameter::kCe || p == SampledParameter::kAlpha; };
  csv << "hip,set";
  for (const SampledParameter parameter : plan.vary) {
    if (!own_column(parameter)) csv << ',' << to_string(parameter) << "_deg";
  }
  csv << ",ce_deg,alpha_deg,step,angle_deg,max_curvilinear_mm,max_radial_mm";
  for (const FeMeasure& measure : validation_fe_measures()) csv << ',' << fe_measure_name(measure);
  csv << '\n';
  for (const SampleFeHip& run : result.hips) {
    const SampledHip& hip = plan.hips.at(run.plan_index);
    if (hip.set != set || !run.error.empty()) continue;
    for (std::size_t k = 0; k < result.motion.steps.size(); ++k) {
      csv << hip.name << ',' << to_string(hip.set);
      for (std::size_t p = 0; p < plan.vary.size(); ++p) {
        if (!own_column(plan.vary[p])) csv << ',' << shortest(hip.values[p]);
      }
      csv << ',' << shortest(hip.parameters.ce_deg) << ',' << shortest(hip.parameters.alpha_deg) << ',' << k + 1 << ','
          << shortest(result.motion.steps[k].angle_deg) << ',' << cell(run.curvilinear_max_mm.at(k)) << ','
          << cell(run.radial_max_mm.at(k));
      for (const auto& measure : run.fe) csv << ',' << cell(measure.at(k));
      csv << '\n';
    }
  }
  return csv.str();
}

}  // namespace

void write_sample_fe_tables(const SamplePlan& plan, const SampleFeResult& result, FeLevel level,
                            const std::filesystem::path& out_dir) {
  write_file_atomically(out_dir / "steps.csv", step_table(plan, result, SampleSet::kTrain));
  write_file_atomically(out_dir / "held_out_steps.csv", step_table(plan, result, SampleSet::kHeldOut));
  std::ostringstream csv;
  csv << "hip,set,ce_deg,alpha_deg,edge_mm,steps,fe_level,penetration_ms,fe_s,fe_reused,fe_steps_failed,error\n";
  for (const SampleFeHip& run : result.hips) {
    const SampledHip& hip = plan.hips.at(run.plan_index);
    std::string error = run.error;
    std::replace(error.begin(), error.end(), ',', ';');
    std::replace(error.begin(), error.end(), '\n', ' ');
    csv << hip.name << ',' << to_string(hip.set) << ',' << shortest(hip.parameters.ce_deg) << ','
        << shortest(hip.parameters.alpha_deg) << ',' << shortest(hip.parameters.edge_mm) << ','
        << result.motion.steps.size() << ',' << to_string(level) << ',' << cell(run.penetration_ms) << ','
        << cell(run.fe_s) << ',' << (run.fe_reused ? 1 : 0) << ',' << run.fe_steps_failed << ',' << error << '\n';
  }
  write_file_atomically(out_dir / "timings.csv", csv.str());
}

std::string sample_fe_summary(const SamplePlan& plan, const SampleFeResult& result, const std::filesystem::path& out_dir) {
  int train = 0, failed = 0;
  for (const SampleFeHip& run : result.hips) {
    train += plan.hips.at(run.plan_index).set == SampleSet::kTrain;
    failed += !run.error.empty();
  }
  std::ostringstream text;
  text << result.hips.size() << " hips with FE (" << train << " train, " << result.hips.size() - train
       << " held_out), " << failed << " failed, " << result.missing << " not generated; " << std::fixed
       << std::setprecision(0) << result.seconds << " s; tables in " << out_dir.string();
  return text.str();
}

std::string design_csv(const SamplePlan& plan) {
  std::ostringstream csv;
  csv << "name,set";
  for (const SampledParameter parameter : plan.vary) csv << ',' << to_string(parameter) << "_deg";
  csv << '\n';
  for (const SampledHip& hip : plan.hips) {
    csv << hip.name << ',' << to_string(hip.set);
    for (const double value : hip.values) csv << ',' << shortest(value);
    csv << '\n';
  }
  return csv.str();
}

void write_design_csv(const SamplePlan& plan, const std::filesystem::path& out_dir) {
  const std::filesystem::path path = out_dir / "design.csv";
  const std::string text = design_csv(plan);
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream old;
    old << in.rdbuf();
    if (old.str() == text) return;
    throw_error(path.string(), ": holds another design (other --n, --held-out, --seed, --design or --vary); "
                               "use another --out or remove the folder");
  }
  std::filesystem::create_directories(out_dir);
  write_file_atomically(path, text);
}

std::string sample_hip_line(const SamplePlan& plan, std::size_t index, const SampleHipOutcome& outcome) {
  const SampledHip& hip = plan.hips.at(index);
  std::ostringstream line;
  line << '[' << index + 1 << '/' << plan.hips.size() << "] " << hip.name << std::setprecision(6);
  for (std::size_t k = 0; k < plan.vary.size(); ++k) line << ' ' << to_string(plan.vary[k]) << ' ' << hip.values[k];
  switch (outcome.status) {
    case SampleHipOutcome::Status::kGenerated:
      line << ": generated in " << std::fixed << std::setprecision(1) << outcome.seconds << " s";
      break;
    case SampleHipOutcome::Status::kSkipped: line << ": complete, skipped"; break;
    case SampleHipOutcome::Status::kFailed: line << ": FAILED: " << outcome.error; break;
  }
  return line.str();
}

std::string sample_summary(const SamplePlan& plan, const std::vector<SampleHipOutcome>& outcomes,
                           const std::filesystem::path& out_dir) {
  int train = 0, generated = 0, skipped = 0, failed = 0;
  for (const SampledHip& hip : plan.hips) train += hip.set == SampleSet::kTrain;
  for (const SampleHipOutcome& outcome : outcomes) {
    generated += outcome.status == SampleHipOutcome::Status::kGenerated;
    skipped += outcome.status == SampleHipOutcome::Status::kSkipped;
    failed += outcome.status == SampleHipOutcome::Status::kFailed;
  }
  std::ostringstream text;
  text << plan.hips.size() << " hips (" << train << " train, " << plan.hips.size() - train << " held_out): "
       << generated << " generated, " << skipped << " skipped, " << failed << " failed; design: "
       << (out_dir / "design.csv").string();
  return text.str();
}

}  // namespace hipfai::studies
