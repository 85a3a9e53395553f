#include "fem/active_set_strategy.h"

#include <algorithm>

namespace hipfai::fem {

using dealii::types::global_dof_index;

void evaluate_nodes(const std::vector<SlaveNode>& nodes, const Linearization& state,
                    const std::vector<dealii::Tensor<1, 3>>& translations,
                    std::vector<double>& force, std::vector<double>& gap) {
  force.assign(nodes.size(), 0.0);
  gap.assign(nodes.size(), 0.0);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const SlaveNode& node = nodes[n];
    const unsigned int k = node.constrained_component;
    // The condensed equations of the free slave components make the nodal force parallel to
    // n, so its k-th component alone gives the normal force.
    force[n] = state.internal_force[node.dofs[k]] / node.normal[k];
    double g = node.initial_gap;
    for (unsigned int c = 0; c < 3; ++c) {
      double master = 0.0;
      if (node.rigid_body >= 0) {
        master = translations[node.rigid_body][c];
      } else {
        for (const auto& [dof, weight] : node.master[c]) master += weight * state.displacement[dof];
      }
      g += node.normal[c] * (state.displacement[node.dofs[c]] - master);
    }
    gap[n] = g;
  }
}

void ActiveSetStrategy::begin_run(const ActiveSetSettings& settings, double gap_tolerance) {
  settings_ = settings;
  gap_tolerance_ = gap_tolerance;
  tried_.clear();
  least_index_rule_ = false;
}

std::vector<bool> ActiveSetStrategy::initial(const std::vector<SlaveNode>& nodes,
                                             const std::vector<dealii::Tensor<1, 3>>& translations,
                                             global_dof_index n_dofs) const {
  // With the last converged displacement at hand (the previous step of a motion: same mesh, same
  // dof numbering), the gap of every node at the new pose is predicted from it, the new pose's
  // contact geometry and the current translations: the nodes it closes start active. The
  // displacement is not rotated with the femur (a few degrees per step turn a 0.1 mm
  // displacement by a few micrometres), so this is a prediction, the active-set loop decides.
  // Without one, a node starts as it ended the last converged run (warm start) or, new, closed
  // when its geometric gap is.
  std::vector<bool> active(nodes.size(), false);
  std::vector<double> predicted(nodes.size());
  const bool predict = settings_.warm_start && converged_solution_.size() == n_dofs;
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const SlaveNode& node = nodes[n];
    predicted[n] = node.initial_gap;
    if (node.rigid_body >= 0) predicted[n] -= translations[node.rigid_body] * node.normal;
    if (predict) {
      for (unsigned int c = 0; c < 3; ++c) {
        double master = 0.0;
        for (const auto& [dof, weight] : node.master[c])
          master += weight * converged_solution_[dof];
        predicted[n] += node.normal[c] * (converged_solution_[node.dofs[c]] - master);
      }
    }
    const auto it = settings_.warm_start ? converged_active_.find({node.pair, node.dofs[0]})
                                         : converged_active_.end();
    const bool was_active = it != converged_active_.end() && it->second;
    active[n] = (it != converged_active_.end() && !predict)
                    ? was_active
                    : was_active || predicted[n] <= gap_tolerance_;
  }
  // Nothing closed: the least open node starts closed. A body under a load (a free direction)
  // cannot be balanced without a contact, and where nothing presses it the loop opens it again.
  if (!nodes.empty() && std::none_of(active.begin(), active.end(), [](bool a) { return a; }))
    active[std::min_element(predicted.begin(), predicted.end()) - predicted.begin()] = true;
  one_constraint_per_node(nodes, active, predicted);
  return active;
}

void ActiveSetStrategy::one_constraint_per_node(const std::vector<SlaveNode>& nodes,
                                                std::vector<bool>& set,
                                                const std::vector<double>& gap,
                                                const std::vector<bool>* current) const {
  // A slave node can belong to several pairs (the acetabular cartilage and the labrum meet both
  // the femoral cartilage and, past its edge, the bone of the head-neck). Two constraints on one
  // node, each eliminating one of its components in terms of the others, can form a cycle that
  // the constraint closure cannot resolve, and where the two masters meet (the cartilage edge
  // on the bone) their normals are nearly parallel, so the pair would be singular anyway. Each
  // node is held by the master it penetrates most (smallest gap; ties: the earlier pair), which
  // leaves the other master in front of it. With `current` (the active set just solved), a node
  // keeps the master that holds it now: where the two masters meet, the gaps of a held node to
  // them trade places from one solve to the next, and the plain rule would hand the node back and
  // forth forever (an active-set 2-cycle of the cam against the cartilage's edge and the labrum)
  // unless the other master is penetrated by more than holder_switch_mm beyond it.
  std::map<global_dof_index, std::size_t> holder;
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (!set[n]) continue;
    const auto [it, inserted] = holder.try_emplace(nodes[n].dofs[0], n);
    if (inserted) continue;
    const std::size_t other = it->second;
    const double margin = settings_.holder_switch_mm;
    const bool keep_n = current != nullptr && (*current)[n] && !(*current)[other] &&
                        !(gap[other] < gap[n] - margin);
    const bool keep_other = current != nullptr && (*current)[other] && !(*current)[n] &&
                            !(gap[n] < gap[other] - margin);
    if (keep_n || (!keep_other && gap[n] < gap[other])) {
      set[other] = false;
      it->second = n;
    } else {
      set[n] = false;
    }
  }
}

std::vector<bool> ActiveSetStrategy::next(unsigned int iteration, bool load_controlled,
                                          const std::vector<SlaveNode>& nodes,
                                          const std::vector<bool>& active,
                                          const std::vector<double>& force,
                                          const std::vector<double>& gap,
                                          dealii::ConditionalOStream& log) {
  // Load control starts from the touching nodes only, so the first balance overshoots the
  // translation and the plain rule would activate the whole geometric overlap, which then
  // shrinks one ring per iteration. For smooth profiles the elastic contact area is about
  // half the geometric overlap (Hertz: a^2 = R d against 2 R d), i.e. the nodes penetrating
  // by more than half the maximum: enter only those after the first iteration. Later
  // iterations use the exact rule, so the converged set is unaffected.
  double enter_threshold = gap_tolerance_;
  if (iteration == 1 && load_controlled) {
    double deepest = 0.0;
    for (std::size_t n = 0; n < nodes.size(); ++n) deepest = std::max(deepest, -gap[n]);
    enter_threshold = std::max(gap_tolerance_, 0.5 * deepest);
  }
  std::vector<bool> next_set(nodes.size());
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    next_set[n] = active[n] ? force[n] > 0.0 : gap[n] < -enter_threshold;
  }
  one_constraint_per_node(nodes, next_set, gap, &active);
  tried_.insert(active);
  // A set the plain rule returns to is a cycle; the set just solved again is convergence.
  if (!least_index_rule_ && next_set != active && tried_.count(next_set) > 0) {
    least_index_rule_ = true;
    log << "fem: active-set cycle detected at iteration " << iteration
        << "; one change per iteration from here" << std::endl;
  }
  if (least_index_rule_) {
    std::vector<bool> single = active;
    for (std::size_t n = 0; n < nodes.size(); ++n) {
      if (next_set[n] != active[n]) {
        single[n] = next_set[n];
        break;
      }
    }
    one_constraint_per_node(nodes, single, gap, &active);
    next_set = std::move(single);
  }
  return next_set;
}

void ActiveSetStrategy::remember_converged(const std::vector<SlaveNode>& nodes,
                                           const std::vector<bool>& active,
                                           const dealii::Vector<double>& displacement) {
  converged_active_.clear();
  for (std::size_t n = 0; n < nodes.size(); ++n)
    converged_active_[{nodes[n].pair, nodes[n].dofs[0]}] = active[n];
  converged_solution_ = displacement;
}

}  // namespace hipfai::fem
