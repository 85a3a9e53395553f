#include "studies/estimator_sample.h"

#include "core/error.h"
#include "geometry/hip_model.h"
#include "studies/estimator_sample_report.h"
#include "tests/core/scratch_folder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace hipfai::studies {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Each range ends where the generator's checks or the published range end: both ends are accepted,
// and where the end is the generator's own limit, a step beyond it is refused.
TEST(EstimatorSample, RangesAreInsideTheGeneratorsChecks) {
  for (const SampledParameter parameter : kSampledParameters) {
    SCOPED_TRACE(to_string(parameter));
    const stats::ParameterRange range = sampled_range(parameter);
    EXPECT_LT(range.low, range.high);
    for (const double value : {range.low, range.high}) {
      EXPECT_NO_THROW(geometry::validate_hip_parameters(with_sampled_value({}, parameter, value)));
    }
  }
  const auto refused = [](SampledParameter parameter, double value) {
    EXPECT_THROW(geometry::validate_hip_parameters(with_sampled_value({}, parameter, value)), Error)
        << to_string(parameter) << ' ' << value;
  };
  refused(SampledParameter::kCe, sampled_range(SampledParameter::kCe).high + 0.01);
  refused(SampledParameter::kCe, sampled_range(SampledParameter::kCe).low - 0.01);
  refused(SampledParameter::kNeckShaftAngle, sampled_range(SampledParameter::kNeckShaftAngle).low - 0.01);
  refused(SampledParameter::kFemoralAnteversion, sampled_range(SampledParameter::kFemoralAnteversion).low - 0.01);
  refused(SampledParameter::kFemoralAnteversion, sampled_range(SampledParameter::kFemoralAnteversion).high + 0.01);
}

TEST(EstimatorSample, PlanHasDisjointTrainingAndHeldOutHipsInsideTheRanges) {
  for (const stats::SamplingDesign design : stats::kSamplingDesigns) {
    SampleOptions options;
    options.n = 20;
    options.held_out = 10;
    options.seed = 4;
    options.design = design;
    options.vary = {SampledParameter::kCe, SampledParameter::kAlpha, SampledParameter::kFemoralAnteversion};
    const SamplePlan plan = plan_sample(options);
    ASSERT_EQ(plan.hips.size(), 30u);
    std::set<std::vector<double>> train;
    std::set<std::string> names;
    for (std::size_t h = 0; h < plan.hips.size(); ++h) {
      const SampledHip& hip = plan.hips[h];
      EXPECT_EQ(hip.set, h < 20 ? SampleSet::kTrain : SampleSet::kHeldOut);
      EXPECT_TRUE(names.insert(hip.name).second) << hip.name;
      ASSERT_EQ(hip.values.size(), 3u);
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_GE(hip.values[k], sampled_range(options.vary[k]).low);
        EXPECT_LE(hip.values[k], sampled_range(options.vary[k]).high);
      }
      EXPECT_EQ(hip.parameters.ce_deg, hip.values[0]);
      EXPECT_EQ(hip.parameters.alpha_deg, hip.values[1]);
      EXPECT_EQ(hip.parameters.femoral_anteversion_deg, hip.values[2]);
      EXPECT_EQ(hip.parameters.neck_shaft_angle_deg, geometry::HipParameters{}.neck_shaft_angle_deg);
      if (hip.set == SampleSet::kTrain) {
        train.insert(hip.values);
      } else {
        EXPECT_EQ(train.count(hip.values), 0u) << hip.name << " is a training hip";
      }
    }
    EXPECT_EQ(plan.hips.front().name, "train_001");
    EXPECT_EQ(plan.hips.back().name, "held_out_010");
  }
}

TEST(EstimatorSample, BadOptionsAreOneLineErrors) {
  SampleOptions options;
  options.n = 0;
  EXPECT_THROW(plan_sample(options), Error);
  options.n = 2;
  options.held_out = -1;
  EXPECT_THROW(plan_sample(options), Error);
  options.held_out = 0;
  options.vary = {SampledParameter::kCe, SampledParameter::kCe};
  EXPECT_THROW(plan_sample(options), Error);
  options.vary.clear();
  EXPECT_THROW(plan_sample(options), Error);
  try {
    parse_sampled_parameter("labrum_height");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "unknown parameter 'labrum_height' to vary (known: ce, alpha, neck_shaft_angle, femoral_anteversion)");
  }
}

// A tiny run at a coarse edge: 3 training and 2 held-out hips, design.csv as stated, every hip a
// complete model folder with the design's values; a re-run skips all of them, and a hip whose
// model.json is missing (an interrupted hand copy) is the only one made again.
TEST(EstimatorSample, TinyRunMakesFiveHipsAndARerunSkipsThem) {
  const fs::path out = fs::path(HIPFAI_BINARY_DIR) / "test-scratch" / "estimator_sample_tiny";
  fs::remove_all(out);
  SampleOptions options;
  options.n = 3;
  options.held_out = 2;
  options.seed = 12;
  options.edge_mm = 7.0;
  const SamplePlan plan = plan_sample(options);
  write_design_csv(plan, out);
  std::vector<std::size_t> reported;
  const auto first = generate_sample_hips(plan, out, [&](std::size_t index, const SampleHipOutcome&) {
    reported.push_back(index);
  });
  EXPECT_EQ(reported, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  for (std::size_t h = 0; h < plan.hips.size(); ++h) {
    EXPECT_EQ(first[h].status, SampleHipOutcome::Status::kGenerated) << sample_hip_line(plan, h, first[h]);
  }

  const auto lines = lines_of(test::file_contents(out / "design.csv"));
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0], "name,set,ce_deg,alpha_deg");
  std::set<std::string> train_values, held_out_values;
  for (std::size_t h = 0; h < 5; ++h) {
    const SampledHip& hip = plan.hips[h];
    const std::string prefix = hip.name + ',' + (h < 3 ? "train," : "held_out,");
    EXPECT_EQ(lines[h + 1].rfind(prefix, 0), 0u) << lines[h + 1];
    const std::string values = lines[h + 1].substr(prefix.size());
    (h < 3 ? train_values : held_out_values).insert(values);
    // The values written are the generator's parameters, exactly.
    const geometry::HipModel model = geometry::load_hip_model(out / hip.name);
    EXPECT_EQ(std::stod(values.substr(0, values.find(','))), model.parameters.ce_deg);
    EXPECT_EQ(std::stod(values.substr(values.find(',') + 1)), model.parameters.alpha_deg);
    EXPECT_EQ(model.parameters.edge_mm, 7.0);
  }
  for (const auto& values : held_out_values) EXPECT_EQ(train_values.count(values), 0u) << values;
  int folders = 0;
  for (const auto& entry : fs::directory_iterator(out)) folders += entry.is_directory();
  EXPECT_EQ(folders, 5) << "one folder per hip, no temporary folder left";

  write_design_csv(plan, out);  // the same design again: accepted
  const auto again = generate_sample_hips(plan, out);
  for (const auto& outcome : again) EXPECT_EQ(outcome.status, SampleHipOutcome::Status::kSkipped);

  fs::remove(out / plan.hips[3].name / "model.json");
  const auto repaired = generate_sample_hips(plan, out);
  for (std::size_t h = 0; h < 5; ++h) {
    EXPECT_EQ(repaired[h].status, h == 3 ? SampleHipOutcome::Status::kGenerated : SampleHipOutcome::Status::kSkipped);
  }
  EXPECT_TRUE(sample_hip_complete(out / plan.hips[3].name));

  SampleOptions other = options;
  other.seed = 13;
  EXPECT_THROW(write_design_csv(plan_sample(other), out), Error);
  fs::remove_all(out);
}

}  // namespace
}  // namespace hipfai::studies
