#include "bushel/analysis/bin_model.hpp"

#include <fmt/format.h>
#include <cmath>
#include <numbers>

#include "bushel/core/choice.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/core/require.hpp"

namespace bushel {

Surcharge parse_surcharge(const std::string& text) {
  return parse_choice<Surcharge>(
      text, {{"level", Surcharge::level}, {"peaked", Surcharge::peaked}, {"inverted", Surcharge::inverted}});
}

namespace {
constexpr double half_pi = 0.5 * std::numbers::pi;

void require_angle(double angle, const char* key, const char* example) {
  if (!(angle > 0.0 && angle < half_pi)) {
    throw InputError(fmt::format("expected an angle between 0 and 90 deg from the horizontal, e.g. {}; got {} deg",
                                 example, angle * 180.0 / std::numbers::pi))
        .with_key(key);
  }
}
}  // namespace

void validate(const BinSpec& s) {
  require_positive(s.diameter, "diameter", "9.14m", "m");
  require_positive(s.grain_height, "grain_height", "7.3m", "m");
  if (s.surcharge != Surcharge::level) require_angle(s.repose_angle, "repose_angle", "25deg");
  if (s.hopper_angle != 0.0) {
    require_angle(s.hopper_angle, "hopper_angle", "45deg");
    if (!(s.outlet_diameter >= 0.0 && s.outlet_diameter < s.diameter)) {
      throw InputError(fmt::format("expected an outlet smaller than the bin's {} m diameter, got {} m", s.diameter,
                                   s.outlet_diameter))
          .with_key("outlet_diameter");
    }
  }
  if (!(s.lateral_ratio >= 0.0) || !std::isfinite(s.lateral_ratio)) {
    throw InputError(fmt::format("expected a lateral pressure ratio K >= 0, got {}", s.lateral_ratio))
        .with_key("lateral_ratio");
  }
  if (!(s.wall_friction >= 0.0) || !std::isfinite(s.wall_friction)) {
    throw InputError(fmt::format("expected a wall friction coefficient >= 0, got {}", s.wall_friction))
        .with_key("wall_friction");
  }
  if (s.layers < 10 || s.layers > 10'000'000) {
    throw InputError(fmt::format("expected 10 to 10,000,000 layers, got {}", s.layers)).with_key("layers");
  }
  require_positive(s.gravity, "gravity", "9.81m/s2", "m/s2");
}

double jaky_lateral_ratio(double friction_angle) {
  require_angle(friction_angle, "friction_angle", "27deg");
  return 1.0 - std::sin(friction_angle);
}

namespace {

// Grain cross-section at a depth, and the bin's parts as depth intervals.
struct Geometry {
  double radius, cone = 0.0, hopper = 0.0, outlet_radius = 0.0, height;
  Surcharge surcharge;
  double area(double z) const {
    const double full = std::numbers::pi * radius * radius;
    if (z < 0.0) {  // peaked surcharge: the cone's section at depth -z below its apex height
      const double r = radius * (z + cone) / cone;
      return std::numbers::pi * r * r;
    }
    if (surcharge == Surcharge::inverted && z < cone) {  // a ring around the drawn-down cone
      const double r = radius * (1.0 - z / cone);
      return full - std::numbers::pi * r * r;
    }
    if (z <= height || hopper <= 0.0) return full;
    const double r = radius - (radius - outlet_radius) * (z - height) / hopper;
    return std::numbers::pi * r * r;
  }
};

}  // namespace

BinResult fill_bin(const BinSpec& spec, const Compressibility& model, double initial_density) {
  validate(spec);
  require_positive(initial_density, "initial_density", "60lb/bu", "kg/m3");
  Geometry geo{0.5 * spec.diameter, 0.0, 0.0, 0.5 * spec.outlet_diameter, spec.grain_height, spec.surcharge};
  if (spec.surcharge != Surcharge::level) geo.cone = geo.radius * std::tan(spec.repose_angle);
  if (spec.surcharge == Surcharge::inverted && geo.cone >= spec.grain_height) {
    throw InputError(fmt::format("the drawn-down cone ({:.3f} m deep at {} deg) reaches the floor of a {} m grain "
                                 "height",
                                 geo.cone, spec.repose_angle * 180.0 / std::numbers::pi, spec.grain_height))
        .with_key("repose_angle");
  }
  if (spec.hopper_angle != 0.0) geo.hopper = (geo.radius - geo.outlet_radius) * std::tan(spec.hopper_angle);

  const double g = spec.gravity;
  const double dz_target = spec.grain_height / spec.layers;
  const double lambda = spec.lateral_ratio * spec.wall_friction / (0.25 * spec.diameter);  // K mu_w / R_h [1/m]
  BinResult out;
  out.initial_density = initial_density;

  // A part [z0, z1) of the bin in layers of about dz_target. `advance(sigma, gamma, z, dz)`
  // gives the pressure at the layer's bottom for a unit weight gamma; the density of a layer
  // is that at its mid-pressure, found by one predictor-corrector pass.
  double sigma = 0.0, weight = 0.0;  // pressure [Pa]; weight of the grain above, per the
                                     // surcharge rule [N]
  auto push_level = [&](double z) {
    out.levels.push_back({z, sigma, model.density(sigma, initial_density), geo.area(z)});
  };
  auto run = [&](double z0, double z1, auto&& advance) {
    const int n = std::max(1, static_cast<int>(std::ceil((z1 - z0) / dz_target - 1e-9)));
    const double dz = (z1 - z0) / n;
    for (int k = 0; k < n; ++k) {
      const double z = z0 + k * dz, z_next = k + 1 == n ? z1 : z0 + (k + 1) * dz;
      const double a_top = geo.area(z), a_mid = geo.area(0.5 * (z + z_next)), a_bottom = geo.area(z_next);
      const double volume = (a_top + 4.0 * a_mid + a_bottom) * dz / 6.0;  // exact: area quadratic in z
      const double predicted = advance(sigma, model.density(sigma, initial_density) * g, z, dz, volume, a_bottom);
      const double density = model.density(0.5 * (sigma + predicted), initial_density);
      sigma = advance(sigma, density * g, z, dz, volume, a_bottom);
      weight += density * g * volume;
      out.volume += volume;
      out.mass += density * volume;
      push_level(z_next);
    }
  };
  // Without a wall (surcharge): the weight above over the section.
  auto unsupported = [&](double, double gamma, double, double, double volume, double a_bottom) {
    return (weight + gamma * volume) / a_bottom;
  };
  // Janssen, exact for a constant gamma over the layer (hydrostatic where K mu_w = 0).
  auto janssen = [&](double s, double gamma, double, double dz, double, double) {
    if (lambda == 0.0) return s + gamma * dz;
    const double decay = std::exp(-lambda * dz);
    return s * decay + gamma / lambda * (1.0 - decay);
  };
  // Hopper: the pressure at the transition is kept (see the header).
  auto held = [&](double s, double, double, double, double, double) { return s; };

  const double top = spec.surcharge == Surcharge::peaked ? -geo.cone : 0.0;
  push_level(top);
  if (spec.surcharge == Surcharge::peaked) run(-geo.cone, 0.0, unsupported);
  if (spec.surcharge == Surcharge::inverted) run(0.0, geo.cone, unsupported);
  run(spec.surcharge == Surcharge::inverted ? geo.cone : 0.0, spec.grain_height, janssen);
  if (geo.hopper > 0.0) run(spec.grain_height, spec.grain_height + geo.hopper, held);
  return out;
}

}  // namespace bushel
