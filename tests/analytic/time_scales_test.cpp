#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bushel/contact/time_scales.hpp"
#include "bushel/particles/material.hpp"

namespace bushel {
namespace {

TEST(TimeScales, RayleighStepOfTheWheatModel) {
  // docs/physics.md section 3 by hand for R = 0.911 mm, wheat: pi R sqrt(rho/G) / (0.1631 nu + 0.8766).
  const Material w = materials::wheat();
  const double expected = std::numbers::pi * 0.911e-3 * std::sqrt(1373.0 / 22.4e6) / (0.1631 * 0.22 + 0.8766);
  EXPECT_DOUBLE_EQ(rayleigh_time_step(0.911e-3, w.density, w.shear_modulus, w.poisson_ratio), expected);
  EXPECT_NEAR(expected, 24.556e-6, 0.001e-6);
}

TEST(TimeScales, HertzContactTimeMatchesTheClassicalConstant) {
  // The textbook form t_c = 2.868 (m*^2 / (R* E*^2 v))^(1/5).
  const double m = 1e-5, r = 1e-3, e = 30e6, v = 2.0;
  const double textbook = 2.8682 * std::pow(m * m / (r * e * e * v), 0.2);
  EXPECT_NEAR(hertz_contact_time(m, r, e, v) / textbook, 1.0, 1e-4);
}

TEST(TimeScales, HertzContactTimeByDirectIntegration) {
  // Integrate m x'' = -(4/3) E* sqrt(R*) x^(3/2) with a fine symplectic Euler step.
  const double m = 2e-5, r = 1.5e-3, e = 40e6, v = 1.0;
  const double k = 4.0 / 3.0 * e * std::sqrt(r);
  const double tc = hertz_contact_time(m, r, e, v);
  const double dt = tc * 1e-6;
  double x = 0, u = v, t = 0, x_max = 0;
  do {
    u -= k * std::pow(std::max(x, 0.0), 1.5) / m * dt;
    x += u * dt;
    t += dt;
    x_max = std::max(x_max, x);
  } while (x > 0);
  EXPECT_NEAR(t / tc, 1.0, 1e-4);
  EXPECT_NEAR(x_max / hertz_max_overlap(m, r, e, v), 1.0, 1e-4);
  EXPECT_NEAR(u, -v, 1e-4 * v);  // elastic: leaves at the speed it came
}

TEST(TimeScales, ContactTimeFallsWithImpactSpeed) {
  EXPECT_NEAR(hertz_contact_time(1e-5, 1e-3, 3e7, 4.0) / hertz_contact_time(1e-5, 1e-3, 3e7, 1.0), std::pow(4.0, -0.2),
              1e-12);
}

}  // namespace
}  // namespace bushel
