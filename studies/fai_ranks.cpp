#include "studies/fai_ranks.h"

#ifdef HIPFAI_WITH_FEM

#include "studies/pipeline/spread_units.h"

#include <array>
#include <cstdio>

namespace hipfai::studies {

// What a worker sends back for a unit: all of its FaiModelRun but the hip, which rank 0 loads.
struct FaiUnitReply {
  FaiModelSummary summary;
  PenetrationRun run;
  double seconds = 0;
};

// The replies' fields, each type's in one order (studies/pipeline/unit_reply.h); internal to this
// file, found by argument-dependent lookup through the writer and reader.
static void write_reply(UnitReplyWriter& out, const contact::LimitingContact& limit) {
  out.add(limit.kind).add(limit.vertex).add(limit.triangle);
  for (const auto& edge : {limit.mobile_edge, limit.fixed_edge}) out.add(edge[0]).add(edge[1]);
}
static void read_reply(UnitReplyReader& in, contact::LimitingContact& limit) {
  in.read(limit.kind).read(limit.vertex).read(limit.triangle);
  for (auto* edge : {&limit.mobile_edge, &limit.fixed_edge}) in.read((*edge)[0]).read((*edge)[1]);
}

static void write_reply(UnitReplyWriter& out, const contact::RangeOfMotion& range) {
  out.add(range.status).add(range.message).add(range.anticlockwise_deg).add(range.clockwise_deg);
  out.add(range.anticlockwise_limit).add(range.clockwise_limit);
}
static void read_reply(UnitReplyReader& in, contact::RangeOfMotion& range) {
  in.read(range.status).read(range.message).read(range.anticlockwise_deg).read(range.clockwise_deg);
  in.read(range.anticlockwise_limit).read(range.clockwise_limit);
}

static void write_reply(UnitReplyWriter& out, const contact::StartPoseOverlap& o) {
  out.add(o.status).add(o.message).add(o.mobile_vertices_inside).add(o.mobile_deepest_mm).add(o.mobile_deepest_vertex);
  out.add(o.fixed_vertices_inside).add(o.fixed_deepest_mm).add(o.fixed_deepest_vertex);
  out.add(o.mobile_edges_through).add(o.fixed_edges_through).add(o.edge_deepest_mm).add(o.touching_mm);
}
static void read_reply(UnitReplyReader& in, contact::StartPoseOverlap& o) {
  in.read(o.status).read(o.message).read(o.mobile_vertices_inside).read(o.mobile_deepest_mm).read(o.mobile_deepest_vertex);
  in.read(o.fixed_vertices_inside).read(o.fixed_deepest_mm).read(o.fixed_deepest_vertex);
  in.read(o.mobile_edges_through).read(o.fixed_edges_through).read(o.edge_deepest_mm).read(o.touching_mm);
}

static void write_reply(UnitReplyWriter& out, const StepPenetration& s) {
  out.add(s.curvilinear_mm).add(s.curvilinear_swap_mm).add(s.radial_mm).add(s.radial_swap_mm);
  out.add(s.curvilinear_vertices).add(s.radial_vertices).add(s.curvilinear_ms).add(s.radial_ms);
}
static void read_reply(UnitReplyReader& in, StepPenetration& s) {
  in.read(s.curvilinear_mm).read(s.curvilinear_swap_mm).read(s.radial_mm).read(s.radial_swap_mm);
  in.read(s.curvilinear_vertices).read(s.radial_vertices).read(s.curvilinear_ms).read(s.radial_ms);
}

static void write_reply(UnitReplyWriter& out, const PenetrationRun& run) {
  out.add(run.steps).add(run.max_fields).add(run.rom_axes).add(run.rom);
  out.add(run.curvilinear_preprocessing_ms).add(run.radial_preprocessing_ms).add(run.contact_tolerance_mm);
  out.add(run.neutral_overlap);
}
static void read_reply(UnitReplyReader& in, PenetrationRun& run) {
  in.read(run.steps).read(run.max_fields).read(run.rom_axes).read(run.rom);
  in.read(run.curvilinear_preprocessing_ms).read(run.radial_preprocessing_ms).read(run.contact_tolerance_mm);
  in.read(run.neutral_overlap);
}

static void write_reply(UnitReplyWriter& out, const FaiModelSummary& m) {
  out.add(m.ce_deg).add(m.alpha_deg).add(m.max_curvilinear_mm).add(m.max_radial_mm).add(m.normalised_difference);
  out.add(m.generate_s).add(m.penetration_ms).add(m.first_contact_deg).add(m.pathology);
}
static void read_reply(UnitReplyReader& in, FaiModelSummary& m) {
  in.read(m.ce_deg).read(m.alpha_deg).read(m.max_curvilinear_mm).read(m.max_radial_mm).read(m.normalised_difference);
  in.read(m.generate_s).read(m.penetration_ms).read(m.first_contact_deg).read(m.pathology);
}

static void write_reply(UnitReplyWriter& out, const FaiUnitReply& reply) {
  out.add(reply.summary).add(reply.run).add(reply.seconds);
}
static void read_reply(UnitReplyReader& in, FaiUnitReply& reply) {
  in.read(reply.summary).read(reply.run).read(reply.seconds);
}

FaiRankRun run_fai_units_over_ranks(const std::vector<FaiUnit>& units, const Motion& motion,
                                    const FaiStudyOptions& options) {
  const MpiWorld world = join_mpi_world();
  // Each unit's threads: the node's cores shared among the worker ranks (the same results: the
  // depths do not depend on the number of threads).
  FaiStudyOptions unit_options = options;
  unit_options.threads = static_cast<int>(threads_per_worker_rank(MPI_COMM_WORLD));
  if (world.rank == 0 && options.progress) {
    std::printf("fai: %zu hips over %d worker ranks (%d thread(s) each)\n", units.size(), world.size - 1,
                unit_options.threads);
    std::fflush(stdout);
  }
  std::size_t done = 0;
  const auto run = [&](std::size_t unit) {
    StageLog log;
    FaiModelRun model = run_fai_unit(units[unit], motion, unit_options, log);
    return FaiUnitReply{std::move(model.summary), std::move(model.run), model.seconds};
  };
  const auto finished = [&](std::size_t unit, int rank, const UnitResult<FaiUnitReply>& result) {
    if (!options.progress) return;
    const std::string name = fai_unit_name(units[unit], options);
    if (result.reply) {
      std::printf("fai: [%zu/%zu] %s on rank %d: max curvilinear %.2f mm, radial %.2f mm\n", ++done, units.size(),
                  name.c_str(), rank, result.reply->summary.max_curvilinear_mm, result.reply->summary.max_radial_mm);
    } else {
      std::printf("fai: [%zu/%zu] %s failed on rank %d: %s\n", ++done, units.size(), name.c_str(), rank,
                  result.error.c_str());
    }
    std::fflush(stdout);
  };
  auto replies = spread_units<FaiUnitReply>(MPI_COMM_WORLD, units.size(), run, finished);
  FaiRankRun out;
  if (!replies) return out;
  out.holds_results = true;
  for (std::size_t k = 0; k < units.size(); ++k) {
    UnitResult<FaiUnitReply>& result = (*replies)[k];
    std::optional<FaiModelRun>& model = out.runs.emplace_back();
    if (result.reply) {
      try {
        StageLog log;
        LoadedHip hip = load_fai_unit_hip(units[k], options, log);
        model = FaiModelRun{std::move(result.reply->summary), std::move(result.reply->run), std::move(hip),
                            result.reply->seconds};
        continue;
      } catch (const std::exception& e) {
        result.error = e.what();
      }
    }
    out.failed.push_back({fai_unit_name(units[k], options), result.error});
  }
  return out;
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
