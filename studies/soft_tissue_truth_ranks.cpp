#include "studies/soft_tissue_truth_ranks.h"

#ifdef HIPFAI_WITH_FEM

#include "core/stopwatch.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/spread_units.h"
#include "studies/soft_tissue_truth_unit.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace hipfai::studies {

// What a worker sends back for a hip: its row and the contact tolerance it used.
struct SoftTissueTruthReply {
  SoftTissueTruthRow row;
  double tolerance_mm = 0.0;
};

// The replies' fields, each type's in one order (studies/pipeline/unit_reply.h); internal to this
// file, found by argument-dependent lookup through the writer and reader.
static void write_reply(UnitReplyWriter& out, const SoftTissueFePeaks& p) {
  out.add(p.pressure_mpa).add(p.ball_pressure_mpa);
  for (std::size_t t = 0; t < p.von_mises_mpa.size(); ++t) out.add(p.von_mises_mpa[t]).add(p.ball_von_mises_mpa[t]);
  out.add(p.steps).add(p.unconverged).add(p.seconds);
}
static void read_reply(UnitReplyReader& in, SoftTissueFePeaks& p) {
  in.read(p.pressure_mpa).read(p.ball_pressure_mpa);
  for (std::size_t t = 0; t < p.von_mises_mpa.size(); ++t) in.read(p.von_mises_mpa[t]).read(p.ball_von_mises_mpa[t]);
  in.read(p.steps).read(p.unconverged).read(p.seconds);
}

static void write_reply(UnitReplyWriter& out, const std::optional<SoftTissueFePeaks>& peaks) {
  out.add(peaks.has_value());
  if (peaks) out.add(*peaks);
}
static void read_reply(UnitReplyReader& in, std::optional<SoftTissueFePeaks>& peaks) {
  peaks.reset();
  if (in.get<bool>()) in.read(peaks.emplace());
}

static void write_reply(UnitReplyWriter& out, const SoftTissueTruthRow& r) {
  out.add(r.hip);
  out.add(r.generated_femoral_cartilage_mm3).add(r.synthesised_femoral_cartilage_mm3);
  out.add(r.generated_acetabular_cartilage_mm3).add(r.synthesised_acetabular_cartilage_mm3);
  out.add(r.generated_labrum_mm3).add(r.synthesised_labrum_mm3);
  out.add(r.synthesised_femoral_mean_thickness_mm).add(r.synthesised_acetabular_mean_thickness_mm);
  out.add(r.generated_curvilinear_mm).add(r.synthesised_curvilinear_mm);
  out.add(r.generated_radial_mm).add(r.synthesised_radial_mm).add(r.synthesis_seconds);
  out.add(r.generated_fe).add(r.synthesised_fe).add(r.fe_error);
}
static void read_reply(UnitReplyReader& in, SoftTissueTruthRow& r) {
  in.read(r.hip);
  in.read(r.generated_femoral_cartilage_mm3).read(r.synthesised_femoral_cartilage_mm3);
  in.read(r.generated_acetabular_cartilage_mm3).read(r.synthesised_acetabular_cartilage_mm3);
  in.read(r.generated_labrum_mm3).read(r.synthesised_labrum_mm3);
  in.read(r.synthesised_femoral_mean_thickness_mm).read(r.synthesised_acetabular_mean_thickness_mm);
  in.read(r.generated_curvilinear_mm).read(r.synthesised_curvilinear_mm);
  in.read(r.generated_radial_mm).read(r.synthesised_radial_mm).read(r.synthesis_seconds);
  in.read(r.generated_fe).read(r.synthesised_fe).read(r.fe_error);
}

static void write_reply(UnitReplyWriter& out, const SoftTissueTruthReply& reply) {
  out.add(reply.row).add(reply.tolerance_mm);
}
static void read_reply(UnitReplyReader& in, SoftTissueTruthReply& reply) {
  in.read(reply.row).read(reply.tolerance_mm);
}

namespace {

// The hip's two FE runs on this rank alone, into the shared cache, their peaks into the row (or,
// as in the one-process run, why a run failed).
void solve_fe_here(SoftTissueTruthRow& row, const SoftTissueTruthOptions& options, const Motion& motion,
                   unsigned int threads) {
  const std::array<FeBatchJob, 2> jobs = soft_tissue_fe_jobs(row, options, motion);
  for (std::size_t k = 0; k < jobs.size(); ++k) {
    try {
      const FeEntryOnRank made = make_fe_entry_on_this_rank(jobs[k], options.cache_dir, threads);
      (k == 0 ? row.generated_fe : row.synthesised_fe) = soft_tissue_fe_peaks(made.entry);
    } catch (const std::exception& e) {
      row.fe_error += (row.fe_error.empty() ? "" : "; ") + std::string(e.what());
    }
  }
}

}  // namespace

SoftTissueTruthResult run_soft_tissue_truth_over_ranks(const SoftTissueTruthOptions& options) {
  const MpiWorld world = join_mpi_world();
  const unsigned int threads = threads_per_worker_rank(MPI_COMM_WORLD);
  // Each hip's penetration threads: the node's cores shared among the worker ranks (the depths do
  // not depend on them).
  SoftTissueTruthOptions unit_options = options;
  unit_options.threads = static_cast<int>(threads);
  const std::vector<std::pair<double, double>> grid = soft_tissue_truth_grid(options);
  const Motion motion = soft_tissue_truth_motion(options);
  const auto name = [&](std::size_t h) { return parametric_hip_id(grid[h].first, grid[h].second); };
  if (world.rank == 0 && options.progress) {
    std::printf("soft-tissue-truth: %zu hips over %d worker ranks (%u thread(s) each)\n", grid.size(),
                world.size - 1, threads);
    std::fflush(stdout);
  }
  const auto start = SteadyClock::now();
  const auto run = [&](std::size_t h) {
    SoftTissueTruthReply reply;
    reply.row = compare_soft_tissue_hip(grid[h].first, grid[h].second, unit_options, motion, reply.tolerance_mm);
    if (options.fe_level) solve_fe_here(reply.row, unit_options, motion, threads);
    return reply;
  };
  std::size_t done = 0;
  const auto finished = [&](std::size_t h, int rank, const UnitResult<SoftTissueTruthReply>& result) {
    if (!options.progress) return;
    if (result.reply) {
      const SoftTissueTruthRow& row = result.reply->row;
      std::printf("soft-tissue-truth: [%zu/%zu] %s on rank %d: curvilinear %.2f / %.2f mm, radial %.2f / %.2f mm%s%s "
                  "(%.0f s elapsed)\n",
                  ++done, grid.size(), row.hip.c_str(), rank, row.generated_curvilinear_mm,
                  row.synthesised_curvilinear_mm, row.generated_radial_mm, row.synthesised_radial_mm,
                  row.fe_error.empty() ? "" : "; FE failed: ", row.fe_error.c_str(), seconds_since(start));
    } else {
      std::printf("soft-tissue-truth: [%zu/%zu] %s failed on rank %d: %s\n", ++done, grid.size(), name(h).c_str(), rank,
                  result.error.c_str());
    }
    std::fflush(stdout);
  };
  auto replies = spread_units<SoftTissueTruthReply>(MPI_COMM_WORLD, grid.size(), run, finished);
  SoftTissueTruthResult out;
  out.options = options;
  if (!replies) {
    out.holds_results = false;
    return out;
  }
  for (std::size_t h = 0; h < grid.size(); ++h) {
    UnitResult<SoftTissueTruthReply>& result = (*replies)[h];
    if (!result.reply) {
      out.failed.push_back({name(h), result.error});
      continue;
    }
    out.contact_tolerance_mm = std::max(out.contact_tolerance_mm, result.reply->tolerance_mm);
    out.rows.push_back(std::move(result.reply->row));
  }
  return out;
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
