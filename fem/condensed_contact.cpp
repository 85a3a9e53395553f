#include "fem/condensed_contact.h"

#include "core/error.h"
#include "core/parallel.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace hipfai::fem {

void CondensedContact::begin_run(BodyCompliance& bodies, const ContactModel& model,
                                 const std::vector<SlaveNode>& nodes,
                                 const std::vector<dealii::Tensor<1, 3>>& translations,
                                 std::size_t n_threads) {
  n_threads_ = static_cast<int>(std::max<std::size_t>(1, n_threads));
  bodies_ = &bodies;
  model_ = &model;
  t0_ = translations;
  const std::size_t n_rigid = model.rigid_bodies.size();
  body_offset_.assign(bodies.n_bodies() + 1, 0);
  for (std::size_t b = 0; b < bodies.n_bodies(); ++b)
    body_offset_[b + 1] = body_offset_[b] + 3 * bodies.n_surface_nodes(b);
  n_surface_dofs_ = body_offset_.back();

  constraints_.assign(nodes.size(), Constraint());
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const SlaveNode& node = nodes[n];
    Constraint& constraint = constraints_[n];
    constraint.dgap_dt.assign(n_rigid, dealii::Tensor<1, 3>());
    constraint.slave_node = bodies.node_of_dof(node.dofs[0]);
    constraint.component = node.constrained_component;
    constraint.normal_component = node.normal[node.constrained_component];
    const auto term_of = [&](int p) -> Term& {
      for (Term& term : constraint.terms)
        if (term.node == p) return term;
      constraint.terms.push_back(
          {p, bodies.body_of_node(p), bodies.surface_index(p), dealii::Tensor<1, 3>(), {}});
      return constraint.terms.back();
    };
    term_of(constraint.slave_node).beta += node.normal;
    if (node.rigid_body >= 0) {
      constraint.dgap_dt[node.rigid_body] -= node.normal;
    } else {
      for (unsigned int c = 0; c < 3; ++c) {
        for (const auto& [dof, weight] : node.master[c])
          term_of(bodies.node_of_dof(dof)).beta[c] -= node.normal[c] * weight;
      }
    }
    // The liftings: u_p = R (sum_k M_pk R^T t_k + e_p) at a term's node p in body b (M_pk's
    // columns: the body-frame displacement for unit translations of its k-th bonded bone).
    double lifted_gap = 0.0;
    for (Term& term : constraint.terms) {
      if (term.surface < 0) {
        throw_error("fem: a contact constraint names a node off every contact surface");
      }
      const dealii::Tensor<2, 3>& r = bodies.rotation(term.body);
      term.local = dealii::transpose(r) * term.beta;
      lifted_gap += term.local * bodies.extra_lifting(term.body, term.surface);
      const std::vector<int>& lifted = bodies.bonded_rigid_bodies(term.body);
      for (std::size_t k = 0; k < lifted.size(); ++k) {
        dealii::Tensor<1, 3> mt_local;  // M_pk^T local
        for (unsigned int c = 0; c < 3; ++c)
          mt_local[c] = bodies.translation_lifting(term.body, k, c, term.surface) * term.local;
        constraint.dgap_dt[lifted[k]] += r * mt_local;
      }
    }
    constraint.base_gap = node.initial_gap + lifted_gap;
    for (std::size_t r = 0; r < n_rigid; ++r)
      constraint.base_gap += constraint.dgap_dt[r] * translations[r];
  }
  h_.assign(nodes.size(), {});
  w_set_.clear();
  w_values_.clear();
  directions_.clear();
  for (unsigned int b = 0; b < n_rigid; ++b) {
    const RigidBody& body = model.rigid_bodies[b];
    if (!body.load_controlled) continue;
    for (const dealii::Tensor<1, 3>& direction : body.free_directions)
      directions_.push_back({b, direction / direction.norm()});
  }
  bodies.lifting_reactions(n_rigid, a_, r0_);
  node_force_.assign(bodies.n_nodes(), dealii::Tensor<1, 3>());
}

namespace {

// target += w0 c0 + w1 c1 + w2 c2 over `size` entries: the three columns of a node in one pass
// over the target (a third of the memory traffic). The AVX2 clone, chosen at run time where the
// processor has it, does the same arithmetic in the same order four entries at a time (no fused
// multiply-add), so its sums are bit for bit the default clone's.
__attribute__((target_clones("avx2", "default"))) void add_weighted_columns(
    double* target, const double* c0, const double* c1, const double* c2, double w0, double w1,
    double w2, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) target[i] += w0 * c0[i] + w1 * c1[i] + w2 * c2[i];
}

}  // namespace

void CondensedContact::compute_h(std::size_t n) {
  std::vector<double>& out = h_[n];
  out.assign(n_surface_dofs_, 0.0);
  for (const Term& term : constraints_[n].terms) {
    const double* columns = bodies_->columns(term.node);
    const std::size_t size = 3 * bodies_->n_surface_nodes(term.body);
    add_weighted_columns(out.data() + body_offset_[term.body], columns, columns + size,
                         columns + 2 * size, term.local[0], term.local[1], term.local[2], size);
  }
}

std::vector<int> CondensedContact::column_nodes(const std::vector<bool>& active) const {
  std::vector<int> nodes;
  for (std::size_t n = 0; n < active.size(); ++n) {
    if (!active[n]) continue;
    for (const Term& term : constraints_[n].terms) nodes.push_back(term.node);
  }
  return nodes;
}

CondensedOutcome CondensedContact::solve(const std::vector<bool>& active,
                                         std::vector<dealii::Tensor<1, 3>>& translations,
                                         std::vector<double>& force, std::vector<double>& gap,
                                         dealii::ConditionalOStream& log) {
  const std::size_t n_rigid = translations.size();
  std::vector<std::size_t> set;
  for (std::size_t n = 0; n < active.size(); ++n) {
    if (!active[n]) continue;
    set.push_back(n);
    for (const Term& term : constraints_[n].terms) {
      if (!bodies_->columns(term.node)) {
        log << "fem: a compliance column the active set needs was not computed" << std::endl;
        return CondensedOutcome::kFailed;
      }
    }
  }
  const std::size_t m = set.size(), d = directions_.size();
  if (d > 0 && m == 0) return CondensedOutcome::kNoContact;  // nothing carries the load

  // h of the nodes new to the set (kept for the run), then W = B_A K^-1 B_A^T (lower triangle),
  // the active gaps at the current translations and their sensitivity to the free directions.
  // Each thread writes its own h and its own columns of W.
  std::vector<std::size_t> fresh;
  for (const std::size_t n : set)
    if (h_[n].empty()) fresh.push_back(n);
  // Neighbouring constraints share most of their columns, which stay cached from one to the
  // next (blocking the constraints over short row chunks was measured no faster).
  parallel_blocks(fresh.size(), n_threads_, 8, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) compute_h(fresh[k]);
  });
  // W's entries between constraints of the previous set are kept: h and B do not change within
  // a run, so they would come out the same. Only the rows and columns of newly active
  // constraints are computed (the sets are sorted, so the lower triangle maps to itself).
  std::vector<int> previous(constraints_.size(), -1);
  for (std::size_t k = 0; k < w_set_.size(); ++k) previous[w_set_[k]] = static_cast<int>(k);
  const std::size_t m_previous = w_set_.size();
  Eigen::MatrixXd w(m, m);
  parallel_blocks(m, n_threads_, 16, [&](std::size_t first, std::size_t last) {
    for (std::size_t j = first; j < last; ++j) {
      const std::vector<double>& hj = h_[set[j]];
      const int pj = previous[set[j]];
      for (std::size_t i = j; i < m; ++i) {
        const int pi = previous[set[i]];
        if (pj >= 0 && pi >= 0) {
          w(i, j) = w_values_[static_cast<std::size_t>(pj) * m_previous + static_cast<std::size_t>(pi)];
          continue;
        }
        double value = 0.0;
        for (const Term& term : constraints_[set[i]].terms) {
          const double* x = hj.data() + body_offset_[term.body] + 3 * term.surface;
          value += term.local[0] * x[0] + term.local[1] * x[1] + term.local[2] * x[2];
        }
        w(i, j) = value;
      }
    }
  });
  w_set_ = set;
  w_values_.assign(w.data(), w.data() + m * m);
  const auto gap_at = [&](std::size_t n, const std::vector<dealii::Tensor<1, 3>>& t) {
    double value = constraints_[n].base_gap;
    for (std::size_t r = 0; r < n_rigid; ++r)
      value += constraints_[n].dgap_dt[r] * (t[r] - t0_[r]);
    return value;
  };
  Eigen::MatrixXd rhs(m, 1 + d);
  for (std::size_t i = 0; i < m; ++i) {
    rhs(i, 0) = gap_at(set[i], translations);
    for (std::size_t k = 0; k < d; ++k)
      rhs(i, 1 + k) = constraints_[set[i]].dgap_dt[directions_[k].body] * directions_[k].direction;
  }
  Eigen::MatrixXd x(m, 1 + d);
  if (m > 0) {
    const Eigen::LLT<Eigen::MatrixXd> llt(w);
    if (llt.info() != Eigen::Success) {
      log << "fem: the condensed contact matrix is not positive definite" << std::endl;
      return CondensedOutcome::kFailed;
    }
    x = llt.solve(rhs);
  }
  // The translations along the free directions: the Schur complement on s.
  Eigen::VectorXd s = Eigen::VectorXd::Zero(d);
  if (d > 0) {
    Eigen::MatrixXd sensitivity(d, d);
    Eigen::VectorXd mismatch(d);
    for (std::size_t i = 0; i < d; ++i) {
      const Direction& row = directions_[i];
      dealii::Tensor<1, 3> transmitted = r0_[row.body];
      for (std::size_t r = 0; r < n_rigid; ++r) transmitted += a_[row.body][r] * translations[r];
      mismatch(i) = (model_->rigid_bodies[row.body].force_n - transmitted) * row.direction;
      mismatch(i) -= rhs.col(1 + i).dot(x.col(0));
      for (std::size_t j = 0; j < d; ++j) {
        const Direction& column = directions_[j];
        sensitivity(i, j) = rhs.col(1 + i).dot(x.col(1 + j)) +
                            row.direction * (a_[row.body][column.body] * column.direction);
      }
    }
    if (!(sensitivity.diagonal().cwiseAbs().maxCoeff() > 0.0)) return CondensedOutcome::kNoContact;
    s = sensitivity.fullPivLu().solve(mismatch);
    for (std::size_t k = 0; k < d; ++k)
      translations[directions_[k].body] += s(k) * directions_[k].direction;
  }
  Eigen::VectorXd lambda(m);
  if (m > 0) lambda = -x.col(0) - x.rightCols(d) * s;

  // Displacements of the surface dofs (body frames), every node's gap and the nodal forces.
  std::vector<double> u(n_surface_dofs_, 0.0);
  parallel_blocks(n_surface_dofs_, n_threads_, 1024, [&](std::size_t first, std::size_t last) {
    for (std::size_t j = 0; j < m; ++j) {
      const double* hj = h_[set[j]].data();
      const double l = lambda(j);
      for (std::size_t i = first; i < last; ++i) u[i] += l * hj[i];
    }
  });
  gap.assign(constraints_.size(), 0.0);
  for (std::size_t n = 0; n < constraints_.size(); ++n) {
    double value = gap_at(n, translations);
    for (const Term& term : constraints_[n].terms) {
      const double* y = u.data() + body_offset_[term.body] + 3 * term.surface;
      value += term.local[0] * y[0] + term.local[1] * y[1] + term.local[2] * y[2];
    }
    gap[n] = value;
  }
  std::fill(node_force_.begin(), node_force_.end(), dealii::Tensor<1, 3>());
  for (std::size_t j = 0; j < m; ++j) {
    for (const Term& term : constraints_[set[j]].terms) node_force_[term.node] += lambda(j) * term.beta;
  }
  force.assign(constraints_.size(), 0.0);
  for (std::size_t n = 0; n < constraints_.size(); ++n) {
    const Constraint& constraint = constraints_[n];
    force[n] = node_force_[constraint.slave_node][constraint.component] / constraint.normal_component;
  }
  return CondensedOutcome::kSolved;
}

}  // namespace hipfai::fem
