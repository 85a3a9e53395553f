// hipfai — the contact problem of one active set condensed onto its contact constraints and the
// free translations (the substructured solver's per-step work).
//
// With each body factorised once (fem/body_compliance.h), the displacement is
//   u = u_lift(t) + K^-1 B^T lambda,
// u_lift the bonded boundaries' data carried into the bodies, t the rigid translations, B the
// rows of the contact constraints (b_n . u + g0_n = gap, the same coefficients as the monolithic
// path's: the slave node's normal, the master nodes' mortar weights times the normal) and
// lambda >= 0 their normal forces. For the active set A and the free translation directions D of
// the load-controlled bones (t = t0 + D s), the contact problem is the small symmetric system
//   [ W       C_A D   ] [ lambda ]   [ -g_A(t0)               ]     W = B_A K^-1 B_A^T
//   [ D^T C_A^T  -D^T A D ] [ s ]  = [ -D^T (F - A t0 - r0)   ]     C = d gap / d t
// (gaps of the active nodes closed, the force each bone transmits, A t + r0 - C^T lambda, equal
// to its load along D), solved by the Schur complement on s. The same discrete problem as the
// monolithic path (fem/linear_solver.h), so the same answers to round-off; only the unknowns
// differ: |A| + |D| instead of every dof.
//
// W is assembled from the bodies' compliance columns: for an active node n,
//   h_n = K0^-1 B_n^T (body frames, at every contact-surface dof),
// kept across the iterations of a run; W_mn = B_m h_n, and the displacement of every surface
// dof is sum_n lambda_n h_n, from which the gaps of all contact nodes follow.
#pragma once

#include "fem/body_compliance.h"
#include "fem/contact_model.h"
#include "fem/mortar_coupling.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/tensor.h>

#include <vector>

namespace hipfai::fem {

// The outcome of one active set.
enum class CondensedOutcome {
  kSolved,       // forces, gaps and translations of the set
  kNoContact,    // the active set carries no load along a free direction
  kFailed,       // a compliance solve failed or W is not positive definite
};

class CondensedContact {
 public:
  // A run's contact nodes: their constraint coefficients, the liftings at their nodes and the
  // translations' effect on their gaps. `bodies` must have begun the run (and be factorised);
  // `translations`: the rigid bodies' current translations.
  // `n_threads` share the dense work of each active set.
  void begin_run(BodyCompliance& bodies, const ContactModel& model,
                 const std::vector<SlaveNode>& nodes,
                 const std::vector<dealii::Tensor<1, 3>>& translations, std::size_t n_threads);

  // The nodes whose compliance columns the active set needs (BodyCompliance::ensure_columns
  // must have them before solve).
  std::vector<int> column_nodes(const std::vector<bool>& active) const;

  // Solves the active set: on kSolved, `translations` move to the balance (load-controlled
  // bones along their free directions), `force` and `gap` hold every node's normal force
  // (compressive > 0, as the monolithic path reads it: the force at the node's constrained dof
  // over its normal component) and gap (negative: penetration).
  CondensedOutcome solve(const std::vector<bool>& active,
                         std::vector<dealii::Tensor<1, 3>>& translations,
                         std::vector<double>& force, std::vector<double>& gap,
                         dealii::ConditionalOStream& log);

  // The contact forces of the last solved set at every node of the system (global frame), for
  // BodyCompliance::recover.
  const std::vector<dealii::Tensor<1, 3>>& node_forces() const { return node_force_; }

 private:
  // One node's share of a constraint: its coefficients (global and body frame).
  struct Term {
    int node;                    // index into BodyCompliance's nodes
    int body;                    // its body
    int surface;                 // its surface index
    dealii::Tensor<1, 3> beta;   // coefficients of its displacement (global frame)
    dealii::Tensor<1, 3> local;  // the same in its body's frame
  };
  struct Constraint {
    std::vector<Term> terms;
    std::vector<dealii::Tensor<1, 3>> dgap_dt;  // per rigid body
    double base_gap = 0.0;                      // at t0, no contact force
    int slave_node = -1;
    unsigned int component = 0;                 // constrained component
    double normal_component = 1.0;
  };
  void compute_h(std::size_t n);  // h_[n] = K0^-1 B_n^T over all surface dofs

  BodyCompliance* bodies_ = nullptr;
  const ContactModel* model_ = nullptr;
  std::vector<Constraint> constraints_;
  std::vector<std::size_t> body_offset_;  // into the concatenated surface dofs
  std::size_t n_surface_dofs_ = 0;
  int n_threads_ = 1;
  std::vector<dealii::Tensor<1, 3>> t0_;
  std::vector<std::vector<double>> h_;    // per node, empty until needed
  // The last solved set's W (column-major, m x m) and its constraints, for the next iteration.
  std::vector<std::size_t> w_set_;
  std::vector<double> w_values_;
  std::vector<dealii::Tensor<1, 3>> node_force_;
  // Free directions of the load-controlled bones.
  struct Direction {
    unsigned int body;
    dealii::Tensor<1, 3> direction;
  };
  std::vector<Direction> directions_;
  std::vector<std::vector<dealii::Tensor<2, 3>>> a_;
  std::vector<dealii::Tensor<1, 3>> r0_;
};

}  // namespace hipfai::fem
