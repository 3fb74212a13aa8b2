#pragma once
// Hertz-Mindlin (no slip) with EDEM's damping, as stateless formulas (physics.md section 2),
// templated on the number type and shared by the sphere-sphere loop, wall contacts and tests.

#include <algorithm>
#include <cmath>

#include "bushel/contact/pair_coefficients.hpp"
#include "bushel/core/vec3.hpp"

namespace bushel::hertz_mindlin {

/// Normal stiffness S_n = 2 E* sqrt(R* delta_n) [N/m].
template <class T>
T normal_stiffness(T e_star, T r_star, T overlap) {
  return T(2) * e_star * std::sqrt(r_star * overlap);
}

/// Normal force magnitude, positive = repulsive [N]:
///   F_n = 4/3 E* sqrt(R*) delta^(3/2) + gamma sqrt(S_n m*) v_n,
/// v_n the approach speed (positive while closing). Net attraction is clamped to zero.
/// Also returns S_n and sqrt(S_n m*), from which the tangential law derives its own
/// stiffness and damping without further square roots: 4/3 E* sqrt(R*) delta^(3/2) = 2/3 S_n delta.
template <class T>
T normal_force(T e_star, T r_star, T m_star, T damping, T overlap, T approach_speed, T& s_n, T& root_s_n_m) {
  s_n = normal_stiffness(e_star, r_star, overlap);
  root_s_n_m = std::sqrt(s_n * m_star);
  return std::max(T(0), T(2) / T(3) * s_n * overlap + damping * root_s_n_m * approach_speed);
}

/// Tangential force on side i [N] from the stored displacement `xi` (updated in place):
/// `xi` is first rotated into the current tangent plane (its length kept), then advanced by
/// the tangential relative velocity v_t times dt; F_t = -S_t xi - gamma sqrt(S_t m*) v_t, and
/// where |F_t| exceeds mu_s F_n the force is cut to the Coulomb limit and xi rescaled to match.
/// S_t = 8 G* sqrt(R* delta) = k S_n with k = 4 G*/E* (`stiffness_ratio`), so the damping
/// coefficient is gamma sqrt(k) sqrt(S_n m*).
template <class T>
Vec3 tangential_force(const Vec3& normal, const Vec3& v_t, T s_n, T root_s_n_m, T stiffness_ratio,
                      T root_stiffness_ratio, T damping, T normal_force_magnitude, T mu_s, T dt, Vec3& xi) {
  const T len2 = norm2(xi);
  if (len2 > T(0)) {
    const T along = dot(xi, normal);
    if (along != T(0)) {  // project into the tangent plane and keep the length
      xi -= along * normal;
      const T projected2 = len2 - along * along;
      xi = projected2 > T(0) ? xi * std::sqrt(len2 / projected2) : Vec3{};
    }
  }
  xi += v_t * dt;
  const T s_t = stiffness_ratio * s_n;
  const T gamma_t = damping * root_stiffness_ratio * root_s_n_m;
  Vec3 f = -s_t * xi - gamma_t * v_t;
  const T limit = mu_s * normal_force_magnitude;
  const T f_len2 = norm2(f);
  if (f_len2 > limit * limit) {
    f = f * (limit / std::sqrt(f_len2));
    xi = s_t > T(0) ? -(f + gamma_t * v_t) / s_t : Vec3{};  // sliding: spring holds the Coulomb force
  }
  return f;
}

}  // namespace bushel::hertz_mindlin
