#include "studies/estimator_sample_report.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <charconv>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace hipfai::studies {
namespace {

std::string exact(double value) {
  char text[64];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::string(text, end);
}

}  // namespace

std::string design_csv(const SamplePlan& plan) {
  std::ostringstream csv;
  csv << "name,set";
  for (const SampledParameter parameter : plan.vary) csv << ',' << to_string(parameter) << "_deg";
  csv << '\n';
  for (const SampledHip& hip : plan.hips) {
    csv << hip.name << ',' << to_string(hip.set);
    for (const double value : hip.values) csv << ',' << exact(value);
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
