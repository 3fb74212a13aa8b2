#pragma once
// Everything a contact law needs about a pair of species, resolved once before the run so the
// hot loop reads one small struct (docs/physics.md section 2).

#include <cmath>
#include <vector>

#include "bushel/contact/contact_table.hpp"
#include "bushel/contact/restitution_damping.hpp"
#include "bushel/contact/species_matrix.hpp"
#include "bushel/particles/material.hpp"

namespace bushel {

struct PairCoefficients {
  double youngs_modulus = 0.0;        ///< E* [Pa]
  double shear_modulus = 0.0;         ///< G* [Pa]
  double damping = 0.0;               ///< gamma in F_n = ... + gamma sqrt(S_n m*) v_n [-] (restitution_damping.hpp)
  double static_friction = 0.0;       ///< mu_s [-]
  double rolling_friction = 0.0;      ///< mu_r [-]
  double stiffness_ratio = 0.0;       ///< S_t / S_n = 4 G* / E* [-]
  double root_stiffness_ratio = 0.0;  ///< sqrt(S_t / S_n) [-]
};

/// Coefficients of a pair; the damping factor restores the requested restitution under the
/// clamped normal law (restitution_damping.hpp).
inline PairCoefficients make_pair_coefficients(const Material& a, const Material& b, const ContactParameters& p) {
  const double e = effective_youngs_modulus(a, b), g = effective_shear_modulus(a, b);
  return {e,
          g,
          damping_for_restitution(p.restitution),
          p.static_friction,
          p.rolling_friction,
          4.0 * g / e,
          std::sqrt(4.0 * g / e)};
}

/// PairCoefficients over species (particle types, then walls).
using PairCoefficientTable = SpeciesMatrix<PairCoefficients>;

}  // namespace bushel
