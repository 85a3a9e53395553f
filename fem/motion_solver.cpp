#include "fem/motion_solver.h"

#include "core/error.h"

#include <cmath>

namespace hipfai::fem {

dealii::Tensor<2, 3> rotation_about_axis(const dealii::Tensor<1, 3>& axis_in, double angle_rad) {
  const dealii::Tensor<1, 3> axis = axis_in / axis_in.norm();
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  dealii::Tensor<2, 3> rotation;
  for (unsigned i = 0; i < 3; ++i) {
    for (unsigned j = 0; j < 3; ++j) rotation[i][j] = (i == j ? c : 0.0) + (1 - c) * axis[i] * axis[j];
  }
  // + s [axis]_x (cross-product matrix)
  rotation[0][1] -= s * axis[2];
  rotation[0][2] += s * axis[1];
  rotation[1][0] += s * axis[2];
  rotation[1][2] -= s * axis[0];
  rotation[2][0] -= s * axis[1];
  rotation[2][1] += s * axis[0];
  return rotation;
}

std::vector<ContactResult> run_motion(
    ContactProblem& problem, const std::vector<MotionStep>& steps, const MotionOptions& options,
    const std::function<void(std::size_t, const ContactResult&)>& on_step) {
  if (options.moving_body >= problem.rigid_bodies.size()) {
    throw_error("fem motion: moving body ", options.moving_body, " does not exist (",
                problem.rigid_bodies.size(), " rigid bodies)");
  }
  RigidBody& body = problem.rigid_bodies[options.moving_body];
  body.load_controlled = true;
  body.free_directions = {dealii::Tensor<1, 3>({1, 0, 0}), dealii::Tensor<1, 3>({0, 1, 0}),
                          dealii::Tensor<1, 3>({0, 0, 1})};
  std::vector<ContactResult> results;
  dealii::Tensor<1, 3> converged_translation = body.translation_mm;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    body.rotation = steps[k].rotation;
    body.force_n = steps[k].force_n;
    body.translation_mm = converged_translation;
    results.push_back(problem.run());
    if (results.back().status == ContactStatus::kConverged) {
      converged_translation = results.back().rigid_translation_mm[options.moving_body];
    }
    if (on_step) on_step(k, results.back());
  }
  return results;
}

}  // namespace hipfai::fem
