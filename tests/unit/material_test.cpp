#include <gtest/gtest.h>

#include "bushel/core/input_error.hpp"
#include "bushel/particles/material.hpp"

namespace bushel {
namespace {

TEST(Material, YoungsModulusFromShearModulus) {
  // E = 2 G (1 + nu): wheat 22.4 MPa, 0.22 -> 54.656 MPa.
  EXPECT_NEAR(materials::wheat().youngs_modulus(), 54.656e6, 1.0);
  EXPECT_NEAR(materials::steel().youngs_modulus(), 92.5e9, 1.0);
}

TEST(Material, EffectiveModuliOfTwoEqualMaterials) {
  const Material w = materials::wheat();
  // Equal materials: E* = E / (2 (1 - nu^2)), G* = G / (2 (2 - nu)).
  EXPECT_NEAR(effective_youngs_modulus(w, w), w.youngs_modulus() / (2 * (1 - 0.22 * 0.22)), 1e-6);
  EXPECT_NEAR(effective_shear_modulus(w, w), w.shear_modulus / (2 * (2 - 0.22)), 1e-6);
  // Against a far stiffer wall, the soft side dominates.
  EXPECT_NEAR(effective_youngs_modulus(w, materials::steel()), w.youngs_modulus() / (1 - 0.22 * 0.22),
              1e-3 * w.youngs_modulus());
}

TEST(Material, ValidationNamesTheField) {
  EXPECT_NO_THROW(validate(materials::wheat()));
  Material m = materials::wheat();
  m.poisson_ratio = 0.6;
  try {
    validate(m);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "wheat.poisson_ratio");
  }
  m = materials::wheat();
  m.density = -1;
  EXPECT_THROW(validate(m), InputError);
  m = materials::wheat();
  m.shear_modulus = 0;
  EXPECT_THROW(validate(m), InputError);
}

}  // namespace
}  // namespace bushel
