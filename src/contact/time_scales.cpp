#include "bushel/contact/time_scales.hpp"

#include <cmath>
#include <numbers>

namespace bushel {

double rayleigh_time_step(double radius, double density, double shear_modulus, double poisson_ratio) {
  return std::numbers::pi * radius * std::sqrt(density / shear_modulus) / (0.1631 * poisson_ratio + 0.8766);
}

double hertz_max_overlap(double effective_mass, double effective_radius, double effective_modulus,
                         double impact_speed) {
  return std::pow(
      15.0 * effective_mass * impact_speed * impact_speed / (16.0 * effective_modulus * std::sqrt(effective_radius)),
      0.4);
}

double hertz_contact_time(double effective_mass, double effective_radius, double effective_modulus,
                          double impact_speed) {
  // Energy conservation gives dt = d(delta) / sqrt(v^2 (1 - (delta/delta_max)^(5/2))).
  static const double integral = std::sqrt(std::numbers::pi) * std::tgamma(1.4) / std::tgamma(0.9);
  return 2.0 * integral * hertz_max_overlap(effective_mass, effective_radius, effective_modulus, impact_speed) /
         impact_speed;
}

}  // namespace bushel
