#include "bushel/particles/particle_template.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "bushel/core/input_error.hpp"
#include "bushel/particles/union_moments.hpp"

namespace bushel {
namespace {

Vec3 to_vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Make an eigenvector's sign canonical: its largest component positive.
Vec3 canonical_sign(Vec3 v) {
  const int k = std::abs(v.x) >= std::abs(v.y) ? (std::abs(v.x) >= std::abs(v.z) ? 0 : 2)
                                               : (std::abs(v.y) >= std::abs(v.z) ? 1 : 2);
  return v[k] < 0 ? -v : v;
}

// Of the input axes, the one least aligned with `a`, made perpendicular to it.
Vec3 perpendicular_input_axis(const Vec3& a) {
  const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const Vec3* best = &axes[0];
  for (const auto& e : axes) {
    if (std::abs(dot(e, a)) < std::abs(dot(*best, a))) best = &e;
  }
  return normalized(*best - dot(*best, a) * a);
}

bool nearly_equal(double a, double b) { return std::abs(a - b) <= 1e-6 * std::max(std::abs(a), std::abs(b)); }

// Principal axes (columns, right-handed) and ascending moments of a symmetric inertia tensor.
// Degenerate moments leave the axes free within a plane (any axisymmetric kernel); we then
// pick axes that follow the input frame so that, e.g., a clump laid along x stays along x.
std::pair<Mat3, Vec3> principal_axes(const Mat3& j) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = j(r, c);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(m);
  const Eigen::Vector3d lambda = solver.eigenvalues();  // ascending
  const Vec3 moments{lambda(0), lambda(1), lambda(2)};
  Vec3 e1 = canonical_sign(to_vec(solver.eigenvectors().col(0)));
  Vec3 e2 = canonical_sign(to_vec(solver.eigenvectors().col(1)));
  const bool d12 = nearly_equal(lambda(0), lambda(1));
  const bool d23 = nearly_equal(lambda(1), lambda(2));
  if (d12 && d23) {
    e1 = {1, 0, 0};
    e2 = {0, 1, 0};
  } else if (d23) {
    e2 = perpendicular_input_axis(e1);
  } else if (d12) {
    const Vec3 e3 = canonical_sign(to_vec(solver.eigenvectors().col(2)));
    e1 = perpendicular_input_axis(e3);
    e2 = cross(e3, e1);
  }
  return {Mat3::from_columns(e1, e2, cross(e1, e2)), moments};
}

}  // namespace

double ParticleTemplate::equivalent_diameter() const { return std::cbrt(6.0 * volume / std::numbers::pi); }

Vec3 ParticleTemplate::extents() const {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const auto& s : spheres) {
    const Vec3 r{s.radius, s.radius, s.radius};
    lo = min(lo, s.centre - r);
    hi = max(hi, s.centre + r);
  }
  return hi - lo;
}

double ParticleTemplate::aspect_ratio() const {
  const Vec3 e = extents();
  return e.x / e.y;
}

double ParticleTemplate::min_sphere_radius() const {
  double r = INFINITY;
  for (const auto& s : spheres) r = std::min(r, s.radius);
  return r;
}

double ParticleTemplate::bounding_radius() const {
  double r = 0.0;
  for (const auto& s : spheres) r = std::max(r, norm(s.centre) + s.radius);
  return r;
}

ParticleTemplate make_template(std::string name, std::vector<SphereElement> spheres, const TemplateOptions& options) {
  if (spheres.empty()) throw InputError("a particle template needs at least one sphere").with_key(name);
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const auto& s = spheres[i];
    // From a dust grain to a boulder: outside it, a unit typed wrong (a radius in m read as
    // mm), or a time step of 1e-306 s that never ends the run.
    if (!(s.radius >= smallest_sphere_radius && s.radius <= largest_sphere_radius)) {
      throw InputError(fmt::format("expected a sphere radius between {:g} and {:g} m, got {:g} m",
                                   smallest_sphere_radius, largest_sphere_radius, s.radius))
          .with_key(name + ".spheres[" + std::to_string(i) + "]");
    }
    if (!(std::abs(s.centre.x) <= largest_sphere_radius && std::abs(s.centre.y) <= largest_sphere_radius &&
          std::abs(s.centre.z) <= largest_sphere_radius)) {
      throw InputError(
          fmt::format("expected a sphere centre within {:g} m of the template's origin", largest_sphere_radius))
          .with_key(name + ".spheres[" + std::to_string(i) + "]");
    }
  }
  ParticleTemplate t;
  t.name = std::move(name);
  if (spheres.size() == 1) {
    // Exact for a lone sphere; no reason to integrate.
    const double r = spheres[0].radius;
    t.volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const double moment = 0.4 * t.volume * r * r;
    t.principal_moments = {moment, moment, moment};
    t.input_centroid = spheres[0].centre;
    t.spheres = {{{0, 0, 0}, r}};
    return t;
  }
  const UnionMoments moments = integrate_union(spheres, options.resolution);
  const auto [axes, principal] = principal_axes(moments.inertia_about_centroid());
  t.volume = moments.volume;
  t.principal_moments = principal;
  t.input_centroid = moments.centroid();
  t.principal_to_input = Quat::from_matrix(axes);
  // Rounding leaves coordinates like -1e-19 where symmetry says 0; snap them so output and
  // later comparisons see the exact zero (and no "-0.0000").
  double extent = 0.0;
  for (const auto& s : spheres) extent = std::max(extent, norm(s.centre - t.input_centroid) + s.radius);
  auto snap = [&](double v) { return std::abs(v) < 1e-12 * extent ? 0.0 : v; };
  for (auto& s : spheres) {
    const Vec3 c = rotate_inverse(t.principal_to_input, s.centre - t.input_centroid);
    s.centre = {snap(c.x), snap(c.y), snap(c.z)};
  }
  t.spheres = std::move(spheres);
  return t;
}

}  // namespace bushel
