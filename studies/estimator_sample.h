// hipfai — a training set for the pressure estimator spread over the hips' parameter space: N
// training hips and M held-out hips placed by a space-filling design (stats/space_filling_design.h)
// and generated with the parametric hip generator, one model folder per hip.
//
// The parameters that can be varied, with their ranges:
//   ce                   lateral CE, 0-45 deg: the study's lower end (literature::kStudyCeMinDeg) to
//                        the generator's upper limit (geometry/hip_parameters.cpp; the grid's 40 is
//                        not the end of the clinical range: > 39 deg is over-coverage).
//   alpha                alpha of Nötzli, 40-80 deg: the study's range (literature::kStudyAlpha*).
//   neck_shaft_angle     CCD, 110-146.2 deg: the adult range of Hartel et al. 2016
//                        (literature::kAdultNeckShaftAngle*, 100.1-146.2) within what the generator
//                        accepts (110-150).
//   femoral_anteversion  -10-40 deg: Hartel et al. 2016's adult range (-23.6-48.7) within what the
//                        generator accepts (-10-40).
// The sensitivity study (docs/hip-sensitivity) also found acetabular anteversion, the socket's
// hemisphere CE, the cam's arc and the labrum's height to move first contact; core/literature.h
// holds no published range for them, so they are not offered. Every other generator parameter
// keeps its default.
//
// The training set is the design's stream 0, the held-out set stream 1 of the same seed (an
// independent draw of the same design); no held-out point equals a training point (checked).
// Hips are named train_001.., held_out_001..; a hip is complete when its folder holds model.json,
// and is written under a temporary name and renamed (core/atomic_file.h), so a killed run leaves
// only whole hips and a re-run makes only the missing ones.
#pragma once

#include "geometry/hip_parameters.h"
#include "stats/space_filling_design.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace hipfai::studies {

enum class SampledParameter { kCe, kAlpha, kNeckShaftAngle, kFemoralAnteversion };
inline constexpr std::array<SampledParameter, 4> kSampledParameters{
    SampledParameter::kCe, SampledParameter::kAlpha, SampledParameter::kNeckShaftAngle,
    SampledParameter::kFemoralAnteversion};
// "ce", "alpha", "neck_shaft_angle", "femoral_anteversion".
const char* to_string(SampledParameter parameter);
// Throws hipfai::Error "unknown parameter 'x' to vary (known: ce, alpha, ...)".
SampledParameter parse_sampled_parameter(const std::string& name);
// The range of the header comment, in the parameter's unit (deg).
stats::ParameterRange sampled_range(SampledParameter parameter);
// `base` with `parameter` set to `value`.
geometry::HipParameters with_sampled_value(geometry::HipParameters base, SampledParameter parameter, double value);

enum class SampleSet { kTrain, kHeldOut };
// "train", "held_out".
const char* to_string(SampleSet set);

struct SampleOptions {
  int n = 0;         // training hips, >= 1
  int held_out = 0;  // held-out hips, >= 0
  std::uint64_t seed = 1;
  stats::SamplingDesign design = stats::SamplingDesign::kLatinHypercube;
  std::vector<SampledParameter> vary{SampledParameter::kCe, SampledParameter::kAlpha};
  double edge_mm = 2.0;  // surface edge of the generated hips (study validate's default)
};

struct SampledHip {
  std::string name;            // folder name: train_001, held_out_001, ...
  SampleSet set = SampleSet::kTrain;
  std::vector<double> values;  // one per varied parameter, in SampleOptions::vary's order
  geometry::HipParameters parameters;
};

struct SamplePlan {
  std::vector<SampledParameter> vary;
  std::vector<SampledHip> hips;  // training hips first, then the held-out ones
};

// The hips of a sample, without generating anything. Throws hipfai::Error on n < 1, held_out < 0,
// no or a repeated parameter in `vary`, or a held-out point equal to a training point.
SamplePlan plan_sample(const SampleOptions& options);

struct SampleHipOutcome {
  enum class Status { kGenerated, kSkipped, kFailed };
  Status status = Status::kFailed;
  std::string error;     // kFailed: the generator's message
  double seconds = 0.0;  // kGenerated: construction, meshing and writing
};

// Generates hip `index` of `plan` into out_dir/<name>/ unless it is complete (kSkipped); a hip the
// generator cannot make is kFailed with the generator's message.
SampleHipOutcome generate_sample_hip(const SamplePlan& plan, std::size_t index, const std::filesystem::path& out_dir);

// Generates every hip of `plan` not yet complete into out_dir/<name>/ (model.json and the tissue
// meshes, as `hipfai generate` writes them), in plan order. A hip the generator cannot make is
// reported in its outcome and the others still run. `on_hip` is called after each hip (progress).
std::vector<SampleHipOutcome> generate_sample_hips(
    const SamplePlan& plan, const std::filesystem::path& out_dir,
    const std::function<void(std::size_t index, const SampleHipOutcome&)>& on_hip = {});

// True when out_dir/<name> is a complete hip folder (it has model.json).
bool sample_hip_complete(const std::filesystem::path& hip_dir);

}  // namespace hipfai::studies
