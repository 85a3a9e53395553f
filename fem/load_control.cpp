#include "fem/load_control.h"

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <algorithm>
#include <cmath>

namespace hipfai::fem {

std::vector<dealii::Tensor<1, 3>> transmitted_force(std::size_t n_rigid_bodies,
                                                    const std::vector<BondedDof>& bonded_dofs,
                                                    const std::vector<SlaveNode>& nodes,
                                                    const std::vector<bool>& active,
                                                    const Linearization& state) {
  std::vector<dealii::Tensor<1, 3>> force(n_rigid_bodies);
  for (const BondedDof& bonded : bonded_dofs) {
    if (bonded.rigid_body >= 0)
      force[bonded.rigid_body][bonded.component] += state.internal_force[bonded.dof];
  }
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const SlaveNode& node = nodes[n];
    if (node.rigid_body < 0 || !active[n]) continue;
    const double normal_force = state.internal_force[node.dofs[node.constrained_component]] /
                                node.normal[node.constrained_component];
    force[node.rigid_body] += normal_force * node.normal;
  }
  return force;
}

LoadControl::LoadControl(const ContactModel& model) {
  for (unsigned int b = 0; b < model.rigid_bodies.size(); ++b) {
    const RigidBody& body = model.rigid_bodies[b];
    if (!body.load_controlled) continue;
    for (const dealii::Tensor<1, 3>& direction : body.free_directions) {
      directions_.push_back({b, direction / direction.norm()});
    }
  }
}

std::vector<std::vector<dealii::Tensor<1, 3>>> LoadControl::probe_translations(
    const std::vector<dealii::Tensor<1, 3>>& translations) const {
  std::vector<std::vector<dealii::Tensor<1, 3>>> sets = {translations};
  for (const FreeDirection& free : directions_) {
    sets.push_back(translations);
    sets.back()[free.body] += free.direction;
  }
  return sets;
}

bool LoadControl::balance(const ContactModel& model, const std::vector<BondedDof>& bonded_dofs,
                          const std::vector<SlaveNode>& nodes, const std::vector<bool>& active,
                          std::vector<Linearization>& probes,
                          std::vector<dealii::Tensor<1, 3>>& translations,
                          Linearization& state) const {
  const std::size_t m = directions_.size();
  const std::size_t n_rigid = model.rigid_bodies.size();
  const Linearization base = std::move(probes.front());
  probes.erase(probes.begin());
  const auto base_force = transmitted_force(n_rigid, bonded_dofs, nodes, active, base);
  dealii::FullMatrix<double> sensitivity(m, m);
  dealii::Vector<double> mismatch(m);
  for (std::size_t j = 0; j < m; ++j) {
    const auto probe_force = transmitted_force(n_rigid, bonded_dofs, nodes, active, probes[j]);
    for (std::size_t i = 0; i < m; ++i) {
      const FreeDirection& row = directions_[i];
      sensitivity(i, j) = (probe_force[row.body] - base_force[row.body]) * row.direction;
    }
  }
  for (std::size_t i = 0; i < m; ++i) {
    const FreeDirection& row = directions_[i];
    mismatch[i] = (model.rigid_bodies[row.body].force_n - base_force[row.body]) * row.direction;
  }
  double scale = 0.0;
  for (std::size_t i = 0; i < m; ++i) scale = std::max(scale, std::abs(sensitivity(i, i)));
  if (!(scale > 0.0)) return false;
  sensitivity.gauss_jordan();
  dealii::Vector<double> step(m);
  sensitivity.vmult(step, mismatch);
  state = base;
  for (std::size_t j = 0; j < m; ++j) {
    translations[directions_[j].body] += step[j] * directions_[j].direction;
    state.displacement.add(step[j], probes[j].displacement);
    state.displacement.add(-step[j], base.displacement);
    for (std::size_t d = 0; d < state.internal_force.size(); ++d) {
      state.internal_force[d] += step[j] * (probes[j].internal_force[d] - base.internal_force[d]);
    }
  }
  return true;
}

}  // namespace hipfai::fem
