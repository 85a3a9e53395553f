// hipfai — the primal-dual active set method for the contact constraints.
//
// For a fixed active set the problem is linear; the active set itself is found by the
// primal-dual active set method (a semismooth Newton method for this linear complementarity
// problem): a node leaves the set when its contact force is tensile and enters it when it
// penetrates. A set the plain rule returns to is a cycle: from there on one change per iteration,
// the lowest-numbered node first (Murty's least-index rule, which ends for the positive definite
// systems of linear elastic contact). A slave node on several masters is held by one of them
// (one_constraint_per_node). Between runs (the steps of a motion) the converged set and
// displacement are kept and start the next run (warm start).
#pragma once

#include "fem/elastic_system.h"
#include "fem/mortar_coupling.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>
#include <deal.II/lac/vector.h>

#include <limits>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace hipfai::fem {

// Settings of the strategy (ContactOptions has them).
struct ActiveSetSettings {
  // A node held by one master switches to another only when that one is penetrated more by
  // this much (mm); see ContactOptions::holder_switch_mm.
  double holder_switch_mm = std::numeric_limits<double>::infinity();
  bool warm_start = true;  // start from the last converged run's set and displacement
};

// Normal contact force (compressive > 0) and gap (negative: penetration) of every node in
// `state`, with the rigid bodies at `translations`.
void evaluate_nodes(const std::vector<SlaveNode>& nodes, const Linearization& state,
                    const std::vector<dealii::Tensor<1, 3>>& translations,
                    std::vector<double>& force, std::vector<double>& gap);

class ActiveSetStrategy {
 public:
  // A new run with these nodes; gap_tolerance: gaps below it count as closed (mm).
  void begin_run(const ActiveSetSettings& settings, double gap_tolerance);
  // The starting set: predicted from the last converged displacement when there is one of the
  // same dof layout (n_dofs), else the last converged set, else the geometric overlap; never
  // empty (with every node open, the least open one starts closed).
  std::vector<bool> initial(const std::vector<SlaveNode>& nodes,
                            const std::vector<dealii::Tensor<1, 3>>& translations,
                            dealii::types::global_dof_index n_dofs) const;
  // The set after `active` from the solved forces and gaps. iteration counts from 1;
  // load_controlled: the first iteration enters only the deeper half of the overlap (see .cpp).
  // Reports a detected cycle on `log`.
  std::vector<bool> next(unsigned int iteration, bool load_controlled,
                         const std::vector<SlaveNode>& nodes, const std::vector<bool>& active,
                         const std::vector<double>& force, const std::vector<double>& gap,
                         dealii::ConditionalOStream& log);
  // Keeps a converged run's set and displacement for the next run's start.
  void remember_converged(const std::vector<SlaveNode>& nodes, const std::vector<bool>& active,
                          const dealii::Vector<double>& displacement);

  // One constraint per slave node in `set`: a node on several masters keeps the one it
  // penetrates most (ties: the earlier pair), or, given the set just solved (`current`), the one
  // holding it unless another is penetrated more by over holder_switch_mm.
  void one_constraint_per_node(const std::vector<SlaveNode>& nodes, std::vector<bool>& set,
                               const std::vector<double>& gap,
                               const std::vector<bool>* current = nullptr) const;

 private:
  ActiveSetSettings settings_;
  double gap_tolerance_ = 0.0;
  std::set<std::vector<bool>> tried_;  // active sets already solved in this run
  bool least_index_rule_ = false;
  // Active set of the last converged run, keyed by (pair, x-component dof of the slave node).
  std::map<std::pair<unsigned int, dealii::types::global_dof_index>, bool> converged_active_;
  dealii::Vector<double> converged_solution_;  // displacement of the last converged run
};

}  // namespace hipfai::fem
