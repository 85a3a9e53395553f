#include "fem/column_deal.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hipfai::fem {

bool ColumnDeal::dealt() const {
  return std::any_of(counts.begin() + (counts.empty() ? 0 : 1), counts.end(),
                     [](std::size_t n) { return n > 0; });
}

ColumnDeal deal_columns(const ColumnDealRequest& request) {
  if (!(request.block_seconds > 0.0) || !std::isfinite(request.block_seconds))
    throw_error("fem: a column deal needs a block's time (> 0 s), got ", request.block_seconds);
  if (!(request.factorisation_seconds >= 0.0) || !std::isfinite(request.factorisation_seconds))
    throw_error("fem: a column deal needs the factorisation's time (>= 0 s), got ",
                request.factorisation_seconds);
  const std::size_t ranks = request.helpers.size() + 1;
  ColumnDeal deal;
  deal.counts.assign(ranks, 0);
  deal.factorise.assign(ranks, false);
  // The helpers that could take blocks, with their delay before the first.
  std::vector<std::pair<double, std::size_t>> candidates;  // (delay, rank)
  for (std::size_t h = 0; h < request.helpers.size(); ++h) {
    const ColumnDealHelper& helper = request.helpers[h];
    if (!helper.has_core || !(helper.busy_seconds >= 0.0) || !std::isfinite(helper.busy_seconds)) continue;
    if (helper.factorised)
      candidates.emplace_back(helper.busy_seconds, h + 1);
    else if (helper.may_factorise)
      candidates.emplace_back(helper.busy_seconds + request.factorisation_seconds, h + 1);
  }
  std::stable_sort(candidates.begin(), candidates.end());
  const double t = request.block_seconds;
  const double alone = static_cast<double>(request.blocks) * t;
  // The common finishing time with the k helpers of smallest delay; k shrinks until every one of
  // them starts before it.
  std::size_t k = candidates.size();
  double finish = alone;
  for (; k > 0; --k) {
    double delays = 0.0;
    for (std::size_t i = 0; i < k; ++i) delays += candidates[i].first;
    finish = (alone + delays) / static_cast<double>(k + 1);
    if (candidates[k - 1].first < finish) break;
  }
  std::size_t given = 0;
  for (std::size_t i = 0; i < k; ++i) {
    const auto [delay, rank] = candidates[i];
    const std::size_t n = static_cast<std::size_t>(std::floor((finish - delay) / t + 1e-9));
    deal.counts[rank] = std::min(n, request.blocks - given);
    given += deal.counts[rank];
    deal.factorise[rank] = deal.counts[rank] > 0 && !request.helpers[rank - 1].factorised;
  }
  deal.counts[0] = request.blocks - given;
  return deal;
}

ColumnDeal deal_columns_evenly(std::size_t blocks, const std::vector<ColumnDealHelper>& helpers) {
  std::vector<std::size_t> takers{0};
  for (std::size_t h = 0; h < helpers.size(); ++h) {
    if (helpers[h].factorised || helpers[h].may_factorise) takers.push_back(h + 1);
  }
  ColumnDeal deal;
  deal.counts.assign(helpers.size() + 1, 0);
  deal.factorise.assign(helpers.size() + 1, false);
  for (std::size_t i = 0; i < takers.size(); ++i) {
    const std::size_t rank = takers[i];
    deal.counts[rank] = blocks / takers.size() + (i < blocks % takers.size() ? 1 : 0);
    deal.factorise[rank] = rank > 0 && deal.counts[rank] > 0 && !helpers[rank - 1].factorised;
  }
  return deal;
}

}  // namespace hipfai::fem
