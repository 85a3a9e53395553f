// hipfai — post-processing of a solved contact state into a ContactResult: the contact nodes'
// forces, pressures and gaps, the per-pair forces, the pressure and von Mises summaries, and
// the mesh-objective (ball-averaged) peaks of fem/peak_measures.h.
#pragma once

#include "fem/contact_result.h"
#include "fem/elastic_system.h"
#include "fem/mortar_coupling.h"

#include <deal.II/lac/vector.h>

#include <cstddef>
#include <vector>

namespace hipfai::fem {

// Fills result.nodes, pair_force_n (n_pairs), max_penetration_mm, the pressure summaries and the
// ball-averaged pressure peak (radius_mm). force and gap per node as evaluate_nodes gives them;
// empty when no state was solved (then no node carries a force and the gaps are the initial
// ones).
void summarize_contact(const std::vector<SlaveNode>& nodes, const std::vector<bool>& active,
                       const std::vector<double>& force, const std::vector<double>& gap,
                       std::size_t n_pairs, double radius_mm, ContactResult& result);

// Fills the per-body von Mises summaries: maximum, nearest-rank 95th percentile, ball-averaged
// peak (radius_mm) and its centre; the bodies on `n_threads` threads (the same numbers).
void summarize_stress(const VonMisesField& field, double radius_mm, ContactResult& result,
                      std::size_t n_threads = 1);

// Replaces every non-finite number of the result and of the displacement by 0; false when there
// was one.
bool make_finite(ContactResult& result, dealii::Vector<double>& displacement);

}  // namespace hipfai::fem
