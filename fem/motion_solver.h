// hipfai — a motion of the femur as a sequence of quasi-static contact solves.
//
// The thesis's kinematics (Arbabi 2009, §4.3.2.3): per step the femur's rotation about the hip
// joint centre is prescribed, its translation is free and found so that the contact resultant
// balances the joint reaction force, which lets the head relocate. Each step is a fresh
// small-strain solve about the rotated configuration (bodies bonded to the femur rotated
// rigidly, contact search redone there); the translation and the active set of the last
// converged solve are the starting guess of the next.
//
// Cutback: a step that does not converge (active set not converged, linear solver failed, no
// contact found, non-finite numbers) is retried as two half increments from the last converged
// state (rotation interpolated along the shortest arc, force linearly), recursively up to
// max_cutback_depth halvings. Because every solve is a fresh small-strain solve about the rotated
// configuration, the sub-steps change only the starting guesses, not the answer: the last
// sub-step is the same problem as the step itself.
//
// The motion comes as plain arrays (rotation matrix and force per step): fem does not parse
// motion files, the caller does (app/cmd_fem.cpp via studies/pipeline/motion.h).
#pragma once

#include "fem/contact_problem.h"

#include <deal.II/base/tensor.h>

#include <functional>
#include <string>
#include <vector>

namespace hipfai::fem {

struct MotionStep {
  dealii::Tensor<2, 3> rotation;  // of the moving body about its rotation_center_mm
  dealii::Tensor<1, 3> force_n;   // joint reaction: force the moving body applies to the tissues
};

struct MotionOptions {
  unsigned int moving_body = 0;  // index into ContactModel::rigid_bodies
  // Directions the moving body may translate in under its load; empty: x, y and z (the femur).
  std::vector<dealii::Tensor<1, 3>> free_directions;
  // Halvings of a step that fails before giving up on it (0: no cutback; 4: down to 1/16 step).
  unsigned int max_cutback_depth = 4;
  // Fields to VTU every vtu_every steps (0: never) and at the last step, as
  // <vtu_prefix>_<step>.vtu (step counted from 1), listed with the step as time in
  // <vtu_prefix>.pvd for ParaView. Rank 0 writes the .pvd; all ranks must call run_motion.
  unsigned int vtu_every = 0;
  std::string vtu_prefix;
  // Search each step's contact while the step before is solved (ContactProblem::expect_next):
  // the same answers, less wall time. Off: every step searches when it starts.
  bool search_ahead = true;
};

// Solves the steps in order; `on_step(step index, result)` is called after each (e.g. to write
// it). The moving body becomes load controlled along options.free_directions (x, y and z unless
// given). Each result carries the sub-steps
// and cutbacks it needed and the iterations and wall time of all its attempts; its solution
// fields are those of the last sub-step. A step that still fails after max_cutback_depth
// halvings is reported in its status (with every non-finite number replaced by 0) and the
// motion continues from the last converged state.
// Throws hipfai::Error for a moving_body that does not exist, or for vtu_every > 0 with an
// empty vtu_prefix.
// Throws hipfai::Error for a moving_body that does not exist.
std::vector<ContactResult> run_motion(
    ContactProblem& problem, const std::vector<MotionStep>& steps, const MotionOptions& options,
    const std::function<void(std::size_t, const ContactResult&)>& on_step = {});

// Rotation by angle_rad about the unit axis (Rodrigues).
dealii::Tensor<2, 3> rotation_about_axis(const dealii::Tensor<1, 3>& axis, double angle_rad);

// Rotation a fraction s in [0, 1] of the way from `from` to `to` along the shortest arc
// (slerp: from * exp(s log(from^T to))). Both must be proper orthogonal.
dealii::Tensor<2, 3> interpolate_rotation(const dealii::Tensor<2, 3>& from, const dealii::Tensor<2, 3>& to,
                                          double s);

}  // namespace hipfai::fem
