#include "bushel/particles/material.hpp"

#include <fmt/format.h>

#include "bushel/core/input_error.hpp"
#include "bushel/core/require.hpp"

namespace bushel {

void validate(const Material& m) {
  try {
    require_positive(m.shear_modulus, "shear_modulus", "22.4MPa", "Pa");
    // Bounds far outside any grain or vessel, that still catch a unit typed wrong: below 1 kPa
    // kernels sink through each other, above 1 TPa nothing is that stiff.
    if (!(m.shear_modulus >= 1e3 && m.shear_modulus <= 1e12)) {
      throw InputError(fmt::format("expected a shear modulus between 1 kPa and 1000 GPa, got {:g} Pa", m.shear_modulus))
          .with_key("shear_modulus");
    }
    if (!(m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5)) {
      throw InputError(fmt::format("expected a Poisson's ratio between -1 and 0.5, got {:g}", m.poisson_ratio))
          .with_key("poisson_ratio");
    }
    require_positive(m.density, "density", "1373kg/m3", "kg/m3");
    if (!(m.density >= 1.0 && m.density <= 1e5)) {
      throw InputError(fmt::format("expected a density between 1 and 100000 kg/m3, got {:g} kg/m3", m.density))
          .with_key("density");
    }
  } catch (const InputError& e) {
    throw e.with_key(m.name.empty() ? "material" : m.name);
  }
}

double effective_youngs_modulus(const Material& a, const Material& b) {
  return 1.0 / ((1.0 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus() +
                (1.0 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus());
}

double effective_shear_modulus(const Material& a, const Material& b) {
  return 1.0 / ((2.0 - a.poisson_ratio) / a.shear_modulus + (2.0 - b.poisson_ratio) / b.shear_modulus);
}

namespace materials {
Material wheat() { return {"wheat", 22.4e6, 0.22, 1373.0}; }
Material steel() { return {"steel", 37e9, 0.25, 8560.0}; }
}  // namespace materials

}  // namespace bushel
