#pragma once
// Shared by the verification scenes (verification.cpp, geometry_verification.cpp): the test
// grain, its time scale and the small pieces every scene is built from.

#include <cmath>
#include <numbers>
#include <string>

#include "bushel/contact/time_scales.hpp"
#include "bushel/experiments/verification.hpp"
#include "bushel/integrate/simulation.hpp"
#include "bushel/particles/material.hpp"

namespace bushel::verification::detail {

constexpr double pi = std::numbers::pi;
constexpr double radius = 1.82e-3;  // the single-sphere large kernel, d = 3.64 mm

inline double rayleigh(double r) {
  const Material w = materials::wheat();
  return rayleigh_time_step(r, w.density, w.shear_modulus, w.poisson_ratio);
}

inline ParticleType sphere(double r = radius) {
  return {"grain", make_template("sphere", {{{0, 0, 0}, r}}), materials::wheat()};
}

inline SimulationSettings settings(double dt, ContactParameters p, Vec3 gravity = {}, const char* rolling = "cdt") {
  SimulationSettings s;
  s.dt = dt;
  s.gravity = gravity;
  s.rolling = rolling;
  s.contacts = ContactTable(p);
  return s;
}

inline Part floor_wall() { return plane_part("floor", materials::steel(), {0, 0, 0}, {0, 0, 1}); }

inline CheckResult result(std::string check, std::string quantity, double expected, double measured, double tolerance) {
  CheckResult r{std::move(check), std::move(quantity), expected, measured, tolerance, false};
  r.pass = r.error() <= tolerance;
  return r;
}

// Equilibrium overlap of a sphere resting on a stiff plane under gravity g.
inline double resting_overlap(const ParticleType& t, double g) {
  const double e_star = effective_youngs_modulus(t.material, materials::steel());
  return std::pow(t.mass() * g / (4.0 / 3.0 * e_star * std::sqrt(radius)), 2.0 / 3.0);
}

}  // namespace bushel::verification::detail
