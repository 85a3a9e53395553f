#include "studies/validation_ranks.h"

#ifdef HIPFAI_WITH_FEM

#include "core/error.h"
#include "core/stopwatch.h"
#include "studies/pipeline/fe_entry.h"
#include "studies/pipeline/hip_source.h"
#include "studies/pipeline/mpi_launch.h"
#include "studies/pipeline/rank_pool.h"
#include "studies/pipeline/unit_reply.h"

#include <algorithm>
#include <cstdio>
#include <deque>
#include <optional>
#include <string>

namespace hipfai::studies {
namespace {

std::string encode_penetration(const ValidationHip& hip) {
  UnitReplyWriter out;
  out.add(hip.id).add(hip.dir.string()).add(hip.curvilinear_max_mm).add(hip.radial_max_mm);
  out.add(hip.timing.generate_s).add(hip.timing.penetration_tables_ms).add(hip.timing.penetration_query_ms);
  return out.take();
}

void decode_penetration(const std::string& bytes, ValidationHip& hip) {
  UnitReplyReader in(bytes);
  hip.id = in.get<std::string>();
  hip.dir = in.get<std::string>();
  in.read(hip.curvilinear_max_mm).read(hip.radial_max_mm);
  in.read(hip.timing.generate_s).read(hip.timing.penetration_tables_ms).read(hip.timing.penetration_query_ms);
  in.expect_end();
}

struct FeReply {
  EntrySource source = EntrySource::kMade;
  std::filesystem::path entry;
  double seconds = 0;
};

std::string encode_fe(const FeReply& reply) {
  UnitReplyWriter out;
  out.add(reply.source).add(reply.entry.string()).add(reply.seconds);
  return out.take();
}

FeReply decode_fe(const std::string& bytes) {
  UnitReplyReader in(bytes);
  FeReply reply;
  reply.source = in.get<EntrySource>();
  reply.entry = in.get<std::string>();
  reply.seconds = in.get<double>();
  in.expect_end();
  return reply;
}

// The units: 0..H-1 the penetration of the hip order[u], H..2H-1 the FE of the hip order[u - H].
struct Units {
  const std::vector<std::pair<double, double>>& grid;
  const std::vector<std::size_t>& order;
  std::size_t hips() const { return order.size(); }
  bool is_fe(std::size_t unit) const { return unit >= hips(); }
  std::size_t hip_of(std::size_t unit) const { return order[is_fe(unit) ? unit - hips() : unit]; }
  std::size_t fe_unit_of_start(std::size_t k) const { return hips() + k; }
};

std::string run_unit(const Units& units, std::size_t unit, const Motion& motion, const ValidationOptions& options,
                     unsigned int threads) {
  const auto [ce, alpha] = units.grid[units.hip_of(unit)];
  if (!units.is_fe(unit)) {
    return encode_penetration(run_validation_penetration(ce, alpha, motion, options, static_cast<int>(threads)));
  }
  // The hip exists: its penetration unit made it (on this rank or another) before this one was handed out.
  ValidationHip hip;
  hip.ce = ce;
  hip.alpha = alpha;
  hip.id = parametric_hip_id(ce, alpha);
  hip.dir = generated_hip_dir(ParametricHip{ce, alpha, options.edge_mm}, options.cache_dir);
  const auto start = SteadyClock::now();
  const FeEntryOnRank made = make_fe_entry_on_this_rank(validation_fe_job(hip, options), options.cache_dir, threads);
  FeReply reply;
  reply.entry = made.entry;
  reply.source = made.source;
  reply.seconds = seconds_since(start);
  return encode_fe(reply);
}

double deepest(const std::vector<double>& values) {
  double value = 0.0;
  for (const double v : values) value = std::max(value, v);
  return value;
}

// Rank 0's side: the units handed out, the replies kept.
class Master {
 public:
  Master(const Units& units, const Motion& motion, const ValidationOptions& options)
      : units_(units), motion_(motion), options_(options), hips_(units.grid.size()), fe_(units.grid.size()),
        errors_(units.grid.size()) {}

  std::optional<std::size_t> next_unit() {
    if (!fe_ready_.empty()) {
      const std::size_t unit = fe_ready_.front();
      fe_ready_.pop_front();
      return unit;
    }
    if (next_penetration_ < units_.hips()) return next_penetration_++;
    return std::nullopt;
  }

  void finished(std::size_t unit, int rank, const UnitOutcome& outcome) {
    const std::size_t h = units_.hip_of(unit);
    const auto [ce, alpha] = units_.grid[h];
    const std::string id = parametric_hip_id(ce, alpha);
    const char* what = units_.is_fe(unit) ? "FE" : "penetration";
    if (!outcome.ok) {
      errors_[h] = std::string(what) + ": " + outcome.error;
      print("validate: %s of %s failed on rank %d: %s\n", what, id.c_str(), rank, outcome.error.c_str());
      return;
    }
    if (!units_.is_fe(unit)) {
      ValidationHip& hip = hips_[h].emplace();
      hip.ce = ce;
      hip.alpha = alpha;
      hip.timing.ce_deg = ce;
      hip.timing.alpha_deg = alpha;
      decode_penetration(outcome.reply, hip);
      fe_ready_.push_back(units_.fe_unit_of_start(unit));
      print("validate: penetration [%zu/%zu] %s on rank %d: max curvilinear %.2f mm, radial %.2f mm\n",
            ++penetrations_done_, units_.hips(), id.c_str(), rank, deepest(hip.curvilinear_max_mm),
            deepest(hip.radial_max_mm));
      return;
    }
    const FeReply reply = decode_fe(outcome.reply);
    FeBatchEntry& entry = fe_[h].emplace();
    entry.entry = reply.entry;
    entry.source = reply.source;
    entry.reused = reply.source != EntrySource::kMade;
    print("validate: FE [%zu/%zu] %s %s on rank %d in %.0f s (%.0f s elapsed)\n", ++fe_done_, units_.hips(), id.c_str(),
          reply.source == EntrySource::kMade ? "solved" : "from the cache", rank, reply.seconds, seconds_since(start_));
  }

  // The hips that succeeded, their FE read back, and the others with why (grid order).
  ValidationRankRun results() {
    ValidationRankRun run;
    run.writes = true;
    for (std::size_t h = 0; h < hips_.size(); ++h) {
      const std::string id = parametric_hip_id(units_.grid[h].first, units_.grid[h].second);
      if (errors_[h].empty() && hips_[h] && fe_[h]) {
        try {
          read_validation_fe_entry(*hips_[h], *fe_[h], motion_, options_);
          run.hips.push_back(std::move(*hips_[h]));
          continue;
        } catch (const Error& e) {
          errors_[h] = e.what();
        }
      }
      run.failed.push_back({id, errors_[h].empty() ? "not run" : errors_[h]});
    }
    return run;
  }

 private:
  template <typename... Args>
  void print(const char* format, Args... args) const {
    if (!options_.progress) return;
    std::printf(format, args...);
    std::fflush(stdout);
  }

  const Units& units_;
  const Motion& motion_;
  const ValidationOptions& options_;
  std::vector<std::optional<ValidationHip>> hips_;
  std::vector<std::optional<FeBatchEntry>> fe_;
  std::vector<std::string> errors_;
  std::deque<std::size_t> fe_ready_;
  std::size_t next_penetration_ = 0, penetrations_done_ = 0, fe_done_ = 0;
  SteadyClock::time_point start_ = SteadyClock::now();
};

}  // namespace

ValidationRankRun run_validation_over_ranks(const std::vector<std::pair<double, double>>& grid,
                                            const std::vector<std::size_t>& order, const Motion& motion,
                                            const ValidationOptions& options) {
  const MpiWorld world = join_mpi_world();
  if (world.size < 2) throw_error("validate: spreading the hips over MPI ranks needs at least 2 ranks");
  const unsigned int threads = threads_per_worker_rank(MPI_COMM_WORLD);
  const Units units{grid, order};
  if (world.rank != 0) {
    run_rank_pool_worker(MPI_COMM_WORLD,
                         [&](std::size_t unit) { return run_unit(units, unit, motion, options, threads); });
    return {};
  }
  if (options.progress) {
    std::printf("validate: %zu hips over %d worker ranks (%u thread(s) each)\n", grid.size(), world.size - 1, threads);
    std::fflush(stdout);
  }
  Master master(units, motion, options);
  run_rank_pool_master(MPI_COMM_WORLD, RankPoolMaster{[&] { return master.next_unit(); },
                                                      [&](std::size_t unit, int rank, const UnitOutcome& outcome) {
                                                        master.finished(unit, rank, outcome);
                                                      }});
  return master.results();
}

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
