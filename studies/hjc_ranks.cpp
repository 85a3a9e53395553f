#include "studies/hjc_ranks.h"

#ifdef HIPFAI_WITH_FEM

#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/spread_units.h"

#include <cstdio>

namespace hipfai::studies {

// The reply's fields (studies/pipeline/unit_reply.h); internal to this file, found by
// argument-dependent lookup through the writer and reader.
static void write_reply(UnitReplyWriter& out, const HjcRotationDepths& d) {
  out.add(d.angle_deg).add(d.curvilinear_mm).add(d.radial_mm);
}
static void read_reply(UnitReplyReader& in, HjcRotationDepths& d) {
  in.read(d.angle_deg).read(d.curvilinear_mm).read(d.radial_mm);
}

static void write_reply(UnitReplyWriter& out, const HjcSubjectResult& subject) {
  out.add(subject.id).add(subject.true_centre_mm).add(subject.centres_mm).add(subject.depths);
}
static void read_reply(UnitReplyReader& in, HjcSubjectResult& subject) {
  in.read(subject.id).read(subject.true_centre_mm).read(subject.centres_mm).read(subject.depths);
}

HjcRankRun run_hjc_subjects_over_ranks(const HjcStudyOptions& options) {
  const MpiWorld world = join_mpi_world();
  // Each subject's threads: the node's cores shared among the worker ranks (the same results).
  HjcStudyOptions unit_options = options;
  unit_options.threads = static_cast<int>(threads_per_worker_rank(MPI_COMM_WORLD));
  const std::size_t subjects = options.subjects.size();
  if (world.rank == 0 && options.progress) {
    std::printf("hjc: %zu subjects over %d worker ranks (%d thread(s) each)\n", subjects, world.size - 1,
                unit_options.threads);
    std::fflush(stdout);
  }
  const auto name = [&](std::size_t s) { return parametric_hip_id(options.subjects[s].first, options.subjects[s].second); };
  std::size_t done = 0;
  const auto run = [&](std::size_t s) {
    ProgressBar quiet("", 0, false);
    return compute_hjc_subject(unit_options, s, quiet);
  };
  const auto finished = [&](std::size_t s, int rank, const UnitResult<HjcSubjectResult>& result) {
    if (!options.progress) return;
    std::printf("hjc: [%zu/%zu] %s on rank %d%s%s\n", ++done, subjects, name(s).c_str(), rank,
                result.reply ? "" : " failed: ", result.reply ? "" : result.error.c_str());
    std::fflush(stdout);
  };
  auto replies = spread_units<HjcSubjectResult>(MPI_COMM_WORLD, subjects, run, finished);
  HjcRankRun out;
  if (!replies) return out;
  out.holds_results = true;
  for (std::size_t s = 0; s < subjects; ++s) {
    UnitResult<HjcSubjectResult>& result = (*replies)[s];
    if (result.reply) {
      out.subjects.push_back(std::move(*result.reply));
    } else {
      out.failed.push_back({name(s), result.error});
    }
  }
  return out;
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
