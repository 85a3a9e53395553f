// hipfai — what `estimator refine` prints and writes: the candidates with their uncertainty, the
// picked ones ranked.
#pragma once

#include "studies/estimator_refine.h"

#include <string>

namespace hipfai::studies {

// refine.csv's text: "hip,score,rank" (rank 0 = not picked), one row per candidate, folder order.
std::string refine_csv(const RefineResult& result);

// The picked candidates, least certain first, one line each ("1  train_004  score 3.21"), after a
// line naming the criterion and how many candidates were compared.
std::string refine_summary(const RefineResult& result, const RefineOptions& options);

// The refinement loop's rounds (rounds.csv): round, training_hips, added (';'-separated folder
// names), failed, fe_s, seconds, then held_out_<method>_case1 / _case2 (mean error %, empty
// without a held-out set).
std::string refine_rounds_csv(const RefineLoopResult& result);

// One line per round: "round 2: 35 hips (+5), held-out error case 1 / case 2: depth_nn 2.1 / 3.9 %, ...".
std::string refine_rounds_summary(const RefineLoopResult& result);

}  // namespace hipfai::studies
