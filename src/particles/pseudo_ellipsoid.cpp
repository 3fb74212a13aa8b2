#include "bushel/particles/pseudo_ellipsoid.hpp"

#include <fmt/format.h>
#include <cmath>
#include <numbers>
#include <vector>

#include "bushel/core/input_error.hpp"
#include "bushel/core/require.hpp"
#include "bushel/particles/union_moments.hpp"

namespace bushel {
namespace {

void check(const PseudoEllipsoidSpec& s) {
  require_positive(s.length, "length", "6.12mm", "m");
  require_positive(s.width, "width", "3.05mm", "m");
  require_positive(s.density, "density", "1373kg/m3", "kg/m3");
  if (s.mass) require_positive(*s.mass, "mass", "0.0346g", "kg");
  if (s.spheres < 1 || s.spheres == 2) {
    throw InputError(fmt::format("expected 1 sphere or 3 and more, got {}", s.spheres)).with_key("spheres");
  }
  if (s.spheres > 1 && s.width > s.length) {
    throw InputError(fmt::format("the width ({:g} mm) exceeds the length ({:g} mm); a kernel's length is its "
                                 "longest dimension",
                                 s.width * 1e3, s.length * 1e3))
        .with_key("width");
  }
  if (s.end_radius && s.mass && s.spheres < 5) {
    throw InputError("with 3 or 4 spheres the end radius is what matches the mass: give end_radius or mass, not both")
        .with_key("end_radius");
  }
  if (s.end_radius && (!(*s.end_radius > 0.0) || *s.end_radius > 0.5 * s.width)) {
    throw InputError(fmt::format("expected an end radius in (0, width/2 = {:g} mm], got {:g} mm", 0.5e3 * s.width,
                                 *s.end_radius * 1e3))
        .with_key("end_radius");
  }
}

// The clump for a given end radius and interior scale; `scale` multiplies the ellipse
// profile of the spheres between the ends and the centre.
std::vector<SphereElement> build(const PseudoEllipsoidSpec& s, double end_radius, double scale) {
  const double a = 0.5 * s.length, b = 0.5 * s.width;
  const int n = s.spheres;
  const double x_end = a - end_radius;
  std::vector<SphereElement> out;
  for (int i = 0; i < n; ++i) {
    const double x = -x_end + 2.0 * x_end * i / (n - 1);
    double r;
    if (i == 0 || i == n - 1) {
      r = end_radius;
    } else if (2 * i == n - 1 || 2 * i == n || 2 * i == n - 2) {
      r = b;  // the central sphere(s) set the width
    } else {
      r = std::min(b, scale * b * std::sqrt(1.0 - x * x / (a * a)));
    }
    out.push_back({{x, 0.0, 0.0}, r});
  }
  return out;
}

// Finds the parameter in [lo, hi] at which volume(p) == target, volume increasing in p.
template <class F>
double bisect(F volume, double lo, double hi, double target) {
  for (int it = 0; it < 60 && hi - lo > 1e-10 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (volume(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

ParticleTemplate make_pseudo_ellipsoid(const PseudoEllipsoidSpec& spec, std::string name,
                                       const TemplateOptions& options) {
  check(spec);
  if (spec.spheres == 1) {
    const double volume =
        spec.mass ? *spec.mass / spec.density : std::numbers::pi / 6.0 * spec.length * spec.width * spec.width;
    return make_template(std::move(name), {{{0, 0, 0}, std::cbrt(3.0 * volume / (4.0 * std::numbers::pi))}}, options);
  }
  const double a = 0.5 * spec.length, b = 0.5 * spec.width;
  double end_radius = spec.end_radius.value_or(b * b / a);  // default: the tip's radius of curvature
  double scale = 1.0;
  if (spec.mass) {
    // The mass is matched by the interior spheres' scale or, with no interior spheres
    // (3 or 4 in all), by the end radius.
    const bool by_scale = spec.spheres >= 5;
    auto volume = [&](double p) {
      const auto spheres = by_scale ? build(spec, end_radius, p) : build(spec, p, scale);
      return integrate_union(spheres, options.resolution).volume;
    };
    // Interior scale: from nearly vanished to every interior sphere as wide as the centre
    // (the outermost one, with the smallest profile, reaches b last).
    const double x_outer = (a - end_radius) * (1.0 - 2.0 / (spec.spheres - 1));
    const double lo = by_scale ? 0.05 : 0.05 * b;
    const double hi = by_scale ? 1.0 / std::sqrt(1.0 - x_outer * x_outer / (a * a)) : b;
    const double target = *spec.mass / spec.density;
    const double vlo = volume(lo), vhi = volume(hi);
    if (target < vlo || target > vhi) {
      throw InputError(fmt::format("a {}-sphere pseudo-ellipsoid of {:g} x {:g} mm can hold {:.4g} to {:.4g} g at "
                                   "{:g} kg/m3; the target is {:.4g} g",
                                   spec.spheres, spec.length * 1e3, spec.width * 1e3, vlo * spec.density * 1e3,
                                   vhi * spec.density * 1e3, spec.density, *spec.mass * 1e3))
          .with_key("mass");
    }
    (by_scale ? scale : end_radius) = bisect(volume, lo, hi, target);
  }
  auto spheres = build(spec, end_radius, scale);
  for (std::size_t i = 1; i < spheres.size(); ++i) {
    // A chain with a gap would be two particles glued by nothing: refuse it.
    if (spheres[i].centre.x - spheres[i - 1].centre.x >= spheres[i].radius + spheres[i - 1].radius) {
      throw InputError(fmt::format("the target mass {:.4g} g is too small for a connected {}-sphere clump of "
                                   "{:g} x {:g} mm",
                                   spec.mass.value_or(0.0) * 1e3, spec.spheres, spec.length * 1e3, spec.width * 1e3))
          .with_key("mass");
    }
  }
  return make_template(std::move(name), std::move(spheres), options);
}

}  // namespace bushel
