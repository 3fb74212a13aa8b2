// The pair batch (kinematics, law and torques in one vectorised kernel) against the contact
// batch fed with the same contacts' kinematics worked out with Vec3 (the brute-force path).

#include "bushel/contact/contact_batch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "bushel/core/vec3.hpp"

namespace bushel {
namespace {

constexpr double no_limit = std::numeric_limits<double>::infinity();  // damping rate [1/s]

struct Side {
  Vec3 offset, velocity, spin;  // element centre minus centre of mass [m], [m/s], [rad/s]
  double radius, mass;
  double inverse_moment;  // largest inverse principal moment [1/(kg m2)]
};

TEST(PairBatch, MatchesContactBatchWithVec3Kinematics) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto vec = [&](double scale) { return Vec3{u(rng), u(rng), u(rng)} * scale; };
  PairBatch pairs;
  ContactBatch contacts;
  Side si[PairBatch::capacity], sj[PairBatch::capacity];
  Vec3 arm_i[PairBatch::capacity], arm_j[PairBatch::capacity];
  constexpr double dt = 1e-5;
  for (int k = 0; k < PairBatch::capacity; ++k) {
    // Every other contact between lone spheres (offsets exactly zero), the rest clump parts;
    // some with a tangential displacement, some sliding (large tangential speed).
    const bool clump = k % 2 == 1;
    // (a lone sphere: I = 2/5 m r^2; a clump part: its body's, here 1/(0.3 m (2 mm)^2))
    const double ri = 1.5e-3 + 0.5e-3 * u(rng), rj = 1.8e-3, mi = 2e-5, mj = 3e-5;
    si[k] = {
        clump ? vec(1e-3) : Vec3{}, vec(0.3), vec(50.0), ri, mi, 1.0 / ((clump ? 0.3 * 4e-6 : 0.4 * ri * ri) * mi)};
    sj[k] = {clump ? vec(1e-3) : Vec3{},
             vec(k % 3 == 0 ? 3.0 : 0.3),
             vec(50.0),
             rj,
             mj,
             1.0 / ((clump ? 0.3 * 4e-6 : 0.4 * rj * rj) * mj)};
    const Vec3 n = normalized(vec(1.0));
    const double overlap = 1e-5 * (1.0 + u(rng));
    const Vec3 d = (si[k].radius + sj[k].radius - overlap) * n;
    pairs.dx[k] = d.x, pairs.dy[k] = d.y, pairs.dz[k] = d.z;
    pairs.ri[k] = si[k].radius, pairs.rj[k] = sj[k].radius;
    pairs.oix[k] = si[k].offset.x, pairs.oiy[k] = si[k].offset.y, pairs.oiz[k] = si[k].offset.z;
    pairs.ojx[k] = sj[k].offset.x, pairs.ojy[k] = sj[k].offset.y, pairs.ojz[k] = sj[k].offset.z;
    pairs.vix[k] = si[k].velocity.x, pairs.viy[k] = si[k].velocity.y, pairs.viz[k] = si[k].velocity.z;
    pairs.vjx[k] = sj[k].velocity.x, pairs.vjy[k] = sj[k].velocity.y, pairs.vjz[k] = sj[k].velocity.z;
    pairs.wix[k] = si[k].spin.x, pairs.wiy[k] = si[k].spin.y, pairs.wiz[k] = si[k].spin.z;
    pairs.wjx[k] = sj[k].spin.x, pairs.wjy[k] = sj[k].spin.y, pairs.wjz[k] = sj[k].spin.z;
    pairs.mi[k] = si[k].mass, pairs.mj[k] = sj[k].mass;
    pairs.ji[k] = si[k].inverse_moment, pairs.jj[k] = sj[k].inverse_moment;
    const Vec3 xi = k % 4 == 1 ? vec(2e-6) : Vec3{};
    pairs.xi_x[k] = contacts.xi_x[k] = xi.x;
    pairs.xi_y[k] = contacts.xi_y[k] = xi.y;
    pairs.xi_z[k] = contacts.xi_z[k] = xi.z;
    pairs.law.youngs_modulus[k] = contacts.law.youngs_modulus[k] = 1.4e7;
    pairs.law.stiffness_ratio[k] = contacts.law.stiffness_ratio[k] = 0.87;
    pairs.law.root_stiffness_ratio[k] = contacts.law.root_stiffness_ratio[k] = std::sqrt(0.87);
    pairs.law.damping[k] = contacts.law.damping[k] = 0.48;
    pairs.law.static_friction[k] = contacts.law.static_friction[k] = 0.27;

    // The same contact through Vec3: normal and overlap from the centres, contact point
    // c = x_i + (r_i - delta/2) n, arms from each centre of mass, velocity of i's point minus j's.
    const double dist = norm(d);
    const Vec3 normal = d / dist;
    const double delta = si[k].radius + sj[k].radius - dist;
    arm_i[k] = si[k].offset + (si[k].radius - 0.5 * delta) * normal;
    arm_j[k] = sj[k].offset - (sj[k].radius - 0.5 * delta) * normal;
    const Vec3 v = si[k].velocity + cross(si[k].spin, arm_i[k]) - sj[k].velocity - cross(sj[k].spin, arm_j[k]);
    contacts.nx[k] = normal.x, contacts.ny[k] = normal.y, contacts.nz[k] = normal.z;
    contacts.overlap[k] = delta;
    contacts.vx[k] = v.x, contacts.vy[k] = v.y, contacts.vz[k] = v.z;
    contacts.r_star[k] = si[k].radius * sj[k].radius / (si[k].radius + sj[k].radius);
    contacts.m_star[k] = si[k].mass * sj[k].mass / (si[k].mass + sj[k].mass);
    // The sliding mass's inverse, 1/m_i + 1/m_j + |arm|^2 J on each side.
    contacts.compliance[k] = 1.0 / si[k].mass + 1.0 / sj[k].mass + norm2(arm_i[k]) * si[k].inverse_moment +
                             norm2(arm_j[k]) * sj[k].inverse_moment;
  }
  pairs.size = contacts.size = PairBatch::capacity;
  pairs.centred = false;   // half of them are clump parts
  PairBatch lone = pairs;  // all at their centres of mass (below)
  // With the tangential damping bounded by the sliding mass (lambda = 2e4 /s: about the
  // model's damping at these overlaps), both batches agree too, and some lanes are bounded.
  {
    PairBatch bounded_pairs = pairs, free_pairs = pairs;
    ContactBatch bounded = contacts;
    constexpr double rate = 2e4;  // [1/s]
    solve(bounded_pairs, dt, rate);
    solve(bounded, dt, rate);
    solve(free_pairs, dt, no_limit);
    int changed = 0;
    for (int k = 0; k < PairBatch::capacity; ++k) {
      SCOPED_TRACE(k);
      const double scale = std::max(std::abs(bounded.fx[k]) + std::abs(bounded.fy[k]) + std::abs(bounded.fz[k]), 1e-2);
      EXPECT_NEAR(bounded_pairs.fx[k], bounded.fx[k], 1e-12 * scale);
      EXPECT_NEAR(bounded_pairs.fy[k], bounded.fy[k], 1e-12 * scale);
      EXPECT_NEAR(bounded_pairs.fz[k], bounded.fz[k], 1e-12 * scale);
      changed += bounded_pairs.fx[k] != free_pairs.fx[k] ? 1 : 0;
    }
    EXPECT_GT(changed, 0);
    EXPECT_LT(changed, PairBatch::capacity);
  }
  solve(pairs, dt, no_limit);
  solve(contacts, dt, no_limit);

  int sliding = 0;
  for (int k = 0; k < PairBatch::capacity; ++k) {
    SCOPED_TRACE(k);
    const Vec3 f{contacts.fx[k], contacts.fy[k], contacts.fz[k]};
    const double scale = std::max(norm(f), 1e-2);  // [N]; a contact flying apart may have none
    const double tol = 1e-12 * scale;
    EXPECT_NEAR(pairs.fx[k], f.x, tol);
    EXPECT_NEAR(pairs.fy[k], f.y, tol);
    EXPECT_NEAR(pairs.fz[k], f.z, tol);
    EXPECT_NEAR(pairs.normal_force[k], contacts.normal_force[k], 1e-12 * contacts.normal_force[k]);
    const Vec3 t_i = cross(arm_i[k], f), t_j = cross(arm_j[k], -f);
    const double torque_tol = 1e-12 * scale * 4e-3;
    EXPECT_NEAR(pairs.tix[k], t_i.x, torque_tol);
    EXPECT_NEAR(pairs.tiy[k], t_i.y, torque_tol);
    EXPECT_NEAR(pairs.tiz[k], t_i.z, torque_tol);
    EXPECT_NEAR(pairs.tjx[k], t_j.x, torque_tol);
    EXPECT_NEAR(pairs.tjy[k], t_j.y, torque_tol);
    EXPECT_NEAR(pairs.tjz[k], t_j.z, torque_tol);
    EXPECT_NEAR(pairs.arm_i[k], norm(arm_i[k]), 1e-15);
    EXPECT_NEAR(pairs.arm_j[k], norm(arm_j[k]), 1e-15);
    EXPECT_NEAR(pairs.xi_x[k], contacts.xi_x[k], 1e-18);
    EXPECT_NEAR(pairs.xi_y[k], contacts.xi_y[k], 1e-18);
    EXPECT_NEAR(pairs.xi_z[k], contacts.xi_z[k], 1e-18);
    EXPECT_NEAR(pairs.overlap[k], contacts.overlap[k], 1e-18);
    if (k % 2 == 0) {  // lone spheres: the same operations in the same order, the same bits
      EXPECT_EQ(pairs.fx[k], f.x);
      EXPECT_EQ(pairs.fy[k], f.y);
      EXPECT_EQ(pairs.fz[k], f.z);
    }
    const double f_t = norm(f + contacts.normal_force[k] * Vec3{contacts.nx[k], contacts.ny[k], contacts.nz[k]});
    if (f_t >= 0.27 * contacts.normal_force[k] * (1.0 - 1e-9)) ++sliding;
  }
  EXPECT_GT(sliding, 0);  // the Coulomb cut was exercised
  EXPECT_LT(sliding, PairBatch::capacity);

  // With every offset zero, the centred kernel (arm lengths without a square root) gives the
  // same as the general one.
  for (int k = 0; k < PairBatch::capacity; ++k) {
    lone.oix[k] = lone.oiy[k] = lone.oiz[k] = lone.ojx[k] = lone.ojy[k] = lone.ojz[k] = 0.0;
  }
  PairBatch general = lone;
  solve(general, dt, no_limit);
  lone.centred = true;
  solve(lone, dt, no_limit);
  for (int k = 0; k < PairBatch::capacity; ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(lone.fx[k], general.fx[k]);
    EXPECT_EQ(lone.tjz[k], general.tjz[k]);
    EXPECT_EQ(lone.xi_y[k], general.xi_y[k]);
    EXPECT_NEAR(lone.arm_i[k], general.arm_i[k], 1e-15 * general.arm_i[k]);
    EXPECT_NEAR(lone.arm_j[k], general.arm_j[k], 1e-15 * general.arm_j[k]);
  }
  // Bounded, the centred kernel takes the sliding mass of two lone spheres as m*/3.5 (their
  // arms at full radius), the general one from the arms, which are shorter by delta/2: the
  // bound is lower by up to delta/r (2 % here), and so is the damping where it binds.
  PairBatch lone_bounded = lone, general_bounded = lone;
  general_bounded.centred = false;
  solve(lone_bounded, dt, 2e4);
  solve(general_bounded, dt, 2e4);
  int lower = 0;
  for (int k = 0; k < PairBatch::capacity; ++k) {
    SCOPED_TRACE(k);
    const double scale =
        std::abs(general_bounded.fx[k]) + std::abs(general_bounded.fy[k]) + std::abs(general_bounded.fz[k]) + 1e-6;
    EXPECT_NEAR(lone_bounded.fx[k], general_bounded.fx[k], 0.02 * scale);
    lower += lone_bounded.fx[k] != general_bounded.fx[k] ? 1 : 0;
  }
  EXPECT_GT(lower, 0);
}

// One sphere-wall contact, normal along z, overlap 10 um: the study's kernel at restitution 0.1.
ContactBatch one_contact(double vx) {
  ContactBatch b;
  b.size = 1;
  b.nx[0] = 0.0, b.ny[0] = 0.0, b.nz[0] = 1.0;
  b.overlap[0] = 1e-5;
  b.vx[0] = vx, b.vy[0] = 0.0, b.vz[0] = 0.0;
  b.r_star[0] = 1.82e-3;
  b.m_star[0] = 3.47e-5;
  b.law.youngs_modulus[0] = 1.4e7;
  b.law.stiffness_ratio[0] = 0.87;
  b.law.root_stiffness_ratio[0] = std::sqrt(0.87);
  b.law.damping[0] = 1.08;
  b.law.static_friction[0] = 0.27;
  b.compliance[0] = 3.5 / 3.47e-5;
  b.xi_x[0] = b.xi_y[0] = b.xi_z[0] = 0.0;
  return b;
}

TEST(ContactBatch, ASlidingSpringHoldsTheCoulombForceAlone) {
  // Sliding at 1 m/s the damping alone (about 0.36 N) is far above the Coulomb force (about
  // 7 mN). The spring keeps the Coulomb force; when the contact point then stops, the contact
  // still pushes against the motion it had. A spring that also kept the damping's share
  // pushed the other way, forward (energy gained; the oblique-impact verification).
  constexpr double dt = 1e-6;
  ContactBatch b = one_contact(1.0);
  solve(b, dt, no_limit);
  const double coulomb = 0.27 * b.normal_force[0];
  EXPECT_NEAR(b.fx[0], -coulomb, 1e-12 * coulomb);
  const double s_t = 0.87 * b.normal_stiffness[0];
  EXPECT_NEAR(b.xi_x[0], coulomb / s_t, 1e-12 * coulomb / s_t);
  EXPECT_EQ(b.xi_y[0], 0.0);
  ContactBatch stopped = one_contact(0.0);
  stopped.xi_x[0] = b.xi_x[0];
  solve(stopped, dt, no_limit);
  EXPECT_NEAR(stopped.fx[0], -coulomb, 1e-12 * coulomb);
}

TEST(ContactBatch, TangentialDampingIsBoundedByTheSlidingMass) {
  // A sticking contact (1 mm/s, its spring stretched by v dt in the step) has
  // F_t = -S_t v dt - gamma_t v, with gamma_t the model's unless lambda m_t is smaller.
  constexpr double dt = 1e-6, v = 1e-3;
  ContactBatch free = one_contact(v), bounded = one_contact(v);
  solve(free, dt, no_limit);
  const double spring = 0.87 * free.normal_stiffness[0] * v * dt;  // [N]
  const double gamma_model = (-free.fx[0] - spring) / v;           // [N s/m]
  EXPECT_NEAR(gamma_model, 1.08 * std::sqrt(0.87) * std::sqrt(free.normal_stiffness[0] * 3.47e-5), 1e-9 * gamma_model);
  const double m_t = 1.0 / bounded.compliance[0];
  const double rate = 0.5 * gamma_model / m_t;  // the bound at half the model's damping
  solve(bounded, dt, rate);
  EXPECT_NEAR((-bounded.fx[0] - spring) / v, rate * m_t, 1e-9 * gamma_model);
  ContactBatch loose = one_contact(v);
  solve(loose, dt, 2.0 * gamma_model / m_t);  // a bound above the model's damping changes nothing
  EXPECT_EQ(loose.fx[0], free.fx[0]);
}

}  // namespace
}  // namespace bushel
