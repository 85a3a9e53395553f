// hipfai — which rank of a team run solves which of the compliance-column blocks still to solve
// (fem/rank_team.h, fem/body_compliance.h).
//
// Rank 0 solves a set of column blocks one after the other and, before each block after the
// first, asks deal_columns() whether handing part of the rest to its helpers finishes the set
// sooner. A helper counts only with a core to solve on (RankTeam::helper_cores). On the leader's
// node the leader's own threads come first: its solving thread keeps its core, and its thread of
// searches ahead (fem/contact_search_ahead.h) needs its work done on the core it shares with a
// helper, so that helper's blocks come after that work (busy seconds); a deal that took the
// searches' core would only move their work to the steps after, which on a full machine have
// no core free for it either. A helper that does not hold the bodies' current factors
// factorises them first, which costs it what the leader's factorisation cost (the same
// matrices).
//
// The deal balances the finishing times from measured times, not from counts: the leader solves
// n_0 blocks in n_0 * t; helper i, after its delay d_i (busy seconds, plus the factorisation if
// it must factorise), solves n_i in d_i + n_i * t; all end together at
// T = (R t + sum d_i) / (1 + k) for the k helpers whose delay is below T. Helpers' counts are
// rounded down (the leader takes the remainder), so a deal never promises a helper more than it
// can finish by T. Which rank solves a block does not change its numbers (each block is one
// block solve of the same right-hand sides), only the time.
#pragma once

#include <cstddef>
#include <vector>

namespace hipfai::fem {

struct ColumnDealHelper {
  bool has_core = false;    // a core to solve on (RankTeam::helper_cores)
  // Work that core has to do first (the leader's searches ahead left on it), seconds.
  double busy_seconds = 0.0;
  bool factorised = false;  // holds the factors of the leader's bodies in their current frame
  // May factorise in this run: the leader factorises every body in this run, so the bodies'
  // frames are this run's placement, which the helper has too. Helpers that are not factorised
  // and may not factorise take no blocks.
  bool may_factorise = false;
};

struct ColumnDealRequest {
  std::size_t blocks = 0;         // blocks left, in the order of BodyCompliance::column_blocks
  double block_seconds = 0.0;     // one block's solve on the leader (measured), > 0
  double factorisation_seconds = 0.0;  // the leader's factorisation of the bodies (measured)
  std::vector<ColumnDealHelper> helpers;  // ranks 1, 2, ... of the team
};

struct ColumnDeal {
  // Blocks per rank (0: the leader), contiguous in this order: the leader takes the first
  // counts[0] of the blocks left, rank 1 the next counts[1], and so on. Sums to the blocks left.
  std::vector<std::size_t> counts;
  // Per rank: factorises before its blocks (never the leader).
  std::vector<bool> factorise;
  // Some helper takes blocks.
  bool dealt() const;
};

// The deal described in the file comment. Throws hipfai::Error for block_seconds <= 0 or a
// negative factorisation time.
ColumnDeal deal_columns(const ColumnDealRequest& request);

// The leader and every helper that holds the factors or may factorise take equal shares (the
// first of them one more where they do not divide), whether or not they have a core of their
// own; those not factorised factorise first: the deal of TeamColumns::kEveryRank.
ColumnDeal deal_columns_evenly(std::size_t blocks, const std::vector<ColumnDealHelper>& helpers);

}  // namespace hipfai::fem
