#include "bushel/contact/contact_batch.hpp"

#include <cmath>

namespace bushel {
namespace {

// One contact (see the header for the equations). Branch-free: both sides of each choice are
// computed and one is selected, which is safe because this file is built without math errno
// and FP trapping (src/CMakeLists.txt); selected values are the same as with branches.
inline void solve_one(ContactBatch& b, int i, double dt) {
  const double nx = b.nx[i], ny = b.ny[i], nz = b.nz[i];
  const double v_n = b.vx[i] * nx + b.vy[i] * ny + b.vz[i] * nz;
  const double tx = b.vx[i] - v_n * nx, ty = b.vy[i] - v_n * ny, tz = b.vz[i] - v_n * nz;
  const double s_n = 2.0 * b.youngs_modulus[i] * std::sqrt(b.r_star[i] * b.overlap[i]);
  const double root_s_n_m = std::sqrt(s_n * b.m_star[i]);
  const double elastic_damped = 2.0 / 3.0 * s_n * b.overlap[i] + b.damping[i] * root_s_n_m * v_n;
  const double f_n = elastic_damped > 0.0 ? elastic_damped : 0.0;

  // Rotate xi into the tangent plane, keeping its length (unchanged if already in it).
  double x = b.xi_x[i], y = b.xi_y[i], z = b.xi_z[i];
  const double len2 = x * x + y * y + z * z;
  const double along = x * nx + y * ny + z * nz;
  const double projected2 = len2 - along * along;
  const double keep = along != 0.0 ? (projected2 > 0.0 ? std::sqrt(len2 / projected2) : 0.0) : 1.0;
  x = (x - along * nx) * keep + tx * dt;
  y = (y - along * ny) * keep + ty * dt;
  z = (z - along * nz) * keep + tz * dt;

  const double s_t = b.stiffness_ratio[i] * s_n;
  const double gamma_t = b.damping[i] * b.root_stiffness_ratio[i] * root_s_n_m;
  double fx = -s_t * x - gamma_t * tx, fy = -s_t * y - gamma_t * ty, fz = -s_t * z - gamma_t * tz;
  const double limit = b.static_friction[i] * f_n;
  const double f_len2 = fx * fx + fy * fy + fz * fz;
  const bool sliding = f_len2 > limit * limit;
  const double cut = sliding ? limit / std::sqrt(f_len2) : 1.0;
  fx *= cut, fy *= cut, fz *= cut;
  // Sliding: the spring holds the Coulomb force.
  const bool spring = sliding && s_t > 0.0;
  const double s_t_safe = s_t > 0.0 ? s_t : 1.0;
  b.xi_x[i] = spring ? -(fx + gamma_t * tx) / s_t_safe : (sliding ? 0.0 : x);
  b.xi_y[i] = spring ? -(fy + gamma_t * ty) / s_t_safe : (sliding ? 0.0 : y);
  b.xi_z[i] = spring ? -(fz + gamma_t * tz) / s_t_safe : (sliding ? 0.0 : z);

  b.fx[i] = -f_n * nx + fx;
  b.fy[i] = -f_n * ny + fy;
  b.fz[i] = -f_n * nz + fz;
  b.normal_force[i] = f_n;
  b.normal_stiffness[i] = s_n;
}

}  // namespace

// Built twice where the compiler and the C library allow it: for AVX2 and for the baseline,
// chosen once at load time by the processor.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx2", "default")))
#endif
void solve(ContactBatch& batch, double dt) {
  const int n = batch.size;
#pragma omp simd
  for (int i = 0; i < n; ++i) solve_one(batch, i, dt);
}

}  // namespace bushel
