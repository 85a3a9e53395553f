// hipfai — the result of one contact solve (fem::ContactProblem::run) and of a motion step
// (fem::run_motion): status, solver statistics, per-node contact data and post-processed peaks.
// Units: mm, N, MPa.
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <vector>

namespace hipfai::fem {

// kNonFinite: a NaN or infinity appeared in the solution or a summary (the numbers of such a
// result are replaced by 0, so no NaN ever leaves the solver).
enum class ContactStatus {
  kConverged,
  kActiveSetNotConverged,
  kLinearSolverFailed,
  kNoContact,
  kNonFinite
};
const char* to_string(ContactStatus status);

// One contact node of a slave surface after the solve.
struct ContactNode {
  unsigned int pair = 0;         // index into ContactModel::contact_pairs
  dealii::Point<3> position_mm;  // reference position
  dealii::Tensor<1, 3> normal;   // master normal at the closest point (into the slave)
  double area_mm2 = 0.0;         // integral of the node's shape function over the slave surface
  double force_n = 0.0;          // normal contact force (compressive > 0)
  double pressure_mpa = 0.0;     // force / area
  double gap_mm = 0.0;           // after the solve; negative = penetration
  bool active = false;           // in the converged (or last) active set
};

// How the solve went. For a motion step (fem/motion_solver.h) the counters and the wall time
// sum over all its attempts.
struct SolveStatistics {
  unsigned int n_cells = 0;                // active cells, all ranks
  unsigned long n_dofs = 0;                // degrees of freedom
  unsigned int n_ranks = 1;                // MPI ranks
  unsigned int active_set_iterations = 0;  // active sets solved
  unsigned int linear_solves = 0;          // right-hand sides solved
  // Substructured: compliance columns this rank solved (on several ranks a share of the columns
  // in linear_solves; with the wall time, what differs between the ranks).
  unsigned int rank_columns = 0;
  unsigned int linear_iterations = 0;      // CG iterations (direct: nonzero right-hand sides)
  unsigned int factorisations = 0;         // direct solver: Cholesky factorisations
  unsigned int low_rank_updates = 0;  // direct solver: active sets solved by a bordered correction
  double wall_time_s = 0.0;           // wall time of the solve (s)
  // The contact nodes came from the search run beside the previous run (ContactProblem::expect_next).
  bool searched_ahead = false;
  // Set by run_motion: solves the step was split into (1: none) and failed attempts that were
  // cut back.
  unsigned int sub_steps = 1;
  unsigned int cutbacks = 0;
};

// Post-processed summaries and peaks of the solution.
struct ContactPeaks {
  double max_penetration_mm = 0.0;  // largest penetration over all contact nodes (0: none)
  // Summaries over the active contact nodes (all pairs).
  double contact_area_mm2 = 0.0;   // sum of the active nodes' areas
  double max_pressure_mpa = 0.0;   // largest nodal pressure
  double mean_pressure_mpa = 0.0;  // total normal force / contact area
  // Von Mises stress per body (index into ContactModel::bodies), over the Gauss points: the
  // largest and the nearest-rank 95th percentile.
  std::vector<double> max_von_mises_mpa;
  std::vector<double> p95_von_mises_mpa;
  // Mesh-objective peaks (fem/peak_measures.h): the largest mean over a ball of radius
  // ContactOptions::peak_average_radius_mm, and the ball's centre (hip frame, the step's pose,
  // undeformed). Von Mises per body, JxW-weighted over the body's Gauss points; pressure
  // area-weighted over the active slave nodes of all pairs (= contact force / contact area
  // inside the ball). 0 (and the origin) where there are no samples.
  double peak_average_radius_mm = 0.0;                            // the radius used
  std::vector<double> ball_peak_von_mises_mpa;                    // per body
  std::vector<dealii::Point<3>> ball_peak_von_mises_position_mm;  // per body
  double ball_peak_pressure_mpa = 0.0;
  dealii::Point<3> ball_peak_pressure_position_mm;
  // The node of max_pressure_mpa (same frame) and the contact pair of that node and of the ball
  // peak's centre (index into ContactModel::contact_pairs; -1: no active node).
  dealii::Point<3> max_pressure_position_mm;
  int max_pressure_pair = -1;
  int ball_peak_pressure_pair = -1;
};

struct ContactResult {
  ContactStatus status = ContactStatus::kNoContact;  // converged, or why not
  SolveStatistics statistics;                        // counters and wall time
  // Per contact node of all pairs (pair by pair), per pair and per rigid body.
  std::vector<ContactNode> nodes;
  std::vector<dealii::Tensor<1, 3>> pair_force_n;          // force on the slave bodies, per pair
  std::vector<dealii::Tensor<1, 3>> rigid_translation_mm;  // per rigid body: prescribed or balanced
  ContactPeaks peaks;                                      // summaries and peaks
};

}  // namespace hipfai::fem
