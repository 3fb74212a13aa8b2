#pragma once
// Time scales that bound the DEM time step (docs/physics.md section 3).

namespace bushel {

/// Rayleigh time step [s] for a sphere of radius R [m] of a solid with density rho
/// [kg/m3], shear modulus G [Pa] and Poisson's ratio nu:
///   T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766).
double rayleigh_time_step(double radius, double density, double shear_modulus, double poisson_ratio);

/// Largest overlap [m] of a Hertzian impact at relative normal speed v [m/s] between bodies
/// of effective mass m* [kg], radius R* [m] and modulus E* [Pa], without damping:
///   delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5).
double hertz_max_overlap(double effective_mass, double effective_radius, double effective_modulus, double impact_speed);

/// Duration [s] of an undamped Hertzian impact: t_c = 2 I delta_max / v, with
/// I = integral_0^1 (1 - x^(5/2))^(-1/2) dx = sqrt(pi) Gamma(7/5) / Gamma(9/10) = 1.47160...
/// (so t_c = 2.9432 delta_max / v).
double hertz_contact_time(double effective_mass, double effective_radius, double effective_modulus,
                          double impact_speed);

}  // namespace bushel
