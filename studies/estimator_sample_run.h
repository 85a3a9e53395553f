// hipfai — a whole `estimator sample` run: the design written (design.csv), every hip generated
// and, with FE options, each hip's depths and FE; on this machine (the hips one after the other,
// the FE in worker processes, studies/estimator_sample_fe.h) or, started by an MPI launcher with two
// ranks or more, each hip on a worker rank (studies/estimator_sample_ranks.h). The same files and
// numbers either way. The tables are written by studies/estimator_sample_report.h.
#pragma once

#include "studies/estimator_sample.h"
#include "studies/estimator_sample_fe.h"
#include "studies/pipeline/mpi_launch.h"

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hipfai::studies {

struct EstimatorSampleRun {
  bool holds_results = true;               // false on the worker ranks of a spread run
  std::vector<SampleHipOutcome> outcomes;  // one per hip of the plan, in plan order
  std::optional<SampleFeResult> fe;        // with FE options
};

// `say(line, failed)` is told one line per hip as it is made (sample_hip_line, and on ranks which
// rank and how its FE went). Throws hipfai::Error (on every rank of a spread run) when out_dir
// holds another design or the FE options are unusable.
EstimatorSampleRun run_estimator_sample(const SamplePlan& plan, const std::filesystem::path& out_dir,
                                        const std::optional<SampleFeOptions>& fe, UnitSpread spread,
                                        const std::function<void(const std::string& line, bool failed)>& say);

}  // namespace hipfai::studies
