// hipfai — the penetration-informed estimator ("depth_nn"): the thesis' two halves joined. Beyond
// the thesis: §4.5 estimates the FE pressure from geometry alone and fails where the hips
// impinge (the peak pressure jumps when cam and rim meet, at a step that depends on CE and alpha
// together); §4.3 computes, from the same geometry and in milliseconds, whether and how deep they
// meet at every step. This estimator uses both:
//
//   estimate(j) = level x profile(j) x factor(j)
//
//   level       the target's contact-free pressure at the first step: mean over the k training
//               hips nearest on the first e' PCA scores (as `knn`) of their value at step 1;
//               only hips with no penetration at step 1 count.
//   profile(j)  the contact-free course of the motion (the load is the same for every hip):
//               mean over the training hips with no penetration at step j of value(j) / value(1).
//   factor(j)   1 when the target has no penetration at step j; otherwise the mean impingement
//               factor value(i, j') / (value(i, 1) profile(j')) of the k training (hip, step)
//               pairs WITH penetration nearest to the target's (curvilinear, radial) depth at j,
//               Euclidean in mm (both are depths along the surface, thesis §3.2 and §3.3), any
//               step j' (the factor follows the depth, not the step). Ties: lowest hip, then step.
//
// "No penetration" = both depths are 0 (the penetration method reports 0 below its contact
// tolerance). The interval is [low level x profile x lowest factor, high level x profile x highest
// factor] over the chosen hips and pairs. k = the thesis' shortlist of 4 (Eq. 22). A step is
// undefined when no training hip is free of contact there (no profile) or no pair penetrates.
#pragma once

#include "stats/knn_regression.h"

#include <Eigen/Core>

#include <vector>

namespace hipfai::stats {

// Penetration depths (mm) per hip (rows) and step (columns), both of thesis §4.3: curvilinear
// (femur bone vs labrum) and radial (femoral cartilage vs acetabular soft tissue). NaN = unknown.
struct PenetrationDepths {
  Eigen::MatrixXd curvilinear_mm, radial_mm;
  bool known() const { return curvilinear_mm.size() > 0; }
};

// Throws hipfai::Error on shape mismatches, k < 1, components < 1, or unknown (NaN) depths.
std::vector<RegressionStep> depth_nn_estimate(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values,
                                              const PenetrationDepths& depths, const Eigen::VectorXd& target,
                                              const PenetrationDepths& target_depths, int components, int k);

// "depth_aligned": depth_nn's level and contact-free course, but each estimate taken from the
// target's own geometric neighbours, their courses aligned by penetration depth rather than by
// step (the thesis' pca_nn copies its neighbours' curves step by step and misses where they
// impinge at another step; depth_nn pools the impingement factors of all training hips at the
// same depth, whatever their geometry):
//
//   free step j      (target's depths both 0): mean over the k level hips (as depth_nn) of
//                    value(i, 1) x course_i(j), course_i(j) = value(i, j) / value(i, 1) where hip
//                    i is free of contact at j, else profile(j) (depth_nn's pooled course);
//   contact step j   (target's depths (c, r)): level x profile(j) x mean over the k hips nearest
//                    on the first e' scores AMONG THOSE THAT PENETRATE at some step of
//                    factor_i(c, r): hip i's steps in order form a path in the (curvilinear,
//                    radial) depth plane, each carrying its factor value(i, j') / (value(i, 1)
//                    profile(j')) (free steps lie at the origin); factor_i is the factor at the
//                    point of the path nearest to (c, r), linear along the segment (ties: the
//                    earlier segment). Beyond the deepest point of a hip's path the factor is
//                    that point's (no extrapolation).
//
// The interval: the range of the level hips' products (free) or low level x profile x lowest
// factor to high level x profile x highest factor (contact). Same k (the thesis' 4) and the same
// plain-mm depth distance as depth_nn: nothing fitted. Same errors as depth_nn_estimate.
std::vector<RegressionStep> depth_aligned_estimate(const Eigen::MatrixXd& scores, const Eigen::MatrixXd& values,
                                                   const PenetrationDepths& depths, const Eigen::VectorXd& target,
                                                   const PenetrationDepths& target_depths, int components, int k);

}  // namespace hipfai::stats
