// hipfai — per-step results of an FE motion, written to HDF5.
//
// Layout (version 1; every dataset has a "unit" attribute, "1" for counts):
//   /                       attributes: layout_version = 1, bodies (names joined by ';')
//   /steps/status                 int[n]          0 converged, 1 active set not converged,
//                                                 2 linear solver failed, 3 no contact
//   /steps/active_set_iterations  int[n]          Newton (semismooth active-set) iterations
//   /steps/linear_solves          int[n]
//   /steps/linear_iterations      int[n]          CG iterations, summed over the solves
//   /steps/wall_time_s            double[n]       s
//   /steps/rotation               double[n][3][3] femur rotation about the HJC (row-major R)
//   /steps/applied_force_n        double[n][3]    N, joint reaction applied by the femur
//   /steps/femur_translation_mm   double[n][3]    mm
//   /steps/contact_resultant_n    double[n][3]    N, contact force on the slave surfaces
//   /steps/max_pressure_mpa, mean_pressure_mpa  double[n]  MPa (mean = force / area)
//   /steps/contact_area_mm2       double[n]       mm^2
//   /steps/max_penetration_mm     double[n]       mm
//   /steps/max_von_mises_mpa      double[n][bodies] MPa, over Gauss points
//   /steps/p95_von_mises_mpa      double[n][bodies] MPa, nearest-rank 95th percentile
// The file is rewritten after every step, so an interrupted motion keeps its finished steps.
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
