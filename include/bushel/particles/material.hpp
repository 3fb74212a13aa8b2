#pragma once
// Elastic and mass properties of a solid (docs/physics.md section 2): what Hertz-Mindlin needs
// from each side of a contact.

#include <string>

namespace bushel {

struct Material {
  std::string name;            ///< unique name used by particle types, walls and the pair table
  double shear_modulus = 0.0;  ///< G [Pa]
  double poisson_ratio = 0.0;  ///< nu [-], in (-1, 0.5)
  double density = 0.0;        ///< solid density rho [kg/m3]

  /// Young's modulus E = 2 G (1 + nu) [Pa] (docs/physics.md section 2).
  double youngs_modulus() const { return 2.0 * shear_modulus * (1.0 + poisson_ratio); }
};

/// Throws InputError (keyed by the offending field) unless G > 0, -1 < nu < 0.5 and rho > 0.
void validate(const Material& m);

/// Effective Young's modulus E* [Pa]: 1/E* = (1 - nu_i^2)/E_i + (1 - nu_j^2)/E_j.
double effective_youngs_modulus(const Material& a, const Material& b);

/// Effective shear modulus G* [Pa] (Mindlin): 1/G* = (2 - nu_i)/G_i + (2 - nu_j)/G_j.
double effective_shear_modulus(const Material& a, const Material& b);

/// Materials of the reference wheat study (docs/wheat.md, "Materials").
namespace materials {
/// Wheat kernel: G 22.4 MPa, nu 0.22, rho 1373 kg/m3.
Material wheat();
/// Steel/brass equipment: G 37 GPa, nu 0.25, rho 8560 kg/m3.
Material steel();
}  // namespace materials

}  // namespace bushel
