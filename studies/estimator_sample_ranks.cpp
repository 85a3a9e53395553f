#include "studies/estimator_sample_ranks.h"

#ifdef HIPFAI_WITH_FEM

#include "core/stopwatch.h"
#include "studies/pipeline/mpi_launch.h"
#include "studies/pipeline/spread_units.h"

#include <string>
#include <utility>

namespace hipfai::studies {

// What a worker sends back for a hip: how its generation went and, with FE, its depths and FE.
struct SampleUnitReply {
  SampleHipOutcome outcome;
  bool has_fe = false;
  SampleFeHip hip;
};

// The replies' fields, each type's in one order (studies/pipeline/unit_reply.h); internal to this
// file, found by argument-dependent lookup through the writer and reader.
static void write_reply(UnitReplyWriter& out, const SampleHipOutcome& o) {
  out.add(o.status).add(o.error).add(o.seconds);
}
static void read_reply(UnitReplyReader& in, SampleHipOutcome& o) { in.read(o.status).read(o.error).read(o.seconds); }

static void write_reply(UnitReplyWriter& out, const SampleFeHip& h) {
  out.add(h.dir.string()).add(h.plan_index).add(h.curvilinear_max_mm).add(h.radial_max_mm).add(h.fe);
  out.add(h.penetration_ms).add(h.fe_s).add(h.fe_reused).add(h.fe_steps_failed).add(h.error);
}
static void read_reply(UnitReplyReader& in, SampleFeHip& h) {
  h.dir = in.get<std::string>();
  in.read(h.plan_index).read(h.curvilinear_max_mm).read(h.radial_max_mm).read(h.fe);
  in.read(h.penetration_ms).read(h.fe_s).read(h.fe_reused).read(h.fe_steps_failed).read(h.error);
}

static void write_reply(UnitReplyWriter& out, const SampleUnitReply& r) {
  out.add(r.outcome).add(r.has_fe);
  if (r.has_fe) out.add(r.hip);
}
static void read_reply(UnitReplyReader& in, SampleUnitReply& r) {
  in.read(r.outcome).read(r.has_fe);
  if (r.has_fe) in.read(r.hip);
}

SampleRankRun run_sample_over_ranks(
    const SamplePlan& plan, const std::filesystem::path& out_dir, const SampleFeOptions* fe,
    const std::function<void(std::size_t index, int rank, const SampleHipOutcome&, const SampleFeHip*)>& on_hip) {
  if (fe) check_sample_fe_options(*fe);  // the same options on every rank: all throw, or none
  join_mpi_world();  // MPI initialised on every rank
  // Each hip's threads (penetration queries and FE): the node's cores shared among the worker
  // ranks. The results do not depend on them.
  const unsigned int threads = threads_per_worker_rank(MPI_COMM_WORLD);
  const auto start = SteadyClock::now();
  const Motion motion = standing_to_sitting(fe ? fe->steps : 3);
  const auto run = [&](std::size_t h) {
    SampleUnitReply reply;
    reply.outcome = generate_sample_hip(plan, h, out_dir);
    if (fe && reply.outcome.status != SampleHipOutcome::Status::kFailed) {
      reply.has_fe = true;
      reply.hip = sample_hip_fe_on_this_rank(h, out_dir / plan.hips[h].name, motion, *fe, threads);
    }
    return reply;
  };
  const auto finished = [&](std::size_t h, int rank, const UnitResult<SampleUnitReply>& result) {
    if (!on_hip) return;
    if (result.reply) {
      on_hip(h, rank, result.reply->outcome, result.reply->has_fe ? &result.reply->hip : nullptr);
    } else {
      SampleHipOutcome failed;
      failed.error = result.error;
      on_hip(h, rank, failed, nullptr);
    }
  };
  auto replies = spread_units<SampleUnitReply>(MPI_COMM_WORLD, plan.hips.size(), run, finished);
  SampleRankRun out;
  if (!replies) return out;
  out.holds_results = true;
  if (fe) {
    out.fe.emplace();
    out.fe->motion = motion;
  }
  for (std::size_t h = 0; h < plan.hips.size(); ++h) {
    UnitResult<SampleUnitReply>& result = (*replies)[h];
    if (!result.reply) {
      // The unit threw past the generator and the FE (a hip that loads but cannot be queried):
      // the hip is named with why, as a failed generation is.
      SampleHipOutcome failed;
      failed.error = result.error;
      out.outcomes.push_back(std::move(failed));
      if (fe) ++out.fe->missing;
      continue;
    }
    out.outcomes.push_back(result.reply->outcome);
    if (!fe) continue;
    if (result.reply->has_fe) {
      out.fe->hips.push_back(std::move(result.reply->hip));
    } else {
      ++out.fe->missing;
    }
  }
  if (fe) out.fe->seconds = seconds_since(start);
  return out;
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
