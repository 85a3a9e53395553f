// The deal of compliance-column blocks on a team run (fem/column_deal.h): checked against the
// finishing times it promises, computed by hand, and against a brute-force search over every
// split of the blocks between the leader and its helpers.
#include "fem/column_deal.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <vector>

namespace hipfai::fem {
namespace {

ColumnDealHelper factorised(double busy = 0.0) {
  return {.has_core = true, .busy_seconds = busy, .factorised = true};
}
ColumnDealHelper to_factorise(double busy = 0.0) {
  return {.has_core = true, .busy_seconds = busy, .may_factorise = true};
}

// The time the deal takes: every rank's delay (busy seconds of a helper's core, a
// factorisation) and its blocks; busy[r] for rank r (the leader's 0).
double finish_time(const ColumnDeal& deal, double t, double f, const std::vector<double>& busy = {}) {
  double finish = 0.0;
  for (std::size_t r = 0; r < deal.counts.size(); ++r) {
    if (deal.counts[r] == 0) continue;
    const double before = (r < busy.size() ? busy[r] : 0.0) + (deal.factorise[r] ? f : 0.0);
    finish = std::max(finish, before + static_cast<double>(deal.counts[r]) * t);
  }
  return finish;
}

TEST(ColumnDeal, NoHelperWithACoreLeavesEveryBlockToTheLeader) {
  const ColumnDeal deal = deal_columns(
      {40, 0.1, 0.5, {{.has_core = false, .factorised = true}, {.has_core = false, .may_factorise = true}}});
  EXPECT_EQ(deal.counts, (std::vector<std::size_t>{40, 0, 0}));
  EXPECT_FALSE(deal.dealt());
}

TEST(ColumnDeal, AFactorisedHelperHalvesAnEvenSet) {
  const ColumnDeal deal = deal_columns({40, 0.1, 0.5, {factorised()}});
  EXPECT_EQ(deal.counts, (std::vector<std::size_t>{20, 20}));
  EXPECT_EQ(deal.factorise, (std::vector<bool>{false, false}));
  EXPECT_TRUE(deal.dealt());
}

TEST(ColumnDeal, AHelperThatMustFactoriseTakesWhatItCanFinishByTheCommonTime) {
  // Alone: 40 x 0.1 = 4 s. With a helper that first factorises for 1 s: T = (4 + 1) / 2 = 2.5 s,
  // the helper solves (2.5 - 1) / 0.1 = 15 blocks, the leader 25.
  const ColumnDeal deal = deal_columns({40, 0.1, 1.0, {to_factorise()}});
  EXPECT_EQ(deal.counts, (std::vector<std::size_t>{25, 15}));
  EXPECT_EQ(deal.factorise, (std::vector<bool>{false, true}));
  EXPECT_NEAR(finish_time(deal, 0.1, 1.0), 2.5, 1e-12);
}

TEST(ColumnDeal, AFactorisationLongerThanTheSetIsNotWorthIt) {
  // Alone 3 blocks x 0.2 s = 0.6 s; a helper would need 0.64 s before its first block.
  const ColumnDeal deal = deal_columns({3, 0.2, 0.64, {to_factorise()}});
  EXPECT_EQ(deal.counts, (std::vector<std::size_t>{3, 0}));
  EXPECT_FALSE(deal.dealt());
  // One block is never split, even with a factorised helper.
  EXPECT_FALSE(deal_columns({1, 0.2, 0.0, {factorised(), factorised()}}).dealt());
}

TEST(ColumnDeal, AHelperSharingTheSearchesCoreStartsAfterTheirWork) {
  // 40 blocks of 0.1 s; the helper's core has 1.5 s of searches ahead and it factorises for 1 s:
  // T = (4 + 2.5) / 2 = 3.25 s, the helper's (3.25 - 2.5) / 0.1 = 7.5 -> 7 blocks.
  const ColumnDeal deal = deal_columns({40, 0.1, 1.0, {to_factorise(1.5)}});
  EXPECT_EQ(deal.counts, (std::vector<std::size_t>{33, 7}));
  EXPECT_LE(finish_time(deal, 0.1, 1.0, {0.0, 1.5}), 3.3 + 1e-12);
  // The searches need the core longer than the columns take alone (as at the default level on
  // two cores, where the searches ahead outlast the columns): no deal.
  EXPECT_FALSE(deal_columns({40, 0.1, 0.64, {to_factorise(4.4)}}).dealt());
  // A factorised helper on a core with work left to do only shares what remains after it.
  EXPECT_EQ(deal_columns({40, 0.1, 1.0, {factorised(2.0)}}).counts, (std::vector<std::size_t>{30, 10}));
}

TEST(ColumnDeal, HelpersThatMayNotFactoriseTakeNothing) {
  // Not factorised and the leader did not factorise in this run: its factors' frame is gone.
  const ColumnDeal deal = deal_columns({40, 0.1, 1.0, {{.has_core = true}, factorised()}});
  EXPECT_EQ(deal.counts, (std::vector<std::size_t>{20, 0, 20}));
}

TEST(ColumnDeal, NeverSlowerThanTheLeaderAloneAndCloseToTheBestSplit) {
  // Brute force over every split of the blocks between the leader and two helpers (one
  // factorised, one not and with 0.4 s of other work on its core): the deal's finishing time is
  // within a block of the best one, and never later than the leader alone.
  for (const double f : {0.0, 0.3, 1.0, 2.5}) {
    for (std::size_t blocks = 1; blocks <= 30; ++blocks) {
      const double t = 0.1;
      const ColumnDeal deal = deal_columns({blocks, t, f, {factorised(), to_factorise(0.4)}});
      ASSERT_EQ(std::accumulate(deal.counts.begin(), deal.counts.end(), std::size_t{0}), blocks);
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t a = 0; a <= blocks; ++a) {
        for (std::size_t b = 0; a + b <= blocks; ++b) {
          ColumnDeal split;
          split.counts = {blocks - a - b, a, b};
          split.factorise = {false, false, b > 0};
          best = std::min(best, finish_time(split, t, f, {0.0, 0.0, 0.4}));
        }
      }
      const double mine = finish_time(deal, t, f, {0.0, 0.0, 0.4});
      EXPECT_LE(mine, static_cast<double>(blocks) * t + 1e-12) << blocks << " blocks, f " << f;
      EXPECT_LE(mine, best + t + 1e-12) << blocks << " blocks, f " << f;
    }
  }
}

TEST(ColumnDeal, EvenDealSharesAmongEveryRankThatCanSolve) {
  const ColumnDeal deal = deal_columns_evenly(7, {to_factorise(), factorised(), {}});
  EXPECT_EQ(deal.counts, (std::vector<std::size_t>{3, 2, 2, 0}));
  EXPECT_EQ(deal.factorise, (std::vector<bool>{false, true, false, false}));
}

TEST(ColumnDeal, BadTimesAreErrors) {
  EXPECT_THROW(deal_columns({4, 0.0, 0.0, {factorised()}}), Error);
  EXPECT_THROW(deal_columns({4, 0.1, -1.0, {factorised()}}), Error);
  EXPECT_THROW(deal_columns({4, std::numeric_limits<double>::quiet_NaN(), 0.0, {}}), Error);
  // A helper whose core's other work is not a time takes nothing.
  EXPECT_FALSE(deal_columns({40, 0.1, 0.0, {factorised(std::numeric_limits<double>::quiet_NaN())}}).dealt());
}

}  // namespace
}  // namespace hipfai::fem
