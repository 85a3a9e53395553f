// hipfai tests — two contact solutions that must be the same to round-off (1e-9 relative), e.g.
// one solver setting against another.
#pragma once

#include "fem/contact_problem.h"
#include "fem/hip_fe_model.h"

#include <gtest/gtest.h>

#include <cstddef>

namespace hipfai::fem {

// Peak pressure, contact area, femur translation and the peak von Mises of every tissue.
inline void expect_same_solution(const ContactResult& result, const ContactResult& reference) {
  EXPECT_NEAR(result.peaks.max_pressure_mpa, reference.peaks.max_pressure_mpa, 1e-9 * reference.peaks.max_pressure_mpa);
  EXPECT_NEAR(result.peaks.contact_area_mm2, reference.peaks.contact_area_mm2, 1e-9 * reference.peaks.contact_area_mm2);
  EXPECT_LT((result.rigid_translation_mm[kFemurBody] - reference.rigid_translation_mm[kFemurBody]).norm(),
            1e-9 * reference.rigid_translation_mm[kFemurBody].norm());
  ASSERT_EQ(result.peaks.max_von_mises_mpa.size(), reference.peaks.max_von_mises_mpa.size());
  for (std::size_t b = 0; b < reference.peaks.max_von_mises_mpa.size(); ++b) {
    EXPECT_NEAR(result.peaks.max_von_mises_mpa[b], reference.peaks.max_von_mises_mpa[b], 1e-9 * reference.peaks.max_von_mises_mpa[b]);
  }
}

// The same, node by node too: the same active set, pressures and gaps.
inline void expect_same_nodes_and_solution(const ContactResult& result, const ContactResult& reference) {
  ASSERT_EQ(result.nodes.size(), reference.nodes.size());
  for (std::size_t n = 0; n < result.nodes.size(); ++n) {
    ASSERT_EQ(result.nodes[n].active, reference.nodes[n].active) << "node " << n;
    EXPECT_NEAR(result.nodes[n].pressure_mpa, reference.nodes[n].pressure_mpa, 1e-9 * reference.peaks.max_pressure_mpa)
        << "node " << n;
    EXPECT_NEAR(result.nodes[n].gap_mm, reference.nodes[n].gap_mm, 1e-12) << "node " << n;
  }
  expect_same_solution(result, reference);
}

}  // namespace hipfai::fem
