// hipfai — a motion of the femur as a sequence of quasi-static contact solves.
//
// The thesis's kinematics (Arbabi 2009, §4.3.2.3): per step the femur's rotation about the hip
// joint centre is prescribed, its translation is free and found so that the contact resultant
// balances the joint reaction force, which lets the head relocate. Each step is a fresh
// small-strain solve about the rotated configuration (bodies bonded to the femur rotated
// rigidly, contact search redone there); the translation of the previous step is the starting
// guess of the next, and the active set is found anew by the semismooth Newton iteration.
//
// The motion comes as plain arrays (rotation matrix and force per step): fem does not parse
// motion files, the caller does (app/cmd_fem.cpp via studies/motion.h).
#pragma once

#include "fem/contact_problem.h"

#include <deal.II/base/tensor.h>

#include <functional>
#include <vector>

namespace hipfai::fem {

struct MotionStep {
  dealii::Tensor<2, 3> rotation;  // of the moving body about its rotation_center_mm
  dealii::Tensor<1, 3> force_n;   // joint reaction: force the moving body applies to the tissues
};

struct MotionOptions {
  unsigned int moving_body = 0;  // index into ContactProblem::rigid_bodies
};

// Solves the steps in order; `on_step(step index, result)` is called after each (e.g. to write
// it). The moving body becomes load controlled in x, y and z. A step that does not converge
// is reported in its status and the motion continues from the last converged translation.
// Throws hipfai::Error for a moving_body that does not exist.
std::vector<ContactResult> run_motion(
    ContactProblem& problem, const std::vector<MotionStep>& steps, const MotionOptions& options,
    const std::function<void(std::size_t, const ContactResult&)>& on_step = {});

// Rotation by angle_rad about the unit axis (Rodrigues).
dealii::Tensor<2, 3> rotation_about_axis(const dealii::Tensor<1, 3>& axis, double angle_rad);

}  // namespace hipfai::fem
