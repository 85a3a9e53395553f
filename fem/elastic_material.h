// hipfai — isotropic linear elastic material (small strain), units mm, N, MPa.
#pragma once

namespace hipfai::fem {

struct ElasticMaterial {
  double youngs_modulus_mpa = 0.0;
  double poisson_ratio = 0.0;

  double shear_modulus_mpa() const { return youngs_modulus_mpa / (2.0 * (1.0 + poisson_ratio)); }
  double lame_lambda_mpa() const {
    return youngs_modulus_mpa * poisson_ratio /
           ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
  }
  // Constrained (oedometric) modulus M = E(1-nu)/((1+nu)(1-2nu)): stress over strain of a layer
  // whose lateral expansion is prevented.
  double p_wave_modulus_mpa() const { return lame_lambda_mpa() + 2.0 * shear_modulus_mpa(); }
  // Plane-strain modulus E* = E/(1-nu^2) of Hertz contact against a rigid body.
  double plane_strain_modulus_mpa() const {
    return youngs_modulus_mpa / (1.0 - poisson_ratio * poisson_ratio);
  }
};

}  // namespace hipfai::fem
