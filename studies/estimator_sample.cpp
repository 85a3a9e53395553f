#include "studies/estimator_sample.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/literature.h"
#include "geometry/hip_generator.h"
#include "geometry/hip_model.h"

#include <algorithm>
#include <chrono>

namespace hipfai::studies {
namespace {

// The generator's limits where they cut a published range (geometry/hip_parameters.cpp's field
// table; tests/studies/estimator_sample_test.cpp checks them against validate_hip_parameters).
constexpr double kGeneratorCeMaxDeg = 45.0;
constexpr double kGeneratorNeckShaftMinDeg = 110.0;
constexpr double kGeneratorNeckShaftMaxDeg = 150.0;
constexpr double kGeneratorFemoralVersionMinDeg = -10.0;
constexpr double kGeneratorFemoralVersionMaxDeg = 40.0;

std::string hip_name(SampleSet set, int index, int count) {
  const std::size_t width = std::max<std::size_t>(3, std::to_string(count).size());
  std::string digits = std::to_string(index + 1);
  digits.insert(0, width - std::min(width, digits.size()), '0');
  return std::string(to_string(set)) + '_' + digits;
}

void add_hips(SamplePlan& plan, const stats::SamplingResult& design, SampleSet set, double edge_mm) {
  const int count = static_cast<int>(design.points.rows());
  for (int i = 0; i < count; ++i) {
    SampledHip hip;
    hip.name = hip_name(set, i, count);
    hip.set = set;
    hip.parameters.edge_mm = edge_mm;
    for (std::size_t k = 0; k < plan.vary.size(); ++k) {
      const double value = design.points(i, static_cast<Eigen::Index>(k));
      hip.values.push_back(value);
      hip.parameters = with_sampled_value(hip.parameters, plan.vary[k], value);
    }
    plan.hips.push_back(std::move(hip));
  }
}

}  // namespace

const char* to_string(SampledParameter parameter) {
  switch (parameter) {
    case SampledParameter::kCe: return "ce";
    case SampledParameter::kAlpha: return "alpha";
    case SampledParameter::kNeckShaftAngle: return "neck_shaft_angle";
    case SampledParameter::kFemoralAnteversion: return "femoral_anteversion";
  }
  return "?";
}

SampledParameter parse_sampled_parameter(const std::string& name) {
  std::string known;
  for (const SampledParameter parameter : kSampledParameters) {
    if (name == to_string(parameter)) return parameter;
    known += (known.empty() ? "" : ", ") + std::string(to_string(parameter));
  }
  throw_error("unknown parameter '", name, "' to vary (known: ", known, ")");
}

stats::ParameterRange sampled_range(SampledParameter parameter) {
  switch (parameter) {
    case SampledParameter::kCe: return {literature::kStudyCeMinDeg, kGeneratorCeMaxDeg};
    case SampledParameter::kAlpha: return {literature::kStudyAlphaMinDeg, literature::kStudyAlphaMaxDeg};
    case SampledParameter::kNeckShaftAngle:
      return {std::max(literature::kAdultNeckShaftAngleMinDeg, kGeneratorNeckShaftMinDeg),
              std::min(literature::kAdultNeckShaftAngleMaxDeg, kGeneratorNeckShaftMaxDeg)};
    case SampledParameter::kFemoralAnteversion:
      return {std::max(literature::kAdultFemoralVersionMinDeg, kGeneratorFemoralVersionMinDeg),
              std::min(literature::kAdultFemoralVersionMaxDeg, kGeneratorFemoralVersionMaxDeg)};
  }
  throw_error("sampled_range: unknown parameter");
}

geometry::HipParameters with_sampled_value(geometry::HipParameters base, SampledParameter parameter, double value) {
  switch (parameter) {
    case SampledParameter::kCe: base.ce_deg = value; break;
    case SampledParameter::kAlpha: base.alpha_deg = value; break;
    case SampledParameter::kNeckShaftAngle: base.neck_shaft_angle_deg = value; break;
    case SampledParameter::kFemoralAnteversion: base.femoral_anteversion_deg = value; break;
  }
  return base;
}

const char* to_string(SampleSet set) { return set == SampleSet::kTrain ? "train" : "held_out"; }

SamplePlan plan_sample(const SampleOptions& options) {
  if (options.n < 1) throw_error("estimator sample: --n ", options.n, " must be at least 1");
  if (options.held_out < 0) throw_error("estimator sample: --held-out ", options.held_out, " must be 0 or more");
  if (options.vary.empty()) throw_error("estimator sample: no parameter to vary");
  for (std::size_t k = 0; k < options.vary.size(); ++k) {
    if (std::count(options.vary.begin(), options.vary.end(), options.vary[k]) > 1) {
      throw_error("estimator sample: parameter '", to_string(options.vary[k]), "' named twice in --vary");
    }
  }
  SamplePlan plan;
  plan.vary = options.vary;
  stats::SamplingRequest request;
  request.design = options.design;
  request.seed = options.seed;
  for (const SampledParameter parameter : options.vary) request.ranges.push_back(sampled_range(parameter));
  request.n = options.n;
  request.stream = 0;
  const stats::SamplingResult train = stats::draw_design(request);
  add_hips(plan, train, SampleSet::kTrain, options.edge_mm);
  if (options.held_out > 0) {
    request.n = options.held_out;
    request.stream = 1;
    const stats::SamplingResult held_out = stats::draw_design(request);
    for (Eigen::Index i = 0; i < held_out.points.rows(); ++i) {
      for (Eigen::Index j = 0; j < train.points.rows(); ++j) {
        if (held_out.points.row(i) == train.points.row(j)) {
          throw_error("estimator sample: held-out hip ", i + 1, " equals training hip ", j + 1,
                      "; draw again with another --seed");
        }
      }
    }
    add_hips(plan, held_out, SampleSet::kHeldOut, options.edge_mm);
  }
  for (const SampledHip& hip : plan.hips) geometry::validate_hip_parameters(hip.parameters, hip.name);
  return plan;
}

bool sample_hip_complete(const std::filesystem::path& hip_dir) {
  std::error_code ec;
  return std::filesystem::is_regular_file(hip_dir / "model.json", ec);
}

SampleHipOutcome generate_sample_hip(const SamplePlan& plan, std::size_t index, const std::filesystem::path& out_dir) {
  const SampledHip& hip = plan.hips.at(index);
  const std::filesystem::path target = out_dir / hip.name;
  SampleHipOutcome outcome;
  if (sample_hip_complete(target)) {
    outcome.status = SampleHipOutcome::Status::kSkipped;
    return outcome;
  }
  const auto start = std::chrono::steady_clock::now();
  try {
    std::filesystem::create_directories(out_dir);
    const geometry::HipGeneratorResult generated = geometry::generate_hip(hip.parameters);
    AtomicDirectory staging(target);
    geometry::write_hip_model(generated.model, staging.partial_path(), "ply");
    staging.commit(sample_hip_complete);
    outcome.status = SampleHipOutcome::Status::kGenerated;
  } catch (const std::exception& error) {
    outcome.status = SampleHipOutcome::Status::kFailed;
    outcome.error = error.what();
  }
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return outcome;
}

std::vector<SampleHipOutcome> generate_sample_hips(
    const SamplePlan& plan, const std::filesystem::path& out_dir,
    const std::function<void(std::size_t index, const SampleHipOutcome&)>& on_hip) {
  std::filesystem::create_directories(out_dir);
  std::vector<SampleHipOutcome> outcomes;
  for (std::size_t h = 0; h < plan.hips.size(); ++h) {
    outcomes.push_back(generate_sample_hip(plan, h, out_dir));
    if (on_hip) on_hip(h, outcomes.back());
  }
  return outcomes;
}

}  // namespace hipfai::studies
