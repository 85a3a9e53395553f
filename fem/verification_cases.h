// hipfai — verification cases of the FE contact model against closed-form solutions.
//
// Each case builds a ContactProblem, solves it and compares a few computed quantities with
// their closed form: `hipfai fem verify` prints them, tests/fem checks them (recomputing the
// closed forms independently from the case's inputs).
//   uniaxial_layer        bonded layer pressed by a rigid plate through contact: p = M d / h
//   uniaxial_load_control same, the plate translation unknown under a prescribed force
//   stacked_layers        two layers on non-matching meshes: p = d / (h1/M1 + h2/M2)
//   spherical_shells      concentric shells (hip dimensions), core expanded: Lame solution
//   hertz                 rigid sphere on a thick block under a prescribed force (slow)
#pragma once

#include "fem/contact_problem.h"

#include <map>
#include <string>
#include <vector>

namespace hipfai::fem {

struct VerificationOptions {
  int refinement = 0;           // extra global refinements on top of the case's default mesh
  unsigned int fe_degree = 2;
  std::string vtu_file;         // displacement field of the solve, when not empty
  bool verbose = false;
  // CG + AMG by default; the direct solver (the hip runs' choice) is checked on the same cases.
  LinearSolver linear_solver = LinearSolver::kCgAmg;
};

struct VerificationQuantity {
  std::string name;
  std::string unit;
  double computed = 0.0;
  double closed_form = 0.0;
  double tolerance = 0.0;  // on the relative error
  double relative_error() const;
  bool passed() const { return relative_error() <= tolerance; }
};

struct VerificationResult {
  std::string case_name;
  std::map<std::string, double> inputs;  // named with units, e.g. "d_mm"
  std::vector<VerificationQuantity> quantities;
  ContactResult solve;
  bool passed() const;
};

const std::vector<std::string>& verification_case_names();

// Full concentric spherical shells with the hip's dimensions (core 23 mm, contact 25 mm, cup
// 27 mm; femoral and acetabular cartilage, E = 12 MPa, nu = 0.45): rigid body 0 is the femur
// (core, rotating about the origin, its shell expanded radially by expansion_mm), rigid body 1
// the pelvis (cup). A spherical joint on which the motion machinery is checked and demonstrated.
void build_concentric_shells(ContactProblem& problem, double expansion_mm);

// Throws hipfai::Error for an unknown case name.
VerificationResult run_verification_case(const std::string& name,
                                          const VerificationOptions& options, MPI_Comm comm);

}  // namespace hipfai::fem
