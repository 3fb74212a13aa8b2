#include "bushel/geometry/region.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace bushel {
namespace {

// 16-point Gauss-Legendre nodes and weights on [-1, 1] (the positive half).
constexpr std::array<double, 8> gl_x = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274, 0.6178762444026438,
                                        0.7554044083550030, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499};
constexpr std::array<double, 8> gl_w = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025, 0.1495959888165767,
                                        0.1246289712555339, 0.0951585116824928, 0.0622535239386479, 0.0271524594117541};

// Integral of f(x) over [a, b] within the chord [c - R, c + R] of a circle, split at the
// breakpoints inside it. The integrands here are a circle's chords or slices, with square-
// root ends at c +- R: in the angle t (x = c + R sin t) they are smooth, so the quadrature
// converges fast; between breakpoints the slice's shape does not change.
template <class F>
double integrate(double c, double R, double a, double b, const std::vector<double>& breaks, const F& f) {
  auto angle = [&](double x) { return std::asin(std::clamp((x - c) / R, -1.0, 1.0)); };
  std::vector<double> t = {angle(a), angle(b)};
  for (const double x : breaks) {
    if (x > a && x < b) t.push_back(angle(x));
  }
  std::sort(t.begin(), t.end());
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < t.size(); ++k) {
    const double mid = 0.5 * (t[k] + t[k + 1]), half = 0.5 * (t[k + 1] - t[k]);
    if (!(half > 0.0)) continue;
    for (std::size_t i = 0; i < gl_x.size(); ++i) {
      for (const double u : {mid - half * gl_x[i], mid + half * gl_x[i]}) {
        sum += gl_w[i] * half * f(c + R * std::sin(u)) * R * std::cos(u);
      }
    }
  }
  return sum;
}

// Area of the intersection of two discs of radii a and R whose centres are d apart.
double lens_area(double a, double R, double d) {
  if (d >= a + R) return 0.0;
  if (d <= std::abs(R - a)) return std::numbers::pi * std::min(a, R) * std::min(a, R);
  const double alpha = std::acos(std::clamp((d * d + a * a - R * R) / (2 * d * a), -1.0, 1.0));
  const double beta = std::acos(std::clamp((d * d + R * R - a * a) / (2 * d * R), -1.0, 1.0));
  const double k = 0.5 * std::sqrt(std::max(0.0, (-d + a + R) * (d + a - R) * (d - a + R) * (d + a + R)));
  return a * a * alpha + R * R * beta - k;
}

}  // namespace

Region Region::cylinder(const Vec3& base_centre, double radius, double height) {
  Region r;
  r.kind = Kind::cylinder;
  r.position = base_centre;
  r.radius = radius;
  r.height = height;
  return r;
}

Region Region::box(const Vec3& centre, const Vec3& size) {
  Region r;
  r.kind = Kind::box;
  r.position = centre;
  r.size = size;
  return r;
}

Vec3 Region::lo() const {
  return kind == Kind::cylinder ? position - Vec3{radius, radius, 0.0} : position - 0.5 * size;
}

Vec3 Region::hi() const {
  return kind == Kind::cylinder ? position + Vec3{radius, radius, height} : position + 0.5 * size;
}

double Region::volume() const {
  return kind == Kind::cylinder ? std::numbers::pi * radius * radius * height : size.x * size.y * size.z;
}

double Region::room() const {
  return kind == Kind::cylinder ? std::min(radius, 0.5 * height) : 0.5 * std::min({size.x, size.y, size.z});
}

bool Region::contains(const Vec3& p) const { return contains_sphere(p, 0.0); }

bool Region::contains_sphere(const Vec3& c, double r, double margin) const {
  const double m = r + margin;
  if (kind == Kind::cylinder) {
    const double dx = c.x - position.x, dy = c.y - position.y;
    return c.z >= position.z + m && c.z <= position.z + height - m && radius >= m &&
           dx * dx + dy * dy <= (radius - m) * (radius - m);
  }
  const Vec3 l = lo(), h = hi();
  return c.x >= l.x + m && c.x <= h.x - m && c.y >= l.y + m && c.y <= h.y - m && c.z >= l.z + m && c.z <= h.z - m;
}

Vec3 Region::sample(std::mt19937_64& rng, double margin) const {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  if (kind == Kind::cylinder) {
    const double rr = (radius - margin) * std::sqrt(u(rng));
    const double phi = 2.0 * std::numbers::pi * u(rng);
    const double z = position.z + margin + (height - 2.0 * margin) * u(rng);
    return {position.x + rr * std::cos(phi), position.y + rr * std::sin(phi), z};
  }
  const Vec3 l = lo() + Vec3{margin, margin, margin}, h = hi() - Vec3{margin, margin, margin};
  const double x = u(rng), y = u(rng), z = u(rng);
  return {l.x + (h.x - l.x) * x, l.y + (h.y - l.y) * y, l.z + (h.z - l.z) * z};
}

double Region::section_area_in_disc(double cx, double cy, double a) const {
  if (!(a > 0.0)) return 0.0;
  if (kind == Kind::cylinder) {
    return lens_area(a, radius, std::hypot(cx - position.x, cy - position.y));
  }
  // The rectangle's part of the disc, column by column: the chord at x clipped to [y0, y1].
  const Vec3 l = lo(), h = hi();
  const double x0 = std::max(l.x, cx - a), x1 = std::min(h.x, cx + a);
  if (!(x1 > x0)) return 0.0;
  std::vector<double> breaks;
  for (const double y : {l.y, h.y}) {
    const double dy = y - cy;
    if (std::abs(dy) < a) {
      const double w = std::sqrt(a * a - dy * dy);
      breaks.push_back(cx - w);
      breaks.push_back(cx + w);
    }
  }
  return integrate(cx, a, x0, x1, breaks, [&](double x) {
    const double w = std::sqrt(std::max(0.0, a * a - (x - cx) * (x - cx)));
    return std::max(0.0, std::min(h.y, cy + w) - std::max(l.y, cy - w));
  });
}

double Region::sphere_volume_inside(const Vec3& c, double r) const {
  if (contains_sphere(c, r)) return 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const Vec3 l = lo(), h = hi();
  const double z0 = std::max(l.z, c.z - r), z1 = std::min(h.z, c.z + r);
  if (!(z1 > z0) || c.x + r <= l.x || c.x - r >= h.x || c.y + r <= l.y || c.y - r >= h.y) return 0.0;
  // Slices change shape where the slice's disc radius meets a distance of the section's
  // boundary from the disc centre: the cylinder's |R - d| and R + d, the box's distances to
  // its sides.
  std::vector<double> radii;
  if (kind == Kind::cylinder) {
    const double d = std::hypot(c.x - position.x, c.y - position.y);
    radii = {std::abs(radius - d), radius + d};
  } else {
    radii = {c.x - l.x, h.x - c.x, c.y - l.y, h.y - c.y};
    for (const double x : {l.x, h.x}) {
      for (const double y : {l.y, h.y}) radii.push_back(std::hypot(x - c.x, y - c.y));  // the corners
    }
  }
  std::vector<double> breaks;
  for (const double rho : radii) {
    if (std::abs(rho) < r) {
      const double dz = std::sqrt(r * r - rho * rho);
      breaks.push_back(c.z - dz);
      breaks.push_back(c.z + dz);
    }
  }
  return integrate(c.z, r, z0, z1, breaks, [&](double z) {
    return section_area_in_disc(c.x, c.y, std::sqrt(std::max(0.0, r * r - (z - c.z) * (z - c.z))));
  });
}

}  // namespace bushel
