#pragma once
// The mass of grain in a round bin, from the bin's shape, the grain's initial (uncompacted)
// bulk density D_o and how it densifies under pressure (compressibility.hpp); docs/wheat.md,
// "Formulas the program offers users".
//
// The vertical pressure follows Janssen's equation, dsigma/dz = gamma(z) - (K mu_w / R_h) sigma
// with R_h = D/4, integrated from the top down in thin layers: within a layer the unit weight
// gamma = D(sigma) g is held at its value at the layer's mid-pressure (a predictor-corrector
// step), and sigma advances by the exact solution for a constant gamma,
//   sigma' = sigma e^(-lambda dz) + (gamma / lambda)(1 - e^(-lambda dz)),  lambda = K mu_w / R_h,
// so that for a constant density the profile is Janssen's closed form at every layer boundary
// and for a varying one the error falls as dz^2. Layer volumes are exact (Simpson's rule on
// areas that are at most quadratic in depth), so without compaction M = D_o V to rounding.
//
// Depth z is measured down from the grain at the wall (the eave for a full bin). Above it a
// peaked surcharge (a cone at the angle of repose) loads the cylinder; an inverted one (a
// cone drawn down to the centre) leaves a ring. In both the wall is not reached or only by
// a ring, and the mean vertical stress is taken as the weight of grain above a level over
// the grain's area at that level (no wall friction there). Below the cylinder a hopper (a
// cone down to an outlet) holds the pressure reached at the transition: converging hoppers
// relieve the vertical stress towards the outlet, so this is the upper bound on compaction.

#include <string>
#include <vector>

#include "bushel/analysis/compressibility.hpp"

namespace bushel {

enum class Surcharge {
  level,     ///< flat grain surface at the wall height
  peaked,    ///< a cone above the wall height at the angle of repose
  inverted,  ///< a cone drawn down from the wall height to the centre
};
/// "level", "peaked", "inverted"; throws InputError (with a did-you-mean) otherwise.
Surcharge parse_surcharge(const std::string& text);

struct BinSpec {
  double diameter = 0.0;      ///< inside diameter D [m]
  double grain_height = 0.0;  ///< grain at the wall, above the floor or hopper top [m]
  Surcharge surcharge = Surcharge::level;
  double repose_angle = 0.0;     ///< angle of the surcharge cone from the horizontal [rad]
  double hopper_angle = 0.0;     ///< hopper wall angle from the horizontal [rad]; 0 = flat floor
  double outlet_diameter = 0.0;  ///< hopper outlet [m], < D
  double lateral_ratio = 0.5;    ///< Janssen's K = sigma_h / sigma_v [-]
  double wall_friction = 0.3;    ///< mu_w, grain on the wall [-]
  int layers = 2000;             ///< layers over the grain height; the other parts alike [-]
  double gravity = 9.80665;      ///< [m/s2]
};

/// Throws InputError (keyed by the field) for non-positive sizes, angles outside (0, 90) deg
/// where used, an outlet not smaller than the bin, negative K or mu_w, or too few layers.
void validate(const BinSpec& spec);

/// Jaky's at-rest ratio K = 1 - sin(phi) for an internal friction angle phi [rad] in (0, 90 deg).
double jaky_lateral_ratio(double friction_angle);

/// The state at one depth.
struct BinLevel {
  double depth = 0.0;     ///< below the grain at the wall; negative in a peaked surcharge [m]
  double pressure = 0.0;  ///< mean vertical pressure [Pa]
  double density = 0.0;   ///< bulk density [kg/m3]
  double area = 0.0;      ///< grain cross-section [m2]
};

struct BinResult {
  std::vector<BinLevel> levels;                             ///< top to bottom, at the layer boundaries
  double volume = 0.0;                                      ///< grain volume [m3]
  double mass = 0.0;                                        ///< [kg]
  double initial_density = 0.0;                             ///< D_o [kg/m3]
  double average_density() const { return mass / volume; }  ///< [kg/m3]
  double packing_ratio() const { return average_density() / initial_density; }              ///< P [-]
  double bottom_pressure() const { return levels.empty() ? 0.0 : levels.back().pressure; }  ///< [Pa]
};

/// Fills the bin described by `spec` with grain of initial density `initial_density` [kg/m3]
/// compacting as `model` says.
BinResult fill_bin(const BinSpec& spec, const Compressibility& model, double initial_density);

}  // namespace bushel
