#include "bushel/contact/contact_batch.hpp"

#include <cmath>

#include "bushel/core/vector_clones.hpp"

namespace bushel {
namespace {

[[gnu::always_inline]] inline void solve_one(ContactBatch& b, int k, double dt, double damping_rate) {
  // (a wall does not move: the sliding mass is the body's alone)
  const LawLanes<ContactBatch::capacity>& law = b.law;
  const LawOutput out =
      HertzMindlin::force({b.nx[k], b.ny[k], b.nz[k], b.overlap[k], b.vx[k], b.vy[k], b.vz[k], b.r_star[k], b.m_star[k],
                           law.youngs_modulus[k], law.stiffness_ratio[k], law.root_stiffness_ratio[k], law.damping[k],
                           law.static_friction[k], damping_rate / b.compliance[k]},
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
  const LawLanes<PairBatch::capacity>& law = b.law;
  const LawOutput out = HertzMindlin::force(
      {nx, ny, nz, overlap, vx, vy, vz, r_star, m_star, law.youngs_modulus[c], law.stiffness_ratio[c],
       law.root_stiffness_ratio[c], law.damping[c], law.static_friction[c], limit},
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
