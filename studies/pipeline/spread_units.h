// hipfai — a study's independent units (a hip, a fold) spread over the ranks of an MPI job and
// their typed replies gathered on rank 0: the rank pool (studies/pipeline/rank_pool.h) hands unit
// 0, 1, ... to whichever worker rank is free, the worker runs it alone and sends its reply back as
// bytes (studies/pipeline/unit_reply.h), and rank 0 gets every unit's reply, or why it failed, in
// unit order. The units do not depend on each other; a study whose units do (validation: a hip's
// FE after its penetration) drives the pool itself.
#pragma once

#ifdef HIPFAI_WITH_FEM

#include "studies/pipeline/mpi_launch.h"
#include "studies/pipeline/rank_pool.h"
#include "studies/pipeline/unit_reply.h"

#include <mpi.h>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hipfai::studies {

// One unit's outcome on rank 0: its reply, or (reply empty) the failure's message.
template <typename Reply>
struct UnitResult {
  std::optional<Reply> reply;
  std::string error;
};

// The untyped spread: on rank 0 every unit's outcome in unit order (`finished` is told of each as
// it arrives, e.g. for progress); on the other ranks, after running the units handed to them with
// `run`, nothing. Collective over `comm` (at least 2 ranks).
std::vector<UnitOutcome> spread_units_over_ranks(
    MPI_Comm comm, std::size_t units, const std::function<std::string(std::size_t unit)>& run,
    const std::function<void(std::size_t unit, int rank, const UnitOutcome& outcome)>& finished = {});

// The typed spread: `run(unit)` returns the unit's Reply on the worker that runs it; rank 0 gets
// them decoded (a reply that does not decode counts as the unit's failure). `finished(unit, rank,
// result)` on rank 0 as each arrives. nullopt on the other ranks.
template <typename Reply>
std::optional<std::vector<UnitResult<Reply>>> spread_units(
    MPI_Comm comm, std::size_t units, const std::function<Reply(std::size_t unit)>& run,
    const std::function<void(std::size_t unit, int rank, const UnitResult<Reply>& result)>& finished = {}) {
  std::vector<UnitResult<Reply>> results(units);
  const auto decode = [&](std::size_t unit, const UnitOutcome& outcome) {
    UnitResult<Reply>& result = results[unit];
    if (!outcome.ok) {
      result.error = outcome.error;
      return;
    }
    try {
      result.reply = decode_unit_reply<Reply>(outcome.reply);
    } catch (const std::exception& e) {
      result.error = e.what();
    }
  };
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  spread_units_over_ranks(
      comm, units, [&](std::size_t unit) { return encode_unit_reply(run(unit)); },
      [&](std::size_t unit, int worker, const UnitOutcome& outcome) {
        decode(unit, outcome);
        if (finished) finished(unit, worker, results[unit]);
      });
  if (rank != 0) return std::nullopt;
  return results;
}

// `bytes` of rank 0 given to every rank of `comm` (collective); the waiting ranks sleep instead of
// spinning on the cores rank 0 computes on.
void share_from_rank_zero(MPI_Comm comm, std::string& bytes);

}  // namespace hipfai::studies

#endif  // HIPFAI_WITH_FEM
