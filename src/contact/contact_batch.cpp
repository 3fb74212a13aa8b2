#include "bushel/contact/contact_batch.hpp"

#include <cmath>

#include "bushel/core/vector_clones.hpp"

namespace bushel {
namespace {

// What the law needs of one contact besides the tangential displacement.
struct LawInput {
  double nx, ny, nz, overlap, vx, vy, vz, r_star, m_star;
  double youngs_modulus, stiffness_ratio, root_stiffness_ratio, damping, static_friction;
  double damping_limit;  // largest gamma_t [N s/m]
};
struct LawOutput {
  double fx, fy, fz, normal_force, normal_stiffness;
};

// One contact (see the header for the equations); updates xi. Branch-free: both sides of each
// choice are computed and one is selected, which is safe because this file is built without
// math errno and FP trapping (src/CMakeLists.txt); selected values are the same as with
// branches.
[[gnu::always_inline]] inline LawOutput hertz_mindlin(const LawInput& in, double& xi_x, double& xi_y, double& xi_z,
                                                      double dt) {
  const double nx = in.nx, ny = in.ny, nz = in.nz;
  const double v_n = in.vx * nx + in.vy * ny + in.vz * nz;
  const double tx = in.vx - v_n * nx, ty = in.vy - v_n * ny, tz = in.vz - v_n * nz;
  const double s_n = 2.0 * in.youngs_modulus * std::sqrt(in.r_star * in.overlap);
  const double root_s_n_m = std::sqrt(s_n * in.m_star);
  const double elastic_damped = 2.0 / 3.0 * s_n * in.overlap + in.damping * root_s_n_m * v_n;
  const double f_n = elastic_damped > 0.0 ? elastic_damped : 0.0;

  // Rotate xi into the tangent plane, keeping its length (unchanged if already in it).
  double x = xi_x, y = xi_y, z = xi_z;
  const double len2 = x * x + y * y + z * z;
  const double along = x * nx + y * ny + z * nz;
  const double projected2 = len2 - along * along;
  const double keep = along != 0.0 ? (projected2 > 0.0 ? std::sqrt(len2 / projected2) : 0.0) : 1.0;
  x = (x - along * nx) * keep + tx * dt;
  y = (y - along * ny) * keep + ty * dt;
  z = (z - along * nz) * keep + tz * dt;

  const double s_t = in.stiffness_ratio * s_n;
  const double gamma_model = in.damping * in.root_stiffness_ratio * root_s_n_m;
  const double gamma_t = gamma_model < in.damping_limit ? gamma_model : in.damping_limit;
  double fx = -s_t * x - gamma_t * tx, fy = -s_t * y - gamma_t * ty, fz = -s_t * z - gamma_t * tz;
  const double limit = in.static_friction * f_n;
  const double f_len2 = fx * fx + fy * fy + fz * fz;
  const bool sliding = f_len2 > limit * limit;
  const double cut = sliding ? limit / std::sqrt(f_len2) : 1.0;
  fx *= cut, fy *= cut, fz *= cut;
  // Sliding: the spring holds the Coulomb force alone (not the damping's share too, which it
  // would give back as the contact point slows: header).
  const bool spring = sliding && s_t > 0.0;
  const double inverse_s_t = 1.0 / (s_t > 0.0 ? s_t : 1.0);  // one division for three
  xi_x = spring ? -fx * inverse_s_t : (sliding ? 0.0 : x);
  xi_y = spring ? -fy * inverse_s_t : (sliding ? 0.0 : y);
  xi_z = spring ? -fz * inverse_s_t : (sliding ? 0.0 : z);
  return {-f_n * nx + fx, -f_n * ny + fy, -f_n * nz + fz, f_n, s_n};
}

[[gnu::always_inline]] inline void solve_one(ContactBatch& b, int k, double dt, double damping_rate) {
  // (a wall does not move: the sliding mass is the body's alone)
  const LawOutput out =
      hertz_mindlin({b.nx[k], b.ny[k], b.nz[k], b.overlap[k], b.vx[k], b.vy[k], b.vz[k], b.r_star[k], b.m_star[k],
                     b.youngs_modulus[k], b.stiffness_ratio[k], b.root_stiffness_ratio[k], b.damping[k],
                     b.static_friction[k], damping_rate / b.compliance[k]},
                    b.xi_x[k], b.xi_y[k], b.xi_z[k], dt);
  b.fx[k] = out.fx, b.fy[k] = out.fy, b.fz[k] = out.fz;
  b.normal_force[k] = out.normal_force;
  b.normal_stiffness[k] = out.normal_stiffness;
}

// The same operations in the same order as Vec3's operators (core/vec3.hpp), so that a pair
// gives the same bits here as through them. Centred: both elements are at their bodies'
// centres of mass (the offsets are zero and not read), so the arm lengths need no square
// root. Uniform: the coefficients are lane 0's. The divider is what limits this loop, so it
// divides as little as it can.
template <bool centred, bool uniform>
[[gnu::always_inline]] inline void solve_one(PairBatch& b, int k, double dt, double damping_rate) {
  const int c = uniform ? 0 : k;
  const double dx = b.dx[k], dy = b.dy[k], dz = b.dz[k], ri = b.ri[k], rj = b.rj[k];
  const double dist = std::sqrt(dx * dx + dy * dy + dz * dz);
  const double inv = 1.0 / dist;
  const double nx = dx * inv, ny = dy * inv, nz = dz * inv;
  const double overlap = ri + rj - dist;
  const double a_i = ri - 0.5 * overlap, a_j = rj - 0.5 * overlap;
  // Arms from each centre of mass to the contact point.
  const double oix = centred ? 0.0 : b.oix[k], oiy = centred ? 0.0 : b.oiy[k], oiz = centred ? 0.0 : b.oiz[k];
  const double ojx = centred ? 0.0 : b.ojx[k], ojy = centred ? 0.0 : b.ojy[k], ojz = centred ? 0.0 : b.ojz[k];
  const double aix = oix + a_i * nx, aiy = oiy + a_i * ny, aiz = oiz + a_i * nz;
  const double ajx = ojx - a_j * nx, ajy = ojy - a_j * ny, ajz = ojz - a_j * nz;
  // Velocity of i's contact point minus j's: v_i + w_i x arm_i - v_j - w_j x arm_j.
  const double wix = b.wix[k], wiy = b.wiy[k], wiz = b.wiz[k], wjx = b.wjx[k], wjy = b.wjy[k], wjz = b.wjz[k];
  const double vx = b.vix[k] + (wiy * aiz - wiz * aiy) - b.vjx[k] - (wjy * ajz - wjz * ajy);
  const double vy = b.viy[k] + (wiz * aix - wix * aiz) - b.vjy[k] - (wjz * ajx - wjx * ajz);
  const double vz = b.viz[k] + (wix * aiy - wiy * aix) - b.vjz[k] - (wjx * ajy - wjy * ajx);
  const double r_star = ri * rj / (ri + rj);
  const double mi = b.mi[k], mj = b.mj[k];
  const double mm = mi * mj, m_star = mm / (mi + mj);
  // Sliding mass of the contact points, 1/m_t = 1/m_i + 1/m_j + a_i^2 J_i + a_j^2 J_j with J the
  // largest inverse principal moment (exact for a lone sphere, whose arm is normal to every
  // tangent; a bound for a clump). Two lone spheres (J = 5/2 / (m r^2), a <= r): m_t >= m*/3.5,
  // which costs neither a division nor a load. gamma_t <= damping_rate m_t.
  const double arm_i2 = aix * aix + aiy * aiy + aiz * aiz, arm_j2 = ajx * ajx + ajy * ajy + ajz * ajz;
  const double limit = centred ? damping_rate * m_star * (1.0 / 3.5)
                               : damping_rate * mm / ((mi + mj) + (arm_i2 * b.ji[k] + arm_j2 * b.jj[k]) * mm);
  const LawOutput out =
      hertz_mindlin({nx, ny, nz, overlap, vx, vy, vz, r_star, m_star, b.youngs_modulus[c], b.stiffness_ratio[c],
                     b.root_stiffness_ratio[c], b.damping[c], b.static_friction[c], limit},
                    b.xi_x[k], b.xi_y[k], b.xi_z[k], dt);
  const double fx = out.fx, fy = out.fy, fz = out.fz;
  b.nx[k] = nx, b.ny[k] = ny, b.nz[k] = nz;
  b.r_star[k] = r_star;
  b.overlap[k] = overlap;
  b.fx[k] = fx, b.fy[k] = fy, b.fz[k] = fz;
  b.tix[k] = aiy * fz - aiz * fy, b.tiy[k] = aiz * fx - aix * fz, b.tiz[k] = aix * fy - aiy * fx;
  b.tjx[k] = ajy * -fz - ajz * -fy, b.tjy[k] = ajz * -fx - ajx * -fz, b.tjz[k] = ajx * -fy - ajy * -fx;
  // An element at its body's centre of mass has its arm along n: length a.
  b.arm_i[k] = centred ? a_i : std::sqrt(aix * aix + aiy * aiy + aiz * aiz);
  b.arm_j[k] = centred ? a_j : std::sqrt(ajx * ajx + ajy * ajy + ajz * ajz);
  b.normal_force[k] = out.normal_force;
  b.normal_stiffness[k] = out.normal_stiffness;
}

}  // namespace

// Built for each instruction set (vector_clones.hpp); AVX-512 gave +10% per step on the
// benchmark's bed.
BUSHEL_VECTOR_CLONES void solve(ContactBatch& batch, double dt, double damping_rate) {
  const int n = batch.size;
#pragma omp simd
  for (int k = 0; k < n; ++k) solve_one(batch, k, dt, damping_rate);
}

namespace {
template <bool centred, bool uniform>
[[gnu::always_inline]] inline void solve_all(PairBatch& batch, double dt, double damping_rate) {
  const int n = batch.size;
#pragma omp simd
  for (int k = 0; k < n; ++k) solve_one<centred, uniform>(batch, k, dt, damping_rate);
}
}  // namespace

BUSHEL_VECTOR_CLONES void solve(PairBatch& batch, double dt, double damping_rate) {
  if (batch.centred) {
    batch.uniform ? solve_all<true, true>(batch, dt, damping_rate) : solve_all<true, false>(batch, dt, damping_rate);
  } else {
    batch.uniform ? solve_all<false, true>(batch, dt, damping_rate) : solve_all<false, false>(batch, dt, damping_rate);
  }
}

}  // namespace bushel
