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

}  // namespace hipfai::studies
