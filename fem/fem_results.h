// hipfai — per-step results of an FE motion, written to HDF5.
//
// Layout (version 3; every dataset has a "unit" attribute, "1" for counts). Documented with
// examples in docs/results-layout.md; keep the two in step.
//   /                       attributes: layout_version = 3, bodies (names joined by ';'),
//                                       code_version, units
//   /steps/status                 int[n]          0 converged, 1 active set not converged,
//                                                 2 linear solver failed, 3 no contact,
//                                                 4 non-finite numbers (replaced by 0)
//   /steps/active_set_iterations  int[n]          Newton (semismooth active-set) iterations,
//                                                 summed over sub-steps and failed attempts
//   /steps/linear_solves          int[n]          likewise
//   /steps/linear_iterations      int[n]          CG iterations (1 per direct solve), likewise
//   /steps/sub_steps              int[n]          solves the step was split into (1: no cutback)
//   /steps/cutbacks               int[n]          failed attempts that were halved
//   /steps/n_cells, n_dofs        int[n], double[n]  mesh size of the solve
//   /steps/wall_time_s            double[n]       s, all attempts of the step
//   /steps/rotation               double[n][3][3] femur rotation about the HJC (row-major R)
//   /steps/applied_force_n        double[n][3]    N, joint reaction applied by the femur
//   /steps/femur_translation_mm   double[n][3]    mm
//   /steps/contact_resultant_n    double[n][3]    N, contact force on the slave surfaces
//   /steps/max_pressure_mpa, mean_pressure_mpa  double[n]  MPa (mean = force / area)
//   /steps/contact_area_mm2       double[n]       mm^2
//   /steps/max_penetration_mm     double[n]       mm
//   /steps/max_von_mises_mpa      double[n][bodies] MPa, over Gauss points
//   /steps/p95_von_mises_mpa      double[n][bodies] MPa, nearest-rank 95th percentile
//   /steps/max_pressure_position_mm  double[n][3]  mm, node of max_pressure_mpa
//   /steps/peak_average_radius_mm    double[n]     mm, ball radius of the ball_peak_* values
//   /steps/ball_peak_von_mises_mpa   double[n][bodies] MPa, largest JxW-weighted mean over a
//                                                 ball (fem/peak_measures.h), per body
//   /steps/ball_peak_von_mises_position_mm  double[n][bodies][3] mm, that ball's centre
//   /steps/ball_peak_pressure_mpa    double[n]     MPa, largest area-weighted mean of the nodal
//                                                 pressure over a ball (active slave nodes)
//   /steps/ball_peak_pressure_position_mm   double[n][3] mm, that ball's centre
// (Positions: hip frame, at the step's pose, undeformed.)
// Version 2 adds sub_steps, cutbacks, n_cells, n_dofs and the code_version/units attributes;
// version 3 the positions and the ball-averaged peaks; every older dataset is unchanged.
// The file is rewritten after every step (to a temporary file, then renamed: core/atomic_file.h), so an interrupted motion
// keeps its finished steps and the file that exists is always whole.
#pragma once

#include "fem/contact_problem.h"
#include "fem/motion_solver.h"

#include <string>
#include <vector>

namespace hipfai::fem {

class FemResultsWriter {
 public:
  // Throws hipfai::Error (naming the file) when it cannot be created.
  // moving_body: the rigid body whose translation is recorded (MotionOptions::moving_body).
  FemResultsWriter(std::string file, std::vector<std::string> body_names, unsigned int moving_body);

  // Records step `result` of `step` and rewrites the file.
  void append(const MotionStep& step, const ContactResult& result);

 private:
  void write() const;
  std::string file_;
  std::vector<std::string> body_names_;
  unsigned int moving_body_ = 0;
  std::vector<MotionStep> steps_;
  std::vector<ContactResult> results_;
};

}  // namespace hipfai::fem
