#include "bushel/integrate/critical_step.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "coefficients.hpp"

namespace bushel {

namespace {

// (c x t)^T diag(inverse) (c x t) at the contact point c = d + r n, over the tangents t across
// the normal n, as a function of t (angles phi, psi) and of w = n x t (the angle theta in the
// plane across t): then c x t = d x t + r w.
double tangential_turning(const Vec3& d, double r, const Vec3& inverse, double phi, double psi, double theta) {
  const Vec3 t{std::sin(phi) * std::cos(psi), std::sin(phi) * std::sin(psi), std::cos(phi)};
  const Vec3 e1 = normalized(cross(t, std::abs(t.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
  const Vec3 w = std::cos(theta) * e1 + std::sin(theta) * cross(t, e1);
  const Vec3 u = cross(d, t) + r * w;
  return inverse.x * u.x * u.x + inverse.y * u.y * u.y + inverse.z * u.z * u.z;
}

// Its largest value: a grid over the three angles, then a pattern search from the best points.
double largest_tangential_turning(const Vec3& d, double r, const Vec3& inverse) {
  constexpr double pi = 3.14159265358979323846;
  struct Point {
    double value, x[3];
  };
  std::vector<Point> grid;
  for (int i = 0; i <= 12; ++i) {
    for (int j = 0; j < 24; ++j) {
      for (int k = 0; k < 12; ++k) {
        const double x[3] = {pi * i / 12, 2 * pi * j / 24, 2 * pi * k / 12};
        grid.push_back({tangential_turning(d, r, inverse, x[0], x[1], x[2]), {x[0], x[1], x[2]}});
      }
    }
  }
  std::partial_sort(grid.begin(), grid.begin() + 4, grid.end(),
                    [](const Point& a, const Point& b) { return a.value > b.value; });
  double best = grid[0].value;
  for (int s = 0; s < 4; ++s) {
    Point p = grid[static_cast<std::size_t>(s)];
    for (double h = 0.1; h > 1e-9; h *= 0.5) {
      for (bool moved = true; moved;) {
        moved = false;
        for (int a = 0; a < 3; ++a) {
          for (const double step : {h, -h}) {
            Point q = p;
            q.x[a] += step;
            q.value = tangential_turning(d, r, inverse, q.x[0], q.x[1], q.x[2]);
            if (q.value > p.value) p = q, moved = true;
          }
        }
      }
    }
    best = std::max(best, p.value);
  }
  return best;
}

// Central-difference stability of a damped oscillator (Belytschko's bound).
double mode_step(double omega, double zeta) { return 2.0 * (std::sqrt(1.0 + zeta * zeta) - zeta) / omega; }

double inverse_mass(const ContactSide& s) { return std::isinf(s.mass) ? 0.0 : 1.0 / s.mass; }

}  // namespace

std::vector<ContactSide> contact_sides(const ParticleType& type) {
  const double mass = type.mass();
  const Vec3 moments = type.shape.principal_inertia(type.material.density);  // ascending
  const Vec3 inverse{1.0 / moments.x, 1.0 / moments.y, 1.0 / moments.z};
  std::vector<ContactSide> sides;
  for (const SphereElement& e : type.shape.spheres) {
    const Vec3& d = e.centre;  // principal frame, centre of mass at the origin
    Eigen::Matrix3d cross;     // [d]x: [d]x n = d x n
    cross << 0.0, -d.z, d.y, d.z, 0.0, -d.x, -d.y, d.x, 0.0;
    const Eigen::Matrix3d b = cross.transpose() * Eigen::Vector3d(inverse.x, inverse.y, inverse.z).asDiagonal() * cross;
    const double normal = std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(b).eigenvalues()(2));
    const double bound = std::pow(std::sqrt(normal) + e.radius * std::sqrt(inverse.x), 2);
    sides.push_back({e.radius, mass, normal, std::min(bound, largest_tangential_turning(d, e.radius, inverse))});
  }
  return sides;
}

ContactModes contact_modes(const ContactSide& i, const ContactSide& j, const PairCoefficients& c,
                           double overlap_ratio) {
  const double r_star = std::isinf(j.radius) ? i.radius : i.radius * j.radius / (i.radius + j.radius);
  const double overlap = overlap_ratio * std::min(i.radius, j.radius);
  const double s_n = 2.0 * c.youngs_modulus * std::sqrt(r_star * overlap);  // S_n (section 2)
  // The damping is gamma sqrt(S m*) with m* the bodies' translational reduced mass, so the
  // damping ratio of a mode of mass m is gamma / 2 sqrt(m* / m). (The tangential bound
  // gamma_max only lowers it, which lengthens the stable step: leaving it out is safe.)
  const double translation = inverse_mass(i) + inverse_mass(j);
  auto mode = [&](double stiffness, double turning) {
    const double inverse = translation + turning;
    const double omega = std::sqrt(stiffness * inverse);
    const double zeta = 0.5 * c.damping * std::sqrt(inverse / translation);
    return CriticalStep{mode_step(omega, zeta), omega, zeta, false, {}};
  };
  ContactModes m{mode(s_n, i.normal_turning + j.normal_turning),
                 mode(c.stiffness_ratio * s_n, i.tangential_turning + j.tangential_turning)};
  m.tangential.tangential = true;
  return m;
}

CriticalStep critical_step(const ContactSide& i, const ContactSide& j, const PairCoefficients& c,
                           double overlap_ratio) {
  const ContactModes m = contact_modes(i, j, c, overlap_ratio);
  return m.tangential.dt < m.normal.dt ? m.tangential : m.normal;
}

CriticalStep critical_time_step(const std::vector<ParticleType>& types, const std::vector<Part>& parts,
                                const ContactTable& table, double overlap_ratio) {
  const PairCoefficientTable coefficients = engine::make_coefficients(table, types, parts);
  std::vector<std::vector<ContactSide>> sides;
  for (const ParticleType& t : types) sides.push_back(contact_sides(t));
  CriticalStep best;
  auto consider = [&](const ContactSide& x, const ContactSide& y, std::size_t p, std::size_t q,
                      const std::string& other) {
    CriticalStep s = critical_step(x, y, coefficients(p, q), overlap_ratio);
    if (s.dt < best.dt) {
      s.pair = types[p].name + "-" + other;
      best = s;
    }
  };
  for (std::size_t p = 0; p < types.size(); ++p) {
    for (const ContactSide& x : sides[p]) {
      for (std::size_t q = p; q < types.size(); ++q) {
        for (const ContactSide& y : sides[q]) consider(x, y, p, q, types[q].name);
      }
      for (std::size_t w = 0; w < parts.size(); ++w) consider(x, ContactSide{}, p, types.size() + w, parts[w].name);
    }
  }
  return best;
}

}  // namespace bushel
